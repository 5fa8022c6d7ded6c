// SurfaceGeometry over CGAL: one Surface_mesh of the whole surface, with
// an AABB tree per component (distances, nesting) and one over every
// triangle (sides), each built when first asked. The kernel has exact
// predicates: do_intersect of two triangles and the ray tests are exact on
// the input doubles; distances are constructions (rounded). The soup test
// (triangles_cross) follows do_faces_intersect with vertices shared by id,
// after exact early exits that are cheap (Epick's statically filtered
// orientation): a triangle all on one side of the other's plane.
#include "mesh/embedding.hpp"

#include "util/error.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <cstdint>

namespace imgmesh {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Face = Mesh::Face_index;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, K, CGAL::Default, Tree>;

K::Point_3 point(const std::vector<Vec3>& points, int v) {
  const Vec3& p = points[std::size_t(v)];
  return {p[0], p[1], p[2]};
}

// Whether every point of q lies strictly on one side of the plane (a, b, c)
// (never for a degenerate a, b, c: every point is on its "plane").
bool strictly_one_side(const K::Point_3& a, const K::Point_3& b, const K::Point_3& c,
                       std::initializer_list<const K::Point_3*> q) {
  CGAL::Orientation side = CGAL::COPLANAR;
  for (const K::Point_3* x : q) {
    const CGAL::Orientation o = CGAL::orientation(a, b, c, *x);
    if (o == CGAL::COPLANAR || (side != CGAL::COPLANAR && o != side)) return false;
    side = o;
  }
  return true;
}
// The axis all six corners share exactly (planes of a voxel map's flat
// regions), or -1. There the test is done exactly in the other two axes
// (a projection that changes nothing), where the predicates rarely meet
// the exact zeros that make 3D ones slow.
int common_axis(const std::array<K::Point_3, 3>& p, const std::array<K::Point_3, 3>& q) {
  for (int a = 0; a < 3; ++a) {
    const double x = p[0][a];
    if (p[1][a] == x && p[2][a] == x && q[0][a] == x && q[1][a] == x && q[2][a] == x) return a;
  }
  return -1;
}

std::array<K::Point_2, 3> project(const std::array<K::Point_3, 3>& p, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return {K::Point_2(p[0][u], p[0][v]), K::Point_2(p[1][u], p[1][v]), K::Point_2(p[2][u], p[2][v])};
}

// triangles_cross for two triangles in one plane of constant `axis`, with
// `shared` ids in common; i, j: the positions in a and in b of the shared
// vertex (shared == 1) or of the corners not shared (shared == 2).
bool plane_triangles_cross(const std::array<K::Point_2, 3>& p, const std::array<K::Point_2, 3>& q, int shared,
                           std::size_t i, std::size_t j) {
  if (shared == 2)
    return CGAL::orientation(p[(i + 1) % 3], p[(i + 2) % 3], p[i]) == CGAL::orientation(p[(i + 1) % 3], p[(i + 2) % 3], q[j]);
  if (shared == 1) {
    // Met only at the shared vertex when a line through it along an edge
    // of one has the other's far corners strictly on the side away from it.
    auto separates = [](const K::Point_2& o, const K::Point_2& x, const K::Point_2& own, const K::Point_2& f0,
                        const K::Point_2& f1) {
      const CGAL::Orientation side = CGAL::orientation(o, x, own);
      return CGAL::orientation(o, x, f0) == -side && CGAL::orientation(o, x, f1) == -side;
    };
    const K::Point_2 &o = p[i], &a1 = p[(i + 1) % 3], &a2 = p[(i + 2) % 3], &b1 = q[(j + 1) % 3], &b2 = q[(j + 2) % 3];
    if (separates(o, a1, a2, b1, b2) || separates(o, a2, a1, b1, b2) || separates(o, b1, b2, a1, a2) ||
        separates(o, b2, b1, a1, a2))
      return false;
    return CGAL::do_intersect(K::Triangle_2(p[0], p[1], p[2]), K::Segment_2(b1, b2)) ||
           CGAL::do_intersect(K::Triangle_2(q[0], q[1], q[2]), K::Segment_2(a1, a2));
  }
  return CGAL::do_intersect(K::Triangle_2(p[0], p[1], p[2]), K::Triangle_2(q[0], q[1], q[2]));
}
} // namespace

