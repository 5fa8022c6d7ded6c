// The unsmoothed surface-nets mesh of K(X) and its per-label surfaces
// (surface_nets.hpp).
#include "surfacenets/surface_nets.hpp"

#include "surfacenets/surface_nets_detail.hpp"
#include "util/error.hpp"
#include "util/ranked_bits.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace imgmesh {
namespace {

std::array<std::uint64_t, 3> strides(const std::array<std::size_t, 3>& lattice) {
  return {1, lattice[0], std::uint64_t(lattice[0]) * lattice[1]};
}

// The four corners of face `key`, counter-clockwise about its normal out of
// the higher label (index space): q, q + e_b, q + e_b + e_c, q + e_c has
// normal e_b x e_c = +e_a for (a, b, c) cyclic.
std::array<std::uint64_t, 4> face_corners(std::uint64_t key, const std::array<std::uint64_t, 3>& s) {
  const std::uint64_t q = InterfaceComplex::face_corner(key);
  const int a = InterfaceComplex::face_axis(key);
  const std::uint64_t b = s[std::size_t((a + 1) % 3)], c = s[std::size_t((a + 2) % 3)];
  if (InterfaceComplex::face_plus(key)) return {q, q + b, q + b + c, q + c};
  return {q, q + c, q + b + c, q + b};
}

int vertex_of(const std::vector<std::uint64_t>& corners, std::uint64_t c) {
  return int(std::lower_bound(corners.begin(), corners.end(), c) - corners.begin());
}

// Kinds and the neighbours each vertex is relaxed toward.
void relaxation_graph(InterfaceMesh& m, const InterfaceComplex& k) {
  const auto s = strides(m.lattice);
  m.kind.assign(m.corners.size(), InterfaceMesh::kSurface);
  std::vector<std::pair<int, int>> curve_pairs;
  for (std::uint64_t e : k.curve_edges) {
    const std::uint64_t c = e / 3;
    const int v = vertex_of(m.corners, c), w = vertex_of(m.corners, c + s[e % 3]);
    curve_pairs.emplace_back(v, w);
    m.kind[std::size_t(v)] = m.kind[std::size_t(w)] = InterfaceMesh::kCurve;
  }
  for (std::uint64_t j : k.junctions) m.kind[std::size_t(vertex_of(m.corners, j))] = InterfaceMesh::kJunction;
  for (std::uint64_t j : k.pinches) m.kind[std::size_t(vertex_of(m.corners, j))] = InterfaceMesh::kJunction;
  std::vector<std::pair<int, int>> pairs;
  auto add = [&](int v, int w, InterfaceMesh::Kind kind) {
    if (m.kind[std::size_t(v)] == kind) pairs.emplace_back(v, w);
    if (m.kind[std::size_t(w)] == kind) pairs.emplace_back(w, v);
  };
  for (const auto& q : m.quads)
    for (int i = 0; i < 4; ++i) add(q[std::size_t(i)], q[std::size_t((i + 1) % 4)], InterfaceMesh::kSurface);
  for (const auto& p : curve_pairs) add(p.first, p.second, InterfaceMesh::kCurve);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  m.neighbour_offsets.assign(m.corners.size() + 1, 0);
  for (const auto& p : pairs) ++m.neighbour_offsets[std::size_t(p.first) + 1];
  for (std::size_t v = 0; v < m.corners.size(); ++v) m.neighbour_offsets[v + 1] += m.neighbour_offsets[v];
  m.neighbours.resize(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) m.neighbours[i] = pairs[i].second;  // sorted: CSR order
}

// 4 sqrt(3) area / sum of squared edge lengths.
double triangle_quality(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]},
      w{c[0] - b[0], c[1] - b[1], c[2] - b[2]};
  const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double area2 = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double sum = u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + v[0] * v[0] + v[1] * v[1] + v[2] * v[2] +
                     w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  return sum > 0 ? 2 * std::sqrt(3.0) * area2 / sum : 0;
}

} // namespace

