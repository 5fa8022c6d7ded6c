// SurfaceGeometry over CGAL: one Surface_mesh of the whole surface, with
// an AABB tree per component (distances, nesting) and one over every
// triangle (sides), each built when first asked. The kernel has exact
// predicates: do_intersect of two triangles and the ray tests are exact on
// the input doubles; distances are constructions (rounded).
#include "mesh/embedding.hpp"

#include "util/error.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace imgmesh {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Face = Mesh::Face_index;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, K, CGAL::Default, Tree>;
using Point = K::Point_3;

// Whether triangles t and u (not degenerate) meet other than in what they
// share: PMP's do_faces_intersect on vertex ids. Sharing an edge pq (r, s
// the others), they overlap only when coplanar with r and s on one side of
// pq; sharing a vertex, when the edge opposite it in one crosses the other.
bool meet_improperly(const std::array<int, 3>& t, const std::array<int, 3>& u, const std::vector<Point>& p) {
  int shared = 0, ti[3], ui[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (t[std::size_t(i)] == u[std::size_t(j)]) ti[shared] = i, ui[shared++] = j;
  auto at = [&](const std::array<int, 3>& x, int i) -> const Point& { return p[std::size_t(x[std::size_t(i % 3)])]; };
  if (shared == 3) return true;
  if (shared == 2) {
    const Point &a = at(t, ti[0]), &b = at(t, ti[1]), &r = at(t, 3 - ti[0] - ti[1]), &s = at(u, 3 - ui[0] - ui[1]);
    return CGAL::coplanar(a, b, r, s) && CGAL::coplanar_orientation(a, b, r, s) == CGAL::POSITIVE;
  }
  const K::Triangle_3 tt(at(t, 0), at(t, 1), at(t, 2)), uu(at(u, 0), at(u, 1), at(u, 2));
  if (shared == 1)
    return CGAL::do_intersect(tt, K::Segment_3(at(u, ui[0] + 1), at(u, ui[0] + 2))) ||
           CGAL::do_intersect(uu, K::Segment_3(at(t, ti[0] + 1), at(t, ti[0] + 2)));
  return CGAL::do_intersect(tt, uu);
}

struct CapReached {};

} // namespace

std::vector<std::array<std::size_t, 2>> intersecting_triangles(const std::vector<Vec3>& points,
                                                               const std::vector<std::array<int, 3>>& triangles,
                                                               std::size_t cap) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
  std::vector<Point> p;
  p.reserve(points.size());
  for (const Vec3& x : points) p.emplace_back(x[0], x[1], x[2]);
  std::vector<std::array<std::size_t, 2>> out;
  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Point &a = p[std::size_t(triangles[t][0])], &b = p[std::size_t(triangles[t][1])], &c = p[std::size_t(triangles[t][2])];
    if (CGAL::collinear(a, b, c)) out.push_back({t, t});
    else boxes.emplace_back(a.bbox() + b.bbox() + c.bbox(), t);
  }
  if (out.size() >= cap) return {out.begin(), out.begin() + std::ptrdiff_t(cap)};
  std::vector<const Box*> ptrs;
  ptrs.reserve(boxes.size());
  for (const Box& b : boxes) ptrs.push_back(&b);
  auto test = [&](const Box* a, const Box* b) {
    const std::size_t t = a->info(), u = b->info();
    if (!meet_improperly(triangles[t], triangles[u], p)) return;
    out.push_back({std::min(t, u), std::max(t, u)});
    if (out.size() >= cap) throw CapReached{};
  };
  try {
    CGAL::box_self_intersection_d<CGAL::Sequential_tag>(ptrs.begin(), ptrs.end(), test, std::ptrdiff_t(2000));
  } catch (const CapReached&) {
  }
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

} // namespace imgmesh
