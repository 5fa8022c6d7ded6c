// Meshes and images that the topology tests here and meshinfo's
// (tests/unit/meshinfo) are made of: closed and open surfaces of quads, a
// ball and a solid torus in a rotated anisotropic grid with their voxel
// boundary triangulated, and a disk and an annulus in pixels with a planar
// mesh of their squares. Inline, in imgmesh::test.
#pragma once
#include "mesh/topology.hpp"

#include <array>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <vector>

namespace imgmesh::test {

// A surface: faces on nv vertices.
struct Faces {
  std::size_t nv = 0;
  std::vector<std::vector<int>> f;
  void add(const Faces& o) {
    for (auto face : o.f) {
      for (int& v : face) v += int(nv);
      f.push_back(face);
    }
    nv += o.nv;
  }
};

// An (n x m) grid of quads, split into triangles; wrap_u / wrap_v glue
// opposite sides (torus when both, cylinder when one).
inline Faces grid(int n, int m, bool wrap_u, bool wrap_v) {
  Faces s;
  const int cu = wrap_u ? n : n + 1, cv = wrap_v ? m : m + 1;
  s.nv = std::size_t(cu * cv);
  auto id = [&](int i, int j) { return (j % cv) * cu + (i % cu); };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      s.f.push_back({a, b, c});
      s.f.push_back({a, c, d});
    }
  return s;
}

// A closed sphere: the boundary of an (n x n x n) cube of quads.
inline Faces cube_sphere(int n) {
  Faces s;
  std::map<std::array<int, 3>, int> id;
  auto v = [&](int x, int y, int z) {
    auto it = id.find({x, y, z});
    if (it != id.end()) return it->second;
    const int k = int(id.size());
    id[{x, y, z}] = k;
    return k;
  };
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      // Outward orientation on each of the six sides.
      s.f.push_back({v(a, b, 0), v(a, b + 1, 0), v(a + 1, b + 1, 0), v(a + 1, b, 0)});
      s.f.push_back({v(a, b, n), v(a + 1, b, n), v(a + 1, b + 1, n), v(a, b + 1, n)});
      s.f.push_back({v(a, 0, b), v(a + 1, 0, b), v(a + 1, 0, b + 1), v(a, 0, b + 1)});
      s.f.push_back({v(a, n, b), v(a, n, b + 1), v(a + 1, n, b + 1), v(a + 1, n, b)});
      s.f.push_back({v(0, a, b), v(0, a, b + 1), v(0, a + 1, b + 1), v(0, a + 1, b)});
      s.f.push_back({v(n, a, b), v(n, a + 1, b), v(n, a + 1, b + 1), v(n, a, b + 1)});
    }
  s.nv = id.size();
  return s;
}

// An empty n x n x n image.
inline BinaryImage image3(int n) {
  Geometry g;
  g.dimension = 3;
  g.size = {std::size_t(n), std::size_t(n), std::size_t(n)};
  return BinaryImage(g, 0);
}

// two_solids' grid.
inline constexpr int kSolidsNx = 40, kSolidsNy = 16, kSolidsNz = 16;

// A box "ball" at x 4..13 and a box ring "solid torus" at x 26..35 with the
// same outer box, so that mirroring x -> 39 - x puts each on the other's
// outer surface. Spacing and direction are not the identity.
inline BinaryImage two_solids(bool fill_hole) {
  Geometry g;
  g.dimension = 3;
  g.size = {kSolidsNx, kSolidsNy, kSolidsNz};
  g.origin = {-5, 3, 7};
  g.spacing = {0.8, 1.2, 2.0};
  g.direction = {0, -1, 0, 1, 0, 0, 0, 0, 1};  // a quarter turn about z
  BinaryImage img(g, 0);
  for (int z = 3; z <= 12; ++z)
    for (int y = 3; y <= 12; ++y)
      for (int x = 0; x < kSolidsNx; ++x) {
        const bool ball = x >= 4 && x <= 13;
        const bool ring = x >= 26 && x <= 35 && (fill_hole || !(x >= 29 && x <= 32 && y >= 6 && y <= 9));
        img(x, y, z) = ball || ring;
      }
  return img;
}