bool triangle_degenerate(const std::vector<Vec3>& points, const std::array<int, 3>& t) {
  return CGAL::collinear(point(points, t[0]), point(points, t[1]), point(points, t[2]));
}

bool triangles_cross(const std::vector<Vec3>& points, const std::array<int, 3>& a, const std::array<int, 3>& b) {
  // How many ids they share; i, j: the positions in a and in b of a shared
  // vertex (one shared) or of the corners not shared (two).
  int shared = 0;
  std::size_t i = 0, j = 0;
  std::array<bool, 3> a_shared{false, false, false}, b_shared{false, false, false};
  for (std::size_t x = 0; x < 3; ++x)
    for (std::size_t y = 0; y < 3; ++y)
      if (a[x] == b[y]) {
        ++shared;
        a_shared[x] = b_shared[y] = true;
        i = x;
        j = y;
      }
  if (shared == 3) return true;  // the same triangle twice
  if (shared == 2) {
    i = j = 0;
    while (a_shared[i]) ++i;
    while (b_shared[j]) ++j;
  }
  const std::array<K::Point_3, 3> p{point(points, a[0]), point(points, a[1]), point(points, a[2])},
      q{point(points, b[0]), point(points, b[1]), point(points, b[2])};
  if (const int axis = common_axis(p, q); axis >= 0)
    return plane_triangles_cross(project(p, axis), project(q, axis), shared, i, j);
  if (shared == 2) {
    // The shared edge e0 e1, a's third corner p[i], b's q[j]: coplanar, on one side.
    const K::Point_3 &e0 = p[(i + 1) % 3], &e1 = p[(i + 2) % 3];
    return CGAL::coplanar(e0, e1, p[i], q[j]) && CGAL::coplanar_orientation(e0, e1, p[i], q[j]) == CGAL::POSITIVE;
  }
  const std::size_t i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
  if (shared == 1) {
    // b's far corners strictly on one side of a's plane: b meets that plane,
    // hence a, only in the shared vertex (and the same the other way).
    if (strictly_one_side(p[0], p[1], p[2], {&q[j1], &q[j2]}) || strictly_one_side(q[0], q[1], q[2], {&p[i1], &p[i2]}))
      return false;
    const K::Triangle_3 ta(p[0], p[1], p[2]), tb(q[0], q[1], q[2]);
    return CGAL::do_intersect(ta, K::Segment_3(q[j1], q[j2])) || CGAL::do_intersect(tb, K::Segment_3(p[i1], p[i2]));
  }
  if (strictly_one_side(p[0], p[1], p[2], {&q[0], &q[1], &q[2]}) || strictly_one_side(q[0], q[1], q[2], {&p[0], &p[1], &p[2]}))
    return false;
  return CGAL::do_intersect(K::Triangle_3(p[0], p[1], p[2]), K::Triangle_3(q[0], q[1], q[2]));
}

std::vector<std::array<std::size_t, 2>> soup_crossing_pairs(const std::vector<Vec3>& points,
                                                            const std::vector<std::array<int, 3>>& triangles,
                                                            std::size_t cap) {
  // Float boxes rounded outward (more candidates, never fewer; the exact
  // test decides), searched through pointers: 36 bytes a triangle where
  // double boxes copied by the search took 128, beside the mesher's
  // triangulation at its peak.
  using Box = CGAL::Box_intersection_d::Box_with_info_d<float, 3, std::uint32_t, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
  struct CapReached {};
  if (triangles.size() > std::numeric_limits<std::uint32_t>::max()) throw Error("too many triangles");
  auto down = [](double x) {
    const float f = float(x);
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
  };
  auto up = [](double x) {
    const float f = float(x);
    return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
  };
  std::vector<std::array<std::size_t, 2>> out;
  std::vector<Box> boxes;
  for (std::size_t t = 0; t < triangles.size() && out.size() < cap; ++t) {
    if (triangle_degenerate(points, triangles[t])) {
      out.push_back({t, t});
      continue;
    }
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      double l = points[std::size_t(triangles[t][0])][a], h = l;
      for (int m = 1; m < 3; ++m) {
        l = std::min(l, points[std::size_t(triangles[t][m])][a]);
        h = std::max(h, points[std::size_t(triangles[t][m])][a]);
      }
      lo[a] = down(l);
      hi[a] = up(h);
    }
    boxes.emplace_back(lo, hi, std::uint32_t(t));
  }
  std::vector<const Box*> at(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) at[i] = &boxes[i];
  if (out.size() < cap) try {
      CGAL::box_self_intersection_d(at.begin(), at.end(), [&](const Box* x, const Box* y) {
        const std::size_t a = x->info(), b = y->info();
        if (!triangles_cross(points, triangles[a], triangles[b])) return;
        out.push_back({std::min(a, b), std::max(a, b)});
        if (out.size() >= cap) throw CapReached{};
      });
    } catch (const CapReached&) {
    }
  std::sort(out.begin(), out.end());
  return out;
}

