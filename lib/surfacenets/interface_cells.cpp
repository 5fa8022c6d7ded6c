// The multi-label certificate's lattice shortcut (interface_certificate.hpp):
// when the mesh IS a surface-nets mesh of K(X) with every vertex strictly
// inside its cell, two of its ray tests have answers the lattice gives,
// and the certificate takes them from there.
//
// The structure (net_cells checks it exactly, on any mesh handed over):
//  - every vertex of a triangle lies strictly inside the cell of a voxel
//    corner c, the open cube (c - 1, c)^3 of continuous index (by a margin
//    far above the rounding of world -> index), no two in one cell;
//  - every triangle's corners are three corners of one face of K(X), its
//    pair the face's, oriented as the face (reversed when its pair is
//    given the other way round); every face has exactly two triangles,
//    which leave out opposite corners: its quad split along a diagonal.
//
// What follows. The cells are the cubes between voxel centres, and the
// segment between two face-neighbouring voxel centres p, p + e_a is an edge
// of theirs, dual to the voxel face between them: the four cells around it
// are the face's corners'. A face's two triangles lie in the convex hull of
// its four vertices, so strictly inside the union of their cells, a convex
// box of 2x2x1 cells; every other segment between voxel centres lies on
// that box's boundary or outside it. So the segment p, p + e_a meets only
// its dual face's triangles, and only when p and p + e_a differ in label.
// Those it crosses exactly once: seen along e_a the four vertices lie one
// in each open quadrant around it, in the quad's cyclic order, so the quad
// winds once around it and exactly one of the two triangles is pierced (or
// their shared diagonal), between p and p + e_a (the box spans just that
// along e_a), in the direction of the face's orientation; it never meets a
// vertex or another edge. Beyond the grid (voxel index -1 or n) a ray to
// infinity meets no triangle (the cells end at -1 and n).
//
// Hence, the parity of crossings along a path being the ray test's answer
// for a closed surface (self-crossing or not):
//  - voxel sides: along a path of such segments from a voxel centre to
//    beyond the grid, L's triangles are crossed once at each change between
//    L and another label; so every voxel centre carries L exactly when it is
//    inside L's surface (label 0's: the surface of X != 0), and none lies on
//    it: no centre on the wrong side.
//  - nesting: a component a of L's surface is a component of bdCA(L) on
//    its corners' cells; no triangle of another component b enters those
//    cells (bdCA(L)'s components share no corner), so a's first vertex is on
//    the side of b that the voxel centre at its cell's lowest corner is:
//    the parity of b's faces crossed from that centre along -x.
// Nothing else is taken from the structure: every other check runs as on
// any mesh, and a mesh without it gets the ray tests.
#include "surfacenets/interface_certificate_detail.hpp"

#include "surfacenets/surface_nets_detail.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surfacenets_detail {
namespace {

constexpr double kInside = 1e-6;  // voxels: a vertex this far inside its cell at least (rounding of world -> index)

NetCells fails(const std::string& why) {
  NetCells c;
  c.why = why;
  return c;
}

// The rounding of continuous_index grows with the coordinates' size.
double slack_of(const std::vector<Vec3>& points, const Geometry& grid) {
  double far = 0;
  for (const Vec3& p : points)
    for (double x : p) far = std::max(far, std::abs(x));
  for (double x : grid.origin) far = std::max(far, std::abs(x));
  return kInside + 1e-12 * far / std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
}

} // namespace

std::uint64_t net_corner(const Vec3& p, const Geometry& grid, const std::array<std::size_t, 3>& lattice, double slack) {
  const Vec3 ci = grid.continuous_index(p);
  std::uint64_t id = 0;
  for (int a = 2; a >= 0; --a) {
    const double x = ci[std::size_t(a)], c = std::ceil(x);
    if (!(x > c - 1 + slack && x < c - slack && c >= 0 && c < double(lattice[std::size_t(a)]))) return NetCells::kNoCorner;
    id = id * lattice[std::size_t(a)] + std::uint64_t(c);
  }
  return id;
}

