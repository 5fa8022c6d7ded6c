// VoxelSides (issue 38): the voxel centres on the wrong side of the
// restricted Delaunay surface and the points of S that refine them.
#include "surface/voxel_side_points.hpp"

#include "mesh/located_cells.hpp"
#include "surface/star.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace imgmesh::surface_detail {

namespace {

// Every corner of an active cube once, from the active cube of least key
// that holds it: grid order, and neighbouring centres one after the other.
// Per sorted active cube, the corners it visits (bit e for corner e).
std::vector<std::uint8_t> centre_corners(const CubeGrid& g) {
  std::vector<std::uint8_t> corners;
  corners.reserve(g.sorted_cubes().size());
  for (const ActiveCube& kc : g.sorted_cubes()) {
    const auto [x, y, z] = g.cube_of_key(kc.key());
    unsigned bits = 0;
    for (int e = 0; e < 8; ++e) {
      const long p[3] = {x + (e & 1), y + (e >> 1 & 1), z + (e >> 2 & 1)};
      bool first = true;
      for (int o = 1; o < 8 && first; ++o) {
        // Cube p - o = kc + (e - o) has the lesser key exactly when e - o
        // is negative in (z, y, x) order: only those are looked up.
        const int d[3] = {(e & 1) - (o & 1), (e >> 1 & 1) - (o >> 1 & 1), (e >> 2 & 1) - (o >> 2 & 1)};
        if (!(d[2] < 0 || (d[2] == 0 && (d[1] < 0 || (d[1] == 0 && d[0] < 0))))) continue;
        first = !g.active(p[0] - (o & 1), p[1] - (o >> 1 & 1), p[2] - (o >> 2 & 1));
      }
      if (first) bits |= 1u << e;
    }
    corners.push_back(std::uint8_t(bits));
  }
  return corners;
}

// A cell's largest vertex id, + 1 (a cell has three finite vertices or four).
std::uint32_t top_of(const Tr& tr, Ch c) {
  int top = -1;
  for (int i = 0; i < 4; ++i)
    if (!tr.is_infinite(c->vertex(i))) top = std::max(top, c->vertex(i)->info().id);
  return std::uint32_t(top + 1);
}

// The cell's side of S: its circumcentre's (f == 0 outside, as everywhere;
// beyond the grid's box, outside); an infinite cell is outside.
bool cell_inside(const Tr& tr, const SurfaceSampler& f, Ch c) { return !tr.is_infinite(c) && f.inside_at(vec(tr.dual(c))); }

// Where the segment from centre p to refine towards ends: the cell's
// circumcentre, or for an infinite cell a point beyond the grid's box, away
// from its hull facet (p lies on that facet's outer side).
Vec3 far_end(const Tr& tr, const CubeGrid& g, Ch c, const Vec3& p) {
  if (!tr.is_infinite(c)) return vec(tr.dual(c));
  const int i = c->index(tr.infinite_vertex());
  const std::array<Vh, 3> fv = facet_vertices(c, i);
  const Vec3 q0 = vec(fv[0]->point());
  Vec3 n = cross(sub(vec(fv[1]->point()), q0), sub(vec(fv[2]->point()), q0));
  const Ch in = c->neighbor(i);
  if (dot(n, sub(vec(in->vertex(in->index(c))->point()), q0)) > 0) n = {-n[0], -n[1], -n[2]};
  const double nl = norm(n);
  double reach = 0;  // far enough to leave the box
  for (int k = 0; k < 3; ++k) reach += std::abs(p[k]) + g.hi[k];
  return {p[0] + n[0] / nl * reach, p[1] + n[1] / nl * reach, p[2] + n[2] / nl * reach};
}

// The crossing of S on [a, b] (ends of opposite signs) by halving on signs
// alone, to ~1e-11 delta: far from S, implicit2mesh's f (clamped samples)
// and seg2mesh's differ in value, never in sign, so both find the same point.
bool crossing(const SurfaceSampler& f, Vec3 a, Vec3 b, Vec3& x) {
  const bool in = SurfaceSampler::inside(f.value(a));
  if (SurfaceSampler::inside(f.value(b)) == in) return false;
  const double tol2 = std::pow(1e-11 * f.grid().delta, 2);
  for (int it = 0; it < 200 && dist2(a, b) > tol2; ++it) {
    const Vec3 m{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    (SurfaceSampler::inside(f.value(m)) == in ? a : b) = m;
  }
  x = b;  // within 1e-11 delta of S
  return true;
}

} // namespace

Candidates VoxelSidePoints::operator()(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& by_id, Vh near,
                                        double guard, long long& wrong, long long& refused) {
  const CubeGrid& g = f.grid();
  if (corners_.empty()) {
    corners_ = centre_corners(g);
    std::size_t n = 0;
    for (std::uint8_t bits : corners_) n += std::size_t(__builtin_popcount(bits));
    cell_.assign(n, Ch());
    top_.assign(n, 0);
  }
  Candidates pts;
  Ch hint = near->cell();
  std::vector<Ch> cells;
  std::unordered_set<const void*> refined;  // membership only: the order is the centres'
  // Cells' sides this pass (W does not change during it), by address:
  // neighbouring centres often share a cell (its circumcentre costs ~500
  // instructions).
  constexpr std::size_t kSlots = 1 << 12;
  std::vector<std::pair<const void*, bool>> sides(kSlots, {nullptr, false});
  auto side_of = [&](Ch h) {
    auto& slot = sides[(reinterpret_cast<std::uintptr_t>(&*h) >> 4) & (kSlots - 1)];
    if (slot.first != &*h) slot = {&*h, cell_inside(tr, f, h)};
    return slot.second;
  };
  long last[3] = {-9, -9, -9};
  // Centre k, at grid point (x, y, z).
  const auto visit = [&](std::size_t k, long x, long y, long z) {
    // A centre still in the cell it was found right in is right. (The walk
    // starts from the last cell a walk found: a centre outside W's hull or
    // on a facet may be found in another cell from another start.)
    if (cell_[k] != Ch() && tr.tds().cells().is_used(cell_[k]) && top_of(tr, cell_[k]) == top_[k]) return;
    const Vec3 p{double(x) * g.s[0], double(y) * g.s[1], double(z) * g.s[2]};
    const Point pp(p[0], p[1], p[2]);
    Tr::Locate_type lt;
    int li, lj;
    // The walk starts from the last centre's cell when that centre is a
    // grid neighbour, else (the centres come in grid order, but a row of
    // active cubes jumps across the shape to the next) from a vertex of the
    // cell p was last found in (an insertion replaced that cell by cells
    // around the new point, next to the vertex's). It goes in floating
    // point first (locate_from): a voxel's step crosses ~6 cells, thin
    // ones near S, each a filtered orientation test or more and a random
    // draw in the exact walk. Where p is not inside one cell the exact walk
    // from the last centre's decides, as always.
    const bool adjacent = std::abs(x - last[0]) <= 1 && std::abs(y - last[1]) <= 1 && std::abs(z - last[2]) <= 1;
    last[0] = x, last[1] = y, last[2] = z;
    const Vh from = top_[k] == 0 ? Vh() : by_id[top_[k] - 1];
    const bool from_near = near_starts_ && !adjacent && from != Vh();
    Ch c = locate_from(tr, pp, lt, li, lj, hint, from_near ? from->cell() : Ch());
    hint = c;
    // The cells holding p: one, or those around the facet, edge or vertex it lies on.
    located_cells(tr, c, lt, li, lj, cells);
    const bool in = g.neg(x, y, z);
    Ch bad;
    for (Ch h : cells)
      if (side_of(h) != in) {
        bad = h;
        break;
      }
    cell_[k] = Ch();
    top_[k] = top_of(tr, c);
    if (bad == Ch()) {
      if (cells.size() == 1) cell_[k] = c;  // on a facet: looked at again
      return;
    }
    ++wrong;
    if (!refined.insert(&*bad).second) return;  // one point per cell and pass
    // The surface centre of the cell's restricted facet with the largest
    // ball, if that is at least half p's distance to W (DELMESH's usual
    // point, well spaced) and the guard; else the point of S towards the
    // circumcentre.
    const double d2 = dist2(p, vec(nearest_vertex(tr, pp, bad)->point()));
    const double least = std::max(d2 / 4, guard * guard);
    int best = -1;
    for (int i = 0; i < 4; ++i)
      if (bad->facet.restricted(i) && bad->facet[i].r2 >= least && (best < 0 || bad->facet[i].r2 > bad->facet[best].r2)) best = i;
    if (best >= 0) {
      pts.emplace_back(facet_center(Facet(bad, best)), bad->facet[best].r2);
      return;
    }
    Vec3 q;
    if (!crossing(f, p, far_end(tr, g, bad, p), q)) return;
    const Vh nv = nearest_vertex(tr, Point(q[0], q[1], q[2]), bad);
    const double clearance2 = dist2(q, vec(nv->point()));
    if (clearance2 < guard * guard) ++refused;
    else pts.emplace_back(q, clearance2);
  };
  std::size_t k = 0;
  const auto& cubes = g.sorted_cubes();
  for (std::size_t i = 0; i < cubes.size(); ++i) {
    const auto [x, y, z] = g.cube_of_key(cubes[i].key());
    for (int e = 0; e < 8; ++e)
      if (corners_[i] >> e & 1) visit(k++, x + (e & 1), y + (e >> 1 & 1), z + (e >> 2 & 1));
  }
  return pts;
}

} // namespace imgmesh::surface_detail