struct SurfaceGeometry::Impl {
  Mesh mesh;
  std::vector<std::vector<Face>> faces;  // per component, ascending
  mutable std::vector<std::unique_ptr<Tree>> trees;
  mutable std::unique_ptr<Tree> all;

  const Tree& tree(std::size_t c) const {
    if (!trees[c]) {
      trees[c] = std::make_unique<Tree>(faces[c].begin(), faces[c].end(), mesh);
      trees[c]->accelerate_distance_queries();
    }
    return *trees[c];
  }
};

SurfaceGeometry::SurfaceGeometry(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                 const std::vector<int>& component, std::size_t components)
    : impl_(std::make_unique<Impl>()) {
  Mesh& m = impl_->mesh;
  m.reserve(Mesh::size_type(points.size()), Mesh::size_type(3 * triangles.size() / 2), Mesh::size_type(triangles.size()));
  for (const Vec3& p : points) m.add_vertex(K::Point_3(p[0], p[1], p[2]));
  impl_->faces.resize(components);
  impl_->trees.resize(components);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const std::array<Mesh::Vertex_index, 3> vs{Mesh::Vertex_index(Mesh::size_type(triangles[t][0])),
                                               Mesh::Vertex_index(Mesh::size_type(triangles[t][1])),
                                               Mesh::Vertex_index(Mesh::size_type(triangles[t][2]))};
    const Face f = CGAL::Euler::add_face(vs, m);
    // Faces are numbered in the order they are added: face t is triangle t.
    if (f == Mesh::null_face() || std::size_t(f) != t)
      throw Error("the surface's triangles do not make a manifold, consistently oriented surface");
    impl_->faces.at(std::size_t(component[t])).push_back(f);
  }
}

SurfaceGeometry::~SurfaceGeometry() = default;

std::vector<std::array<std::size_t, 2>> SurfaceGeometry::intersecting_pairs(std::size_t cap) const {
  std::vector<std::pair<Face, Face>> found;
  CGAL::Polygon_mesh_processing::self_intersections(impl_->mesh, std::back_inserter(found),
                                                    CGAL::parameters::maximum_number(unsigned(cap)));
  std::vector<std::array<std::size_t, 2>> out(found.size());
  for (std::size_t i = 0; i < found.size(); ++i) {
    out[i] = {std::size_t(found[i].first), std::size_t(found[i].second)};
    if (out[i][0] > out[i][1]) std::swap(out[i][0], out[i][1]);
  }
  return out;
}

SelfIntersections SurfaceGeometry::self_intersections(std::size_t cap) const {
  return summarize_intersections(intersecting_pairs(cap), cap);
}

SelfIntersections summarize_intersections(const std::vector<std::array<std::size_t, 2>>& found, std::size_t cap) {
  SelfIntersections s;
  s.pairs = found.size();
  s.capped = cap > 0 && found.size() >= cap;
  for (std::size_t i = 0; i < found.size(); ++i) {
    s.degenerate += found[i][0] == found[i][1];
    if (i == 0 || found[i] < s.first) s.first = found[i];
  }
  return s;
}

