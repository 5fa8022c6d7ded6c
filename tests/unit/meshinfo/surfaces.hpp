// Surfaces and images for the certificate's tests (test_certificate.cpp):
// well-composed images in rotated, anisotropic grids with an origin; right
// meshes of them (marching tetrahedra on the voxel centres, surfaces of
// revolution in index space, smooth wobbles well within the tolerance); and
// the edits that make wrong meshes of right ones. Inline, in imgmesh::test.
#pragma once
#include "mesh/topology.hpp"
#include "wellcomposed/well_composed.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <vector>

namespace imgmesh::test {

// A triangle surface (world coordinates unless said otherwise).
struct Surface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> tris;
  void add(const Surface& o) {
    const int n = int(points.size());
    points.insert(points.end(), o.points.begin(), o.points.end());
    for (auto t : o.tris) tris.push_back({t[0] + n, t[1] + n, t[2] + n});
  }
  Surface& flip() {
    for (auto& t : tris) std::swap(t[1], t[2]);
    return *this;
  }
  double volume() const {
    double v = 0;
    for (const auto& t : tris) {
      const Vec3 &a = points[std::size_t(t[0])], &b = points[std::size_t(t[1])], &c = points[std::size_t(t[2])];
      v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
    return v;
  }
};

// A grid of n voxels an axis with spacing, origin and a rotation (a quarter
// turn about z, then a tilt about x), as scanners write them.
inline Geometry scan_grid(std::array<std::size_t, 3> n, Vec3 spacing = {0.7, 0.7, 1.3}, Vec3 origin = {-41.5, 12.25, 80}) {
  Geometry g;
  g.dimension = 3;
  g.size = n;
  g.spacing = spacing;
  g.origin = origin;
  const double c = std::cos(0.3), s = std::sin(0.3);
  g.direction = {0, -1, 0, c, 0, -s, s, 0, c};  // columns: the index axes in world
  return g;
}

// The voxels whose index satisfies `in`, made well-composed as img2wc does.
inline BinaryImage solid(const Geometry& g, const std::function<bool(double, double, double)>& in) {
  BinaryImage img(g, 0);
  for (std::size_t k = 0; k < g.size[2]; ++k)
    for (std::size_t j = 0; j < g.size[1]; ++j)
      for (std::size_t i = 0; i < g.size[0]; ++i) img(i, j, k) = in(double(i), double(j), double(k));
  return make_well_composed(img).image;
}

inline Surface to_world(Surface s, const Geometry& g) {
  for (Vec3& p : s.points) p = g.world(p[0], p[1], p[2]);
  return s;
}

// A closed surface of revolution about the line through c along the first
// axis: profile points (x, r); the first and last are poles (r = 0) unless
// `ring`, where the profile is a closed loop (a torus). Outward.
inline Surface revolve(const std::vector<std::array<double, 2>>& profile, const Vec3& c, int segments, bool ring = false) {
  Surface s;
  const int n = int(profile.size());
  std::vector<int> first(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const bool pole = !ring && (i == 0 || i == n - 1);
    first[std::size_t(i)] = int(s.points.size());
    for (int j = 0; j < (pole ? 1 : segments); ++j) {
      const double a = 2 * M_PI * j / segments, r = profile[std::size_t(i)][1];
      s.points.push_back({c[0] + profile[std::size_t(i)][0], c[1] + r * std::cos(a), c[2] + r * std::sin(a)});
    }
  }
  auto at = [&](int i, int j) { return first[std::size_t(i % n)] + (j % segments); };
  for (int i = 0; i < (ring ? n : n - 1); ++i)
    for (int j = 0; j < segments; ++j) {
      if (!ring && i == 0) s.tris.push_back({first[0], at(1, j + 1), at(1, j)});
      else if (!ring && i == n - 2) s.tris.push_back({at(i, j), at(i, j + 1), first[std::size_t(n - 1)]});
      else {
        s.tris.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
        s.tris.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      }
    }
  if (s.volume() < 0) s.flip();
  return s;
}

inline Surface sphere(const Vec3& c, double r, int rings = 18, int segments = 28) {
  std::vector<std::array<double, 2>> p;
  for (int i = 0; i <= rings; ++i) {
    const double a = M_PI * i / rings;
    p.push_back({-r * std::cos(a), i == 0 || i == rings ? 0.0 : r * std::sin(a)});
  }
  return revolve(p, c, segments);
}

// The torus around the first axis: tube radius r at distance R from it.
inline Surface torus(const Vec3& c, double R, double r, int tube = 16, int segments = 36) {
  std::vector<std::array<double, 2>> p;
  for (int i = 0; i < tube; ++i) {
    const double a = 2 * M_PI * i / tube;
    p.push_back({r * std::sin(a), R + r * std::cos(a)});
  }
  return revolve(p, c, segments, true);
}

// bdCA(X) itself: its squares split into two triangles each, at the voxel
// corners (world coordinates).
inline Surface voxel_faces(const BinaryImage& img) {
  const VoxelBoundary b = voxel_boundary(img);
  Surface s;
  for (std::size_t v = 0; v < b.lattice_ids.size(); ++v) s.points.push_back(corner_position(img, b, v));
  for (std::size_t f = 0; f + 1 < b.offsets.size(); ++f) {
    const int* q = &b.corners[b.offsets[f]];
    s.tris.push_back({q[0], q[1], q[2]});
    s.tris.push_back({q[0], q[2], q[3]});
  }
  const auto& d = img.direction;  // a reflecting direction matrix turns the squares inside out
  const double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) + d[2] * (d[3] * d[7] - d[4] * d[6]);
  if (det < 0) s.flip();
  return s;
}