std::array<std::size_t, 3> InterfaceMesh::corner(std::size_t vertex) const {
  const std::uint64_t id = corners[vertex];
  return {std::size_t(id % lattice[0]), std::size_t(id / lattice[0] % lattice[1]),
          std::size_t(id / lattice[0] / lattice[1])};
}

std::vector<Vec3> corner_points(const InterfaceMesh& m) {
  std::vector<Vec3> p(m.corners.size());
  for (std::size_t v = 0; v < p.size(); ++v) {
    const auto c = m.corner(v);
    p[v] = m.grid.world(double(c[0]) - 0.5, double(c[1]) - 0.5, double(c[2]) - 0.5);
  }
  return p;
}

InterfaceMesh interface_mesh(const Geometry& image, const InterfaceComplex& k) {
  if (k.dimension != 3) throw Error("interface_mesh: a 3D label image is needed");
  if (k.critical.total()) throw Error("interface_mesh: " + k.failed_guarantee());
  InterfaceMesh m;
  m.grid = image;
  m.lattice = k.lattice;
  const auto s = strides(m.lattice);
  // The corners K(X)'s faces touch, and each one's rank among them (its
  // vertex id: vertices in ascending corner order).
  RankedBits ranks(std::uint64_t(m.lattice[0]) * m.lattice[1] * m.lattice[2]);
  for (std::uint64_t f : k.faces)
    for (std::uint64_t c : face_corners(f, s)) ranks.set(c);
  ranks.rank();
  if (ranks.count() > 0x7fffffffu) throw Error("interface_mesh: more than 2^31 vertices");
  ranks.list(m.corners);
  m.points = corner_points(m);
  const bool reflect = surfacenets_detail::reflects(image);
  m.quads.resize(k.faces.size());
  m.labels.resize(k.faces.size());
  for (std::size_t f = 0; f < k.faces.size(); ++f) {
    const auto c = face_corners(k.faces[f], s);
    for (int i = 0; i < 4; ++i) m.quads[f][std::size_t(i)] = int(ranks(c[std::size_t(i)]));
    if (reflect) std::swap(m.quads[f][1], m.quads[f][3]);
    const auto& p = k.patches[k.face_patch[f]];
    m.labels[f] = {p.behind, p.front};
  }
  relaxation_graph(m, k);
  split_quads(m);
  return m;
}

void split_quads(InterfaceMesh& m) {
  m.triangles.resize(m.quads.size() * 2);
  for (std::size_t f = 0; f < m.quads.size(); ++f) surfacenets_detail::split_quad(m, f);
}

bool surfacenets_detail::reflects(const Geometry& grid) {
  const auto& m = grid.direction;
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]) < 0;
}

void surfacenets_detail::split_quad(InterfaceMesh& m, std::size_t f) {
  const auto& q = m.quads[f];
  const Vec3 &p0 = m.points[std::size_t(q[0])], &p1 = m.points[std::size_t(q[1])], &p2 = m.points[std::size_t(q[2])],
             &p3 = m.points[std::size_t(q[3])];
  const double first = std::min(triangle_quality(p0, p1, p2), triangle_quality(p0, p2, p3));
  const double second = std::min(triangle_quality(p0, p1, p3), triangle_quality(p1, p2, p3));
  // A margin so that rounding never decides a planar rectangle's split.
  if (second > first * (1 + 1e-9)) {
    m.triangles[2 * f] = {q[0], q[1], q[3]};
    m.triangles[2 * f + 1] = {q[1], q[2], q[3]};
  } else {
    m.triangles[2 * f] = {q[0], q[1], q[2]};
    m.triangles[2 * f + 1] = {q[0], q[2], q[3]};
  }
}

std::vector<std::array<int, 3>> label_triangles(const InterfaceMesh& m, std::int32_t label,
                                                std::vector<std::size_t>* face_of) {
  std::vector<std::array<int, 3>> out;
  if (face_of) face_of->clear();
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto l = m.triangle_labels(t);
    if (l[0] != label && l[1] != label) continue;
    auto tri = m.triangles[t];
    if (l[1] == label) std::swap(tri[1], tri[2]);
    out.push_back(tri);
    if (face_of) face_of->push_back(t);
  }
  return out;
}

} // namespace imgmesh