std::vector<int> SurfaceGeometry::nesting_depths(const std::vector<int>& component_of) const {
  const Mesh& m = impl_->mesh;
  const std::size_t n = impl_->faces.size();
  std::vector<CGAL::Bbox_3> box(n);
  std::vector<std::vector<Mesh::Vertex_index>> samples(n);  // per component, its vertices ascending
  for (std::size_t v = 0; v < component_of.size(); ++v) {
    const int c = component_of[v];
    if (c < 0) continue;
    const Mesh::Vertex_index x{Mesh::size_type(v)};
    box[std::size_t(c)] += m.point(x).bbox();
    samples[std::size_t(c)].push_back(x);
  }
  auto within = [](const K::Point_3& p, const CGAL::Bbox_3& b) {
    return p.x() >= b.xmin() && p.y() >= b.ymin() && p.z() >= b.zmin() && p.x() <= b.xmax() && p.y() <= b.ymax() &&
           p.z() <= b.zmax();
  };
  std::vector<int> depth(n, 0);
  for (std::size_t b = 0; b < n; ++b) {
    std::unique_ptr<Side> side;
    for (std::size_t a = 0; a < n; ++a) {
      // Only a component whose first vertex is in b's box can be inside b.
      if (a == b || samples[a].empty() || !within(m.point(samples[a][0]), box[b])) continue;
      if (!side) side = std::make_unique<Side>(impl_->tree(b));
      // a's first vertex not on b's surface (the two meet only where
      // triangles intersect, which the certificate refuses anyway).
      for (Mesh::Vertex_index x : samples[a]) {
        const CGAL::Bounded_side s = (*side)(m.point(x));
        if (s == CGAL::ON_BOUNDARY) continue;
        depth[a] += s == CGAL::ON_BOUNDED_SIDE;
        break;
      }
    }
  }
  return depth;
}

double SurfaceGeometry::distance(const Vec3& p, int component) const {
  return std::sqrt(impl_->tree(std::size_t(component)).squared_distance(K::Point_3(p[0], p[1], p[2])));
}

int SurfaceGeometry::side(const Vec3& p) const {
  if (!impl_->all) impl_->all = std::make_unique<Tree>(faces(impl_->mesh).first, faces(impl_->mesh).second, impl_->mesh);
  const CGAL::Bounded_side s = Side(*impl_->all)(K::Point_3(p[0], p[1], p[2]));
  return s == CGAL::ON_BOUNDED_SIDE ? -1 : s == CGAL::ON_BOUNDARY ? 0 : 1;
}

struct LineSides::Impl {
  const std::vector<Vec3>& points;
  const std::vector<std::array<int, 3>>& triangles;
  int axis, u, v;  // the rays' axis; (u, v, axis) a cyclic order of (x, y, z)
  // Bins of side h over the (u, v) box of the triangles from (u0, v0): per
  // bin (u fastest) its triangles, those whose (u, v) box meets it.
  bool binned = false;  // else (non-finite points, too many triangles) every line grazes
  double u0 = 0, v0 = 0, u1 = -1, v1 = -1, h = 1;
  std::size_t nu = 0, nv = 0;
  std::vector<std::uint32_t> start, items;
  // The last line: its (u, v), whether it grazes, and the triangles it
  // crosses with the sign of their normal's axis component (the
  // projection's orientation).
  bool cached = false, grazing = false;
  double lu = 0, lv = 0;
  std::vector<std::pair<std::uint32_t, CGAL::Orientation>> crossed;

  Impl(const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& t, int a)
      : points(p), triangles(t), axis(a), u((a + 1) % 3), v((a + 2) % 3) {}
  std::size_t bin(double x, double lo, std::size_t n) const {
    return std::min(n - 1, std::size_t((x - lo) / h));  // monotone in x: a box's bins hold its points'
  }
  void box(const std::array<int, 3>& t, int a, double& lo, double& hi) const {
    lo = hi = points[std::size_t(t[0])][a];
    for (int c = 1; c < 3; ++c) {
      lo = std::min(lo, points[std::size_t(t[std::size_t(c)])][a]);
      hi = std::max(hi, points[std::size_t(t[std::size_t(c)])][a]);
    }
  }
  void line(double pu, double pv);
};