// Marching tetrahedra on the voxel centres (each cube of eight centres cut
// into six tetrahedra about its main diagonal), the level 1/2 of the 0/1
// image: a closed, outward 2-manifold whose vertices are midpoints of
// centres of different sides, which lie on bdCA(X); world coordinates.
inline Surface marching_tetrahedra(const BinaryImage& img) {
  const long nx = long(img.size[0]), ny = long(img.size[1]), nz = long(img.size[2]);
  auto in = [&](long i, long j, long k) { return img.at(i, j, k, 0) != 0; };
  auto key = [&](long i, long j, long k) { return ((k + 1) * (ny + 2) + (j + 1)) * (nx + 2) + (i + 1); };
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  Surface s;
  std::map<std::pair<long, long>, int> vertex;
  using L = std::array<long, 3>;
  auto mid = [&](const L& a, const L& b) {
    const std::pair<long, long> e{std::min(key(a[0], a[1], a[2]), key(b[0], b[1], b[2])),
                                  std::max(key(a[0], a[1], a[2]), key(b[0], b[1], b[2]))};
    auto it = vertex.find(e);
    if (it != vertex.end()) return it->second;
    s.points.push_back(img.world((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0));
    return vertex[e] = int(s.points.size()) - 1;
  };
  auto emit = [&](int a, int b, int c, const Vec3& from_in) {
    const Vec3 &p = s.points[std::size_t(a)], &q = s.points[std::size_t(b)], &r = s.points[std::size_t(c)];
    const Vec3 u{q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v{r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    if (n[0] * from_in[0] + n[1] * from_in[1] + n[2] * from_in[2] < 0) s.tris.push_back({a, c, b});
    else s.tris.push_back({a, b, c});
  };
  for (long k = -1; k < nz; ++k)
    for (long j = -1; j < ny; ++j)
      for (long i = -1; i < nx; ++i)
        for (const auto& pm : perms) {
          std::array<L, 4> t;
          t[0] = {i, j, k};
          for (int m = 0; m < 3; ++m) {
            t[std::size_t(m + 1)] = t[std::size_t(m)];
            ++t[std::size_t(m + 1)][std::size_t(pm[m])];
          }
          std::vector<L> ins, outs;
          for (const L& p : t) (in(p[0], p[1], p[2]) ? ins : outs).push_back(p);
          if (ins.empty() || outs.empty()) continue;
          Vec3 ci{0, 0, 0}, co{0, 0, 0};
          for (const L& p : ins) for (int a = 0; a < 3; ++a) ci[std::size_t(a)] += double(p[std::size_t(a)]) / double(ins.size());
          for (const L& p : outs) for (int a = 0; a < 3; ++a) co[std::size_t(a)] += double(p[std::size_t(a)]) / double(outs.size());
          const Vec3 wi = img.world(ci[0], ci[1], ci[2]), wo = img.world(co[0], co[1], co[2]);
          const Vec3 dir{wo[0] - wi[0], wo[1] - wi[1], wo[2] - wi[2]};
          if (ins.size() == 1 || outs.size() == 1) {
            const std::vector<L>& one = ins.size() == 1 ? ins : outs;
            const std::vector<L>& three = ins.size() == 1 ? outs : ins;
            emit(mid(one[0], three[0]), mid(one[0], three[1]), mid(one[0], three[2]), dir);
          } else {
            const int ac = mid(ins[0], outs[0]), ad = mid(ins[0], outs[1]), bd = mid(ins[1], outs[1]), bc = mid(ins[1], outs[0]);
            emit(ac, ad, bd, dir);
            emit(ac, bd, bc, dir);
          }
        }
  return s;
}

// Each vertex moved by a smooth field (a sum of three waves of the given
// wavelength, world units, random phases and directions): at most
// `amplitude` from where it was, and no fold for an amplitude small against
// the wavelength and the triangles.
inline void wobble(Surface& s, double amplitude, double wavelength, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::array<Vec3, 3> dir, kv;
  std::array<double, 3> phase;
  for (int w = 0; w < 3; ++w) {
    Vec3 d{u(rng), u(rng), u(rng)}, k{u(rng), u(rng), u(rng)};
    const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), kn = std::sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
    for (int a = 0; a < 3; ++a) {
      dir[std::size_t(w)][std::size_t(a)] = d[std::size_t(a)] / dn;
      kv[std::size_t(w)][std::size_t(a)] = k[std::size_t(a)] / kn * 2 * M_PI / wavelength;
    }
    phase[std::size_t(w)] = M_PI * u(rng);
  }
  for (Vec3& p : s.points) {
    Vec3 m{0, 0, 0};
    for (std::size_t w = 0; w < 3; ++w) {
      const double a = amplitude / 3 * std::sin(kv[w][0] * p[0] + kv[w][1] * p[1] + kv[w][2] * p[2] + phase[w]);
      for (int x = 0; x < 3; ++x) m[std::size_t(x)] += a * dir[w][std::size_t(x)];
    }
    for (int x = 0; x < 3; ++x) p[std::size_t(x)] += m[std::size_t(x)];
  }
}

} // namespace imgmesh::test