NetCells net_cells(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                   const std::vector<std::array<std::int32_t, 2>>& pairs, const Geometry& grid,
                   const InterfaceComplex& k) {
  if (triangles.size() != 2 * k.faces.size()) return fails("not two triangles a face of K(X)");
  NetCells r;
  r.slack = slack_of(points, grid);
  // Each vertex in its own cell: one bit a vertex (seen) and a corner (taken).
  std::vector<bool> seen_vertex(points.size(), false), taken(k.lattice[0] * k.lattice[1] * k.lattice[2], false);
  auto corner = [&](int v) { return net_corner(points[std::size_t(v)], grid, k.lattice, r.slack); };
  for (const auto& t : triangles)
    for (int v : t) {
      if (seen_vertex[std::size_t(v)]) continue;
      seen_vertex[std::size_t(v)] = true;
      const std::uint64_t c = corner(v);
      if (c == NetCells::kNoCorner) return fails("vertex " + std::to_string(v) + " is not strictly inside a voxel-corner cell");
      if (taken[c]) return fails("vertex " + std::to_string(v) + " shares its cell with another");
      taken[c] = true;
    }
  const bool reflect = reflects(grid);
  // Per face: the corners its triangles leave out (bits 0..3, corner (i, j)
  // bit i + 2 j along the face's axes b, c), and their count (bits 4..).
  std::vector<std::uint8_t> seen(k.faces.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::array<std::array<std::size_t, 3>, 3> c;
    for (std::size_t i = 0; i < 3; ++i) c[i] = k.corner(corner(triangles[t][i]));
    std::array<std::size_t, 3> lo{};
    int axis = -1, flat = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min({c[0][a], c[1][a], c[2][a]});
      const std::size_t span = std::max({c[0][a], c[1][a], c[2][a]}) - lo[a];
      if (span > 1) return fails("triangle " + std::to_string(t) + " is not on a voxel face");
      if (span == 0) axis = int(a), ++flat;
    }
    if (flat != 1) return fails("triangle " + std::to_string(t) + " is not on a voxel face");
    const std::size_t f = k.find_face(lo[0] + k.lattice[0] * (lo[1] + k.lattice[1] * lo[2]), axis);
    if (f == k.faces.size()) return fails("triangle " + std::to_string(t) + " is on no face of K(X)");
    const auto& patch = k.patches[k.face_patch[f]];
    const auto& pr = pairs[t];
    if (std::max(pr[0], pr[1]) != patch.behind || std::min(pr[0], pr[1]) != patch.front)
      return fails("triangle " + std::to_string(t) + " has another pair than its face");
    const std::size_t b = std::size_t(axis + 1) % 3, e = std::size_t(axis + 2) % 3;
    auto d = [&](std::size_t i, std::size_t x) { return (long long)c[i][x] - (long long)c[0][x]; };
    const bool ccw = d(1, b) * d(2, e) - d(1, e) * d(2, b) > 0;  // about +e_axis, in index space
    const bool out_of_higher = pr[0] > pr[1];
    if (ccw != (InterfaceComplex::face_plus(k.faces[f]) == out_of_higher) != reflect)
      return fails("triangle " + std::to_string(t) + " is not oriented as its face");
    unsigned mask = 15;
    for (std::size_t i = 0; i < 3; ++i) mask &= ~(1u << ((c[i][b] - lo[b]) + 2 * (c[i][e] - lo[e])));
    if (seen[f] >> 4 == 2) return fails("face " + std::to_string(f) + " of K(X) has more than two triangles");
    seen[f] = std::uint8_t(((seen[f] >> 4) + 1) << 4 | (seen[f] & 15) | mask);
  }
  for (std::size_t f = 0; f < seen.size(); ++f)
    if (seen[f] != (2 << 4 | 9) && seen[f] != (2 << 4 | 6))
      return fails("face " + std::to_string(f) + " of K(X) is not split in two along a diagonal");
  r.holds = true;
  return r;
}

std::vector<int> net_depths(const MeshTopology& surface, const std::vector<Vec3>& points, const Geometry& grid,
                            const std::array<std::size_t, 3>& lattice, double slack,
                            const std::array<std::size_t, 3>& crop_lo, const VoxelBoundary& vb, const MeshTopology& bt) {
  const auto& ids = vb.lattice_ids;
  const std::uint64_t nx = vb.lattice[0], ny = vb.lattice[1];
  std::vector<int> depth(surface.components.size(), 0), crossed;
  for (std::size_t a = 0; a < depth.size(); ++a) {
    std::uint64_t rest = net_corner(points[surface.components[a].first_vertex], grid, lattice, slack);
    if (rest == NetCells::kNoCorner) return {};
    // Its corner in the crop's lattice, and the component of bdCA(L) there.
    std::array<long long, 3> c{};
    for (std::size_t x = 0; x < 3; ++x) {
      c[x] = (long long)(rest % lattice[x]) - (long long)crop_lo[x];
      rest /= lattice[x];
      if (c[x] < 0 || c[x] >= (long long)vb.lattice[x]) return {};
    }
    const std::uint64_t at = std::uint64_t(c[0]) + nx * (std::uint64_t(c[1]) + ny * std::uint64_t(c[2]));
    const auto own = std::lower_bound(ids.begin(), ids.end(), at);
    if (own == ids.end() || *own != at) return {};
    const int self = bt.component_of[std::size_t(own - ids.begin())];
    // From voxel c - 1 along -x: the faces normal to x at corners (0..c_x - 1, c_y - 1, c_z - 1).
    crossed.clear();
    if (c[1] > 0 && c[2] > 0) {
      const std::uint64_t row = nx * (std::uint64_t(c[1] - 1) + ny * std::uint64_t(c[2] - 1));
      for (auto it = std::lower_bound(ids.begin(), ids.end(), row); it != ids.end() && *it < row + std::uint64_t(c[0]); ++it)
        if (vb.faces[std::size_t(it - ids.begin())] & VoxelBoundary::kNormalAxis)
          crossed.push_back(bt.component_of[std::size_t(it - ids.begin())]);
    }
    std::sort(crossed.begin(), crossed.end());
    for (std::size_t i = 0, j; i < crossed.size(); i = j) {
      for (j = i; j < crossed.size() && crossed[j] == crossed[i];) ++j;
      depth[a] += crossed[i] != self && (j - i) % 2 == 1;
    }
  }
  return depth;
}

} // namespace imgmesh::surfacenets_detail