LineSides::LineSides(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles, int axis)
    : impl_(std::make_unique<Impl>(points, triangles, axis)) {
  Impl& m = *impl_;
  if (triangles.size() > std::numeric_limits<std::uint32_t>::max() / 8) return;
  for (const auto& t : triangles)
    for (int c : t)
      if (!std::isfinite(points[std::size_t(c)][0]) || !std::isfinite(points[std::size_t(c)][1]) ||
          !std::isfinite(points[std::size_t(c)][2]))
        return;
  m.binned = true;
  if (triangles.empty()) return;
  // Bins the size of a mean triangle's (u, v) box, at most 4 a triangle.
  double extent = 0;
  m.u0 = m.v0 = std::numeric_limits<double>::infinity();
  m.u1 = m.v1 = -std::numeric_limits<double>::infinity();
  for (const auto& t : triangles) {
    double ulo, uhi, vlo, vhi;
    m.box(t, m.u, ulo, uhi);
    m.box(t, m.v, vlo, vhi);
    m.u0 = std::min(m.u0, ulo), m.u1 = std::max(m.u1, uhi), m.v0 = std::min(m.v0, vlo), m.v1 = std::max(m.v1, vhi);
    extent += std::max(uhi - ulo, vhi - vlo);
  }
  m.h = extent / double(triangles.size());
  const double cap = 4.0 * double(triangles.size()) + 16;
  if (!(m.h > 0) || ((m.u1 - m.u0) / m.h + 1) * ((m.v1 - m.v0) / m.h + 1) > cap)
    m.h = std::max({m.h, (m.u1 - m.u0 + m.v1 - m.v0) / std::sqrt(cap), 1e-300});
  m.nu = std::size_t((m.u1 - m.u0) / m.h) + 1;
  m.nv = std::size_t((m.v1 - m.v0) / m.h) + 1;
  m.start.assign(m.nu * m.nv + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      for (std::size_t b = 1; b < m.start.size(); ++b) m.start[b] += m.start[b - 1];
      m.items.resize(m.start.back());
    }
    for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
      double ulo, uhi, vlo, vhi;
      m.box(triangles[ti], m.u, ulo, uhi);
      m.box(triangles[ti], m.v, vlo, vhi);
      for (std::size_t bv = m.bin(vlo, m.v0, m.nv); bv <= m.bin(vhi, m.v0, m.nv); ++bv)
        for (std::size_t bu = m.bin(ulo, m.u0, m.nu); bu <= m.bin(uhi, m.u0, m.nu); ++bu) {
          const std::size_t b = bv * m.nu + bu;
          if (pass == 0) ++m.start[b + 1];
          else m.items[m.start[b]++] = std::uint32_t(ti);
        }
    }
  }
  for (std::size_t b = m.start.size() - 1; b > 0; --b) m.start[b] = m.start[b - 1];  // back to each bin's first
  m.start[0] = 0;
}

LineSides::~LineSides() = default;

void LineSides::Impl::line(double pu, double pv) {
  cached = true, lu = pu, lv = pv, grazing = false;
  crossed.clear();
  if (!binned) {
    grazing = true;
    return;
  }
  if (triangles.empty() || !(pu >= u0 && pu <= u1 && pv >= v0 && pv <= v1)) return;
  const std::size_t b = bin(pv, v0, nv) * nu + bin(pu, u0, nu);
  const K::Point_2 q(pu, pv);
  for (std::uint32_t i = start[b]; i < start[b + 1]; ++i) {
    const auto& t = triangles[items[i]];
    double lo, hi;
    box(t, u, lo, hi);
    if (pu < lo || pu > hi) continue;
    box(t, v, lo, hi);
    if (pv < lo || pv > hi) continue;
    const Vec3 &a = points[std::size_t(t[0])], &b1 = points[std::size_t(t[1])], &c = points[std::size_t(t[2])];
    const K::Point_2 pa(a[u], a[v]), pb(b1[u], b1[v]), pc(c[u], c[v]);
    const CGAL::Orientation o = CGAL::orientation(pa, pb, pc);
    if (o == CGAL::COLLINEAR) {
      // Along the rays: its projection a segment (or a point), which the
      // line meets (within the box, on its line) or misses.
      const K::Point_2& far = pa != pb ? pb : pc;
      if (pa == far || CGAL::orientation(pa, far, q) == CGAL::COLLINEAR) {
        grazing = true;
        return;
      }
      continue;
    }
    const CGAL::Orientation e[3] = {CGAL::orientation(pa, pb, q), CGAL::orientation(pb, pc, q), CGAL::orientation(pc, pa, q)};
    if (e[0] == -o || e[1] == -o || e[2] == -o) continue;  // outside the closed projection
    if (e[0] == CGAL::COLLINEAR || e[1] == CGAL::COLLINEAR || e[2] == CGAL::COLLINEAR) {  // on its edge or corner
      grazing = true;
      return;
    }
    crossed.emplace_back(items[i], o);
  }
}