// A triangle mesh in world coordinates.
struct Tri {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> tris;
  void add(const Tri& o) {
    const int n = int(points.size());
    points.insert(points.end(), o.points.begin(), o.points.end());
    for (auto t : o.tris) tris.push_back({t[0] + n, t[1] + n, t[2] + n});
  }
};

// bdCA(X)'s quads as triangles in world coordinates, the components in
// `keep` only; mirrored in x about the grid's centre (faces flipped to stay
// outward) and each vertex moved by up to `jitter` lattice steps per axis.
inline Tri triangulate(const BinaryImage& img, const std::set<int>& keep, bool mirror, double jitter = 0,
                       unsigned seed = 1) {
  const VoxelBoundary b = voxel_boundary(img);
  const MeshTopology bt = mesh_topology(b);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  Tri t;
  for (std::size_t v = 0; v < b.lattice_ids.size(); ++v) {
    const auto c = b.corner(v);
    double i = double(c[0]) - 0.5, j = double(c[1]) - 0.5, k = double(c[2]) - 0.5;
    if (mirror) i = double(kSolidsNx - 1) - i;
    t.points.push_back(img.world(i + u(rng), j + u(rng), k + u(rng)));
  }
  for (std::size_t f = 0; f + 1 < b.offsets.size(); ++f) {
    const int* q = &b.corners[b.offsets[f]];
    if (!keep.count(bt.component_of[std::size_t(q[0])])) continue;
    if (mirror) { t.tris.push_back({q[0], q[2], q[1]}); t.tris.push_back({q[0], q[3], q[2]}); }
    else { t.tris.push_back({q[0], q[1], q[2]}); t.tris.push_back({q[0], q[2], q[3]}); }
  }
  return t;
}

// disk_and_annulus' grid.
inline constexpr int kDiskNx = 36, kDiskNy = 16;

// Disk: x 3..12; annulus: x 23..32 with the hole x 26..29, y 6..9; both y 3..12.
inline LabelImage disk_and_annulus(bool fill_hole, std::int32_t annulus_label = 1) {
  Geometry g;
  g.dimension = 2;
  g.size = {kDiskNx, kDiskNy, 1};
  g.origin = {-5, 3, 0};
  g.spacing = {0.8, 1.5, 1};
  LabelImage img(g, 0);
  for (int y = 3; y <= 12; ++y)
    for (int x = 0; x < kDiskNx; ++x) {
      if (x >= 3 && x <= 12) img(x, y) = 1;
      const bool hole = x >= 26 && x <= 29 && y >= 6 && y <= 9;
      if (x >= 23 && x <= 32 && (fill_hole || !hole)) img(x, y) = annulus_label;
    }
  return img;
}

// A planar mesh with a region label per face (meshinfo's PolyMesh holds it
// as well).
struct PixelMesh {
  std::vector<Vec3> points;
  std::vector<std::vector<int>> faces;
  std::vector<std::int32_t> region;
};

// One counter-clockwise quad per pixel of `img` split into two triangles,
// labelled as the pixel; background faces too unless foreground_only. Points
// in world coordinates, mirrored in x about the grid's centre when asked,
// each moved by up to `jitter` pixels per axis.
inline PixelMesh pixel_mesh(const LabelImage& img, bool mirror = false, double jitter = 0,
                            bool foreground_only = false, unsigned seed = 1) {
  PixelMesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  const std::size_t W = img.size[0] + 1;
  for (std::size_t j = 0; j <= img.size[1]; ++j)
    for (std::size_t i = 0; i < W; ++i) {
      double x = double(i) - 0.5 + u(rng), y = double(j) - 0.5 + u(rng);
      if (mirror) x = double(img.size[0] - 1) - x;
      const Vec3 p = img.world(0, 0, 0);
      m.points.push_back({p[0] + x * img.spacing[0], p[1] + y * img.spacing[1], 0.0});
    }
  for (std::size_t y = 0; y < img.size[1]; ++y)
    for (std::size_t x = 0; x < img.size[0]; ++x) {
      const std::int32_t l = img(x, y);
      if (foreground_only && !l) continue;
      const int a = int(x + W * y), b = a + 1, c = b + int(W), d = a + int(W);
      m.faces.push_back({a, b, c});
      m.faces.push_back({a, c, d});
      m.region.push_back(l);
      m.region.push_back(l);
    }
  if (foreground_only) m.region.clear();
  return m;
}

} // namespace imgmesh::test