int LineSides::side(const Vec3& p) {
  Impl& m = *impl_;
  if (!m.cached || p[std::size_t(m.u)] != m.lu || p[std::size_t(m.v)] != m.lv) m.line(p[std::size_t(m.u)], p[std::size_t(m.v)]);
  if (m.grazing) return kGrazing;
  // (b - a) x (c - a) . (p - a) = n_axis (p_axis - t_axis) on the line: the
  // ray crosses the triangle (t_axis > p_axis) where the orientation has
  // the sign opposite to n_axis's.
  const K::Point_3 x(p[0], p[1], p[2]);
  std::size_t n = 0;
  for (const auto& [t, o] : m.crossed) {
    const auto& tri = m.triangles[t];
    const CGAL::Orientation s = CGAL::orientation(point(m.points, tri[0]), point(m.points, tri[1]), point(m.points, tri[2]), x);
    if (s == CGAL::COPLANAR) return 0;
    n += s == -o;
  }
  return n % 2 ? -1 : 1;
}

std::vector<int> nesting_depths(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                const std::vector<int>& component, std::size_t components,
                                const std::vector<int>& component_of) {
  const std::size_t n = components;
  std::vector<std::array<Vec3, 2>> box(n, {Vec3{INFINITY, INFINITY, INFINITY}, Vec3{-INFINITY, -INFINITY, -INFINITY}});
  std::vector<std::vector<std::size_t>> samples(n);  // per component, its vertices ascending
  for (std::size_t v = 0; v < component_of.size(); ++v) {
    const int c = component_of[v];
    if (c < 0) continue;
    for (int a = 0; a < 3; ++a) {
      box[std::size_t(c)][0][a] = std::min(box[std::size_t(c)][0][a], points[v][a]);
      box[std::size_t(c)][1][a] = std::max(box[std::size_t(c)][1][a], points[v][a]);
    }
    samples[std::size_t(c)].push_back(v);
  }
  auto within = [](const Vec3& p, const std::array<Vec3, 2>& b) {
    return p[0] >= b[0][0] && p[1] >= b[0][1] && p[2] >= b[0][2] && p[0] <= b[1][0] && p[1] <= b[1][1] && p[2] <= b[1][2];
  };
  std::vector<int> depth(n, 0);
  std::vector<std::array<int, 3>> own;  // component b's triangles
  for (std::size_t b = 0; b < n; ++b) {
    std::unique_ptr<LineSides> lines[3];
    std::unique_ptr<SurfaceGeometry> rays;
    auto side = [&](const Vec3& p) {
      for (int a = 0; a < 3; ++a) {
        if (!lines[a]) lines[a] = std::make_unique<LineSides>(points, own, a);
        if (const int s = lines[a]->side(p); s != LineSides::kGrazing) return s;
      }
      if (!rays) rays = std::make_unique<SurfaceGeometry>(points, own, std::vector<int>(own.size(), 0), 1);
      return rays->side(p);
    };
    bool built = false;
    for (std::size_t a = 0; a < n; ++a) {
      // Only a component whose first vertex is in b's box can be inside b.
      if (a == b || samples[a].empty() || !within(points[samples[a][0]], box[b])) continue;
      if (!built) {
        own.clear();
        for (std::size_t t = 0; t < triangles.size(); ++t)
          if (std::size_t(component[t]) == b) own.push_back(triangles[t]);
        built = true;
      }
      // a's first vertex not on b's surface (the two meet only where
      // triangles intersect, which the certificate refuses anyway).
      for (std::size_t x : samples[a]) {
        const int s = side(points[x]);
        if (s == 0) continue;
        depth[a] += s < 0;
        break;
      }
    }
  }
  return depth;
}

} // namespace imgmesh
