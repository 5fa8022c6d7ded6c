// poly2tri's engine: CGAL constrained Delaunay triangulation + Delaunay
// refinement, then Triangle's conventions on the result (region attributes,
// segment markers carried to the subsegments and their vertices). The
// driver, triangulate_pslg, at the end; the lattices in lattice.cpp.
// CGAL's assertions on here, NDEBUG or not: where rounded refinement points
// break the mesher's invariants (a point in conflict with neither face beside
// the segment it splits, a flat face among the bad ones) CGAL's check throws,
// where without it the next step dereferences a null face. Cost: within the
// noise on a 100,000-triangle mesh (BrainT1Slice.poly --max-area 0.5).
#define CGAL_DEBUG
#include "planar/triangulate.hpp"

#include "planar/triangulate_detail.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

// Delaunay refinement places its points by inexact constructions
// (circumcentres, segment midpoints, cluster split points). Next to features
// of a few units in the last place of their coordinates a rounded point can
// fall on an end of its segment or off its circle, or come out non-finite;
// CGAL then walks the triangulation into a null face (SIGSEGV) or hands inf
// to an exact predicate, which GMP answers with SIGFPE (issue 35). So every
// refinement point is checked as it is made, and such an input refused.
namespace imgmesh::planar_detail {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

struct RefinementKernel : Epick {
  [[noreturn]] static void beyond_precision(const Epick::Point_2& near) {
    std::ostringstream msg;
    msg << std::setprecision(6) << "refinement needs a point beyond double precision near (" << near.x() << ", "
        << near.y() << "): features there are too small for the size of their coordinates";
    throw Error(msg.str());
  }
  static bool finite(const Epick::Point_2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

  struct Construct_circumcenter_2 : Epick::Construct_circumcenter_2 {
    template <class... P> Epick::Point_2 operator()(const Epick::Point_2& a, const P&... rest) const {
      const Epick::Point_2 c = Epick::Construct_circumcenter_2::operator()(a, rest...);
      if (!finite(c)) beyond_precision(a);
      return c;
    }
  };
  // A segment's split point: strictly inside its diametral circle (it then
  // conflicts with a face beside the segment, as the mesher needs).
  struct Construct_midpoint_2 : Epick::Construct_midpoint_2 {
    Epick::Point_2 operator()(const Epick::Point_2& a, const Epick::Point_2& b) const {
      const Epick::Point_2 m = Epick::Construct_midpoint_2::operator()(a, b);
      if (!finite(m) || CGAL::side_of_bounded_circle(a, b, m) != CGAL::ON_BOUNDED_SIDE) beyond_precision(a);
      return m;
    }
  };
  // A cluster's split point, a + v: not a itself.
  struct Construct_translated_point_2 : Epick::Construct_translated_point_2 {
    Epick::Point_2 operator()(const Epick::Point_2& a, const Epick::Vector_2& v) const {
      const Epick::Point_2 p = Epick::Construct_translated_point_2::operator()(a, v);
      if (!finite(p) || p == a) beyond_precision(a);
      return p;
    }
  };
  Construct_circumcenter_2 construct_circumcenter_2_object() const { return {}; }
  Construct_midpoint_2 construct_midpoint_2_object() const { return {}; }
  Construct_translated_point_2 construct_translated_point_2_object() const { return {}; }
};

} // namespace imgmesh::planar_detail

// As for Epick: locate walks with inexact orientations first (structural
// filtering). Without it the walks, and so the order of the triangulation's
// faces and vertices, differ from Epick's: another mesh.
namespace CGAL {
template <> struct Triangulation_structural_filtering_traits<imgmesh::planar_detail::RefinementKernel> {
  typedef Tag_true Use_structural_filtering_tag;
};
} // namespace CGAL

namespace imgmesh {
namespace {

using K = planar_detail::RefinementKernel;

struct VertexInfo {
  int input = -1;  // input vertex id, or -1 for a Steiner point
  int id = -1;     // output id
  int marker = 0;
  bool near_small_angle = false;
  int visit = -1;  // last apex whose disc walk reached this vertex
};
struct FaceInfo {
  double attribute = 0;
  int region = -1;  // last regional point that reached this face
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K, CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K, CGAL::Delaunay_mesh_face_base_2<K>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Crossing segments are bad input, not something to split silently.
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_tag>;
using Vertex_handle = CDT::Vertex_handle;
using Face_handle = CDT::Face_handle;

// CGAL's shape + edge-length criteria, plus an area bound (Triangle's -a).
class QualityCriteria : public CGAL::Delaunay_mesh_size_criteria_2<CDT> {
public:
  using Base = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
  QualityCriteria(double B, double edge, double area) : Base(B, edge), max_area_(area) {}

  class Is_bad : public Base::Is_bad {
  public:
    Is_bad(double B, double edge, double area, const K& t) : Base::Is_bad(B, edge, t), max_area_(area) {}
    using Base::Is_bad::operator();
    CGAL::Mesh_2::Face_badness operator()(const Face_handle& fh, Quality& q) const {
      const CGAL::Mesh_2::Face_badness r = Base::Is_bad::operator()(fh, q);
      if (r == CGAL::Mesh_2::IMPERATIVELY_BAD || max_area_ <= 0) return r;
      const double area = std::abs(CGAL::to_double(
          CGAL::area(fh->vertex(0)->point(), fh->vertex(1)->point(), fh->vertex(2)->point())));
      if (area > max_area_) {
        q.second = std::max(q.second, area / max_area_);
        q.first = 1;
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      return r;
    }

  private:
    double max_area_;
  };
  Is_bad is_bad_object() const { return Is_bad(this->bound(), this->size_bound(), max_area_, this->traits); }

private:
  double max_area_;
};

double angle_deg(const K::Point_2& a, const K::Point_2& b, const K::Point_2& c) {
  // Angle at a in triangle abc.
  const double ux = b.x() - a.x(), uy = b.y() - a.y(), vx = c.x() - a.x(), vy = c.y() - a.y();
  return std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / M_PI;
}

using Mesher = CGAL::Delaunay_mesher_2<CDT, QualityCriteria>;

// What the stages share: the input, the triangulation being refined, the
// vertex of each input point, the hole seeds and the result.
struct Triangulation {
  Triangulation(const PlanarMesh& in, const TriangulateOptions& opt) : in(in), opt(opt) {}
  const PlanarMesh& in;
  const TriangulateOptions& opt;
  CDT cdt;
  std::vector<Vertex_handle> vh;  // per input point (duplicates share one)
  std::vector<K::Point_2> seeds;  // the holes
  TriangulateResult res;
};

std::string segment_name(const PlanarMesh& in, std::size_t s) {
  return "segment " + std::to_string(s + in.first_index);
}

void check_input(const PlanarMesh& in, const TriangulateOptions& opt) {
  if (in.points.size() < 3) throw Error("a PSLG needs at least 3 vertices");
  if (!(opt.min_angle >= 0 && opt.min_angle <= 34))
    throw UsageError("the minimum angle must be between 0 and 34 degrees (refinement may not end beyond)");
  // The readers hold the range; a PSLG made otherwise (img2poly's) too.
  for (const auto& p : in.points)
    for (double c : p)
      if (!valid_coordinate(c)) throw Error("a vertex's " + coordinate_error(c));
  check_extent(in.points, "");
}

// The input points, then its segments as constraints.
void insert_input(Triangulation& t) {
  const PlanarMesh& in = t.in;
  t.vh.resize(in.points.size());
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    t.vh[i] = t.cdt.insert(K::Point_2(in.points[i][0], in.points[i][1]));
    // Duplicate points collapse onto one vertex; the first id wins.
    if (t.vh[i]->info().input < 0) {
      t.vh[i]->info().input = int(i);
      if (!in.point_markers.empty()) t.vh[i]->info().marker = in.point_markers[i];
    }
  }
  t.res.input_vertices = t.cdt.number_of_vertices();
  t.res.input_segments = in.segments.size();
  t.res.holes = in.holes.size();
  t.res.regions = in.regions.size();
  t.res.min_angle_bound = t.opt.min_angle;
  for (std::size_t s = 0; s < in.segments.size(); ++s) {
    const auto [a, b] = in.segments[s];
    if (t.vh[a] == t.vh[b]) throw Error(segment_name(in, s) + " has zero length");
    try {
      t.cdt.insert_constraint(t.vh[a], t.vh[b]);
    } catch (const CDT::Intersection_of_constraints_exception&) {
      throw Error(segment_name(in, s) + " (" + std::to_string(a + in.first_index) + ", " +
                  std::to_string(b + in.first_index) +
                  ") crosses or overlaps another segment (the PSLG must not self-intersect)");
    }
  }
}

// The domain: the faces not reached from a hole's point.
void mark_holes(Triangulation& t) {
  for (const auto& h : t.in.holes) t.seeds.emplace_back(h[0], h[1]);
  Mesher::mark_facets(t.cdt, t.seeds.begin(), t.seeds.end(), false);
}

// A size bound that asks for more vertices than --max-vertices is refused at
// once, not after minutes of refinement (a triangle of the bound is at most
// max_area, or an equilateral one of side max_edge; vertices are about half
// the triangles).
void check_size_bound(const Triangulation& t) {
  const TriangulateOptions& opt = t.opt;
  if (!(opt.max_area > 0 || opt.max_edge > 0)) return;
  double area = 0;
  for (auto f = t.cdt.finite_faces_begin(); f != t.cdt.finite_faces_end(); ++f)
    if (f->is_in_domain()) area += std::abs(CGAL::area(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()));
  const double tri = opt.max_area > 0 ? opt.max_area : std::sqrt(3.0) / 4 * opt.max_edge * opt.max_edge;
  const double need = area / tri / 2;
  if (need > double(opt.max_vertices)) {
    std::ostringstream msg;
    msg << "the size bound asks for about " << std::setprecision(2) << need << " vertices, over --max-vertices ("
        << opt.max_vertices << ")";
    throw UsageError(msg.str());
  }
}

// The lattice's points in the domain, before refinement (none when it would
// be too large and is optional).
void insert_lattice(Triangulation& t) {
  const TriangulateOptions& opt = t.opt;
  Face_handle hint;
  const planar_detail::InDomain in_domain = [&](const Point2& p) {
    hint = t.cdt.locate(K::Point_2(p[0], p[1]), hint);
    return !t.cdt.is_infinite(hint) && hint->is_in_domain();
  };
  std::vector<Point2> lattice;
  try {
    lattice = opt.square_lattice ? planar_detail::square_lattice(t.in, opt.lattice, opt.grading, opt.max_side,
                                                                 opt.narrow, opt.max_vertices, in_domain)
                                 : planar_detail::equilateral_lattice(t.in, opt.lattice, opt.max_vertices, in_domain);
  } catch (const UsageError&) {
    if (!opt.lattice_optional) throw;
  }
  std::vector<K::Point_2> points;
  points.reserve(lattice.size());
  for (const auto& p : lattice) points.emplace_back(p[0], p[1]);
  t.cdt.insert(points.begin(), points.end());
  t.res.lattice_points = t.cdt.number_of_vertices() - t.res.input_vertices;
}

// Delaunay refinement to the angle and size bounds, one vertex a step.
void refine(Triangulation& t) {
  const TriangulateOptions& opt = t.opt;
  const double B = opt.min_angle > 0 ? std::pow(std::sin(opt.min_angle * M_PI / 180), 2) : 0;
  QualityCriteria criteria(B, opt.max_edge > 0 ? opt.max_edge : 0, opt.max_area);
  Mesher mesher(t.cdt, criteria);
  mesher.set_seeds(t.seeds.begin(), t.seeds.end(), false);
  mesher.init();
  if (!(opt.min_angle > 0 || opt.max_area > 0 || opt.max_edge > 0)) return;
  std::size_t steps = 0, idle = 0, vertices = t.cdt.number_of_vertices();
  while (!mesher.is_refinement_done()) {
    mesher.step_by_step_refine_mesh();
    // Every step: a small --max-vertices must hold too (a step adds one vertex).
    if (t.cdt.number_of_vertices() > opt.max_vertices) {
      t.res.limit_reached = true;
      break;
    }
    // A step adds no vertex where it drops an element no longer to refine
    // (at most one a queued face or edge: fewer than 8 a vertex; on the
    // bundled images at most 1 step in a row). Where features are below
    // double precision (a rectangle 1 by 1e-300) the mesher went on for
    // ever without placing a vertex (issue 35).
    if (t.cdt.number_of_vertices() != vertices) {
      vertices = t.cdt.number_of_vertices();
      idle = 0;
    } else if (++idle > 8 * vertices + 1024) {
      throw Error("refinement went beyond double precision: the PSLG has features too small for the size of their "
                  "coordinates (no vertex placed in " + std::to_string(idle) + " steps)");
    }
    if (++steps % 4096 == 0 && opt.progress) opt.progress(t.cdt.number_of_vertices());
  }
}

// Regions: flood fill across unconstrained edges, in the order given (a
// later regional point overrides an earlier one, as in Triangle).
void fill_regions(Triangulation& t) {
  for (std::size_t r = 0; r < t.in.regions.size(); ++r) {
    const auto& reg = t.in.regions[r];
    Face_handle f = t.cdt.locate(K::Point_2(reg.point[0], reg.point[1]));
    if (f == Face_handle() || t.cdt.is_infinite(f) || !f->is_in_domain()) {
      ++t.res.regions_outside_domain;
      continue;
    }
    std::vector<Face_handle> stack{f};
    f->info().region = int(r);
    while (!stack.empty()) {
      Face_handle g = stack.back();
      stack.pop_back();
      g->info().attribute = reg.attribute;
      for (int i = 0; i < 3; ++i) {
        if (g->is_constrained(i)) continue;
        Face_handle n = g->neighbor(i);
        if (t.cdt.is_infinite(n) || !n->is_in_domain() || n->info().region == int(r)) continue;
        n->info().region = int(r);
        stack.push_back(n);
      }
    }
  }
}

// The domain's triangles with their attributes, and their vertices.
void output_triangles(Triangulation& t) {
  PlanarMesh& m = t.res.mesh;
  m.first_index = t.in.first_index;
  for (auto f = t.cdt.finite_faces_begin(); f != t.cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    std::vector<int> tri(3);
    for (int i = 0; i < 3; ++i) {
      Vertex_handle v = f->vertex(i);
      if (v->info().id < 0) {
        v->info().id = int(m.points.size());
        m.points.push_back({v->point().x(), v->point().y()});
      }
      tri[i] = v->info().id;
    }
    m.elements.push_back(std::move(tri));
    m.element_attributes.push_back({f->info().attribute});
  }
  if (m.elements.empty()) throw Error("the segments enclose no area to triangulate");
}

// Input segment s is now a chain of constrained edges; walk it from a to b
// (the split points are midpoints, inexact, so "on the segment" is a
// tolerance test), giving its subsegments and their vertices its marker.
void output_subsegments(Triangulation& t, std::size_t s) {
  const PlanarMesh& in = t.in;
  PlanarMesh& m = t.res.mesh;
  const Vertex_handle va = t.vh[in.segments[s][0]], vb = t.vh[in.segments[s][1]];
  const int marker = in.segment_markers.empty() ? 0 : in.segment_markers[s];
  const double ax = va->point().x(), ay = va->point().y();
  const double dx = vb->point().x() - ax, dy = vb->point().y() - ay;
  const double len2 = dx * dx + dy * dy;
  // The split points are rounded midpoints: off the line by a few units in
  // the last place of the coordinates, which a short segment among large
  // coordinates (1e-12 long at 0.5) makes more than 1e-6 of its length.
  const double scale = std::max({std::abs(ax), std::abs(ay), std::abs(vb->point().x()), std::abs(vb->point().y())});
  const double tolerance = 1e-6 * std::sqrt(len2) + 1e-13 * scale;
  Vertex_handle cur = va;
  double tcur = 0;
  for (std::size_t guard = 0; cur != vb; ++guard) {
    Vertex_handle best;
    double best_d = 1e300, best_t = 0;
    auto circ = t.cdt.incident_edges(cur), end = circ;
    do {
      if (t.cdt.is_infinite(*circ) || !t.cdt.is_constrained(*circ)) continue;
      const Face_handle f = circ->first;
      const int i = circ->second;
      Vertex_handle w = f->vertex(CDT::cw(i)) == cur ? f->vertex(CDT::ccw(i)) : f->vertex(CDT::cw(i));
      const double px = w->point().x() - ax, py = w->point().y() - ay;
      const double u = (px * dx + py * dy) / len2;
      const double d = std::abs(px * dy - py * dx) / std::sqrt(len2);  // distance to the line
      if (u > tcur && u <= 1 + 1e-9 && d < best_d) {
        best = w;
        best_d = d;
        best_t = u;
      }
    } while (++circ != end);
    if (best == Vertex_handle() || best_d > tolerance || guard > t.cdt.number_of_vertices())
      throw Error(segment_name(in, s) + " is not a chain of mesh edges: refinement went beyond double precision "
                  "along it (features too small for the size of their coordinates)");
    if (cur->info().id >= 0 && best->info().id >= 0) {
      m.segments.push_back({cur->info().id, best->info().id});
      m.segment_markers.push_back(marker);
    }
    if (best != vb && best->info().marker == 0) best->info().marker = marker;
    cur = best;
    tcur = best_t;
  }
}

// Input vertices keep their own marker, or take one of their segments'.
void output_point_markers(Triangulation& t) {
  const PlanarMesh& in = t.in;
  for (std::size_t s = 0; s < in.segments.size(); ++s)
    for (int e : {0, 1}) {
      auto v = t.vh[in.segments[s][e]];
      if (v->info().marker == 0 && !in.segment_markers.empty()) v->info().marker = in.segment_markers[s];
    }
  PlanarMesh& m = t.res.mesh;
  m.point_markers.assign(m.points.size(), 0);
  for (auto v = t.cdt.finite_vertices_begin(); v != t.cdt.finite_vertices_end(); ++v)
    if (v->info().id >= 0) m.point_markers[v->info().id] = v->info().marker;
}

// "Near a small input angle": within the disc around the apex whose radius
// is the shorter of the two segments, where CGAL's clusters (like Triangle)
// give up the bound. Marked by a walk over the mesh from the apex.
void mark_near_small_angles(Triangulation& t, const std::vector<std::pair<std::size_t, double>>& apexes) {
  for (std::size_t k = 0; k < apexes.size(); ++k) {
    const auto [v, r] = apexes[k];
    const Vertex_handle apex = t.vh[v];
    const K::Point_2 c = apex->point();
    std::vector<Vertex_handle> stack{apex};
    apex->info().near_small_angle = true;
    apex->info().visit = int(k);
    while (!stack.empty()) {
      Vertex_handle u = stack.back();
      stack.pop_back();
      auto circ = t.cdt.incident_vertices(u), end = circ;
      do {
        if (t.cdt.is_infinite(circ) || circ->info().visit == int(k)) continue;
        if (std::sqrt(CGAL::to_double(CGAL::squared_distance(circ->point(), c))) > r * (1 + 1e-9)) continue;
        circ->info().visit = int(k);
        circ->info().near_small_angle = true;
        stack.push_back(circ);
      } while (++circ != end);
    }
  }
}

// The quality report: Steiner points and smallest angles, near small input
// angles and away from them.
void report_quality(Triangulation& t) {
  TriangulateResult& res = t.res;
  res.steiner_points = t.cdt.number_of_vertices() - res.input_vertices;
  res.min_angle = 180;
  res.min_angle_away_from_small_input_angles = 180;
  for (auto f = t.cdt.finite_faces_begin(); f != t.cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    const auto &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
    const double mn = std::min({angle_deg(a, b, c), angle_deg(b, c, a), angle_deg(c, a, b)});
    res.min_angle = std::min(res.min_angle, mn);
    bool near = false;
    for (int i = 0; i < 3; ++i) near |= f->vertex(i)->info().near_small_angle;
    if (!near)
      res.min_angle_away_from_small_input_angles = std::min(res.min_angle_away_from_small_input_angles, mn);
    else if (mn < t.opt.min_angle)
      ++res.below_bound_near_small_angles;
  }
}

} // namespace

namespace planar_detail {

InputAngles input_angles(const PlanarMesh& in) {
  InputAngles r;
  std::vector<std::vector<std::size_t>> at(in.points.size());
  for (std::size_t s = 0; s < in.segments.size(); ++s) {
    at[in.segments[s][0]].push_back(s);
    at[in.segments[s][1]].push_back(s);
  }
  auto seg_length = [&](std::size_t s) {
    const auto& a = in.points[in.segments[s][0]];
    const auto& b = in.points[in.segments[s][1]];
    return std::hypot(b[0] - a[0], b[1] - a[1]);
  };
  for (std::size_t v = 0; v < in.points.size(); ++v) {
    if (at[v].size() < 2) continue;
    std::vector<std::pair<double, std::size_t>> dirs;
    for (std::size_t s : at[v]) {
      const int w = in.segments[s][0] == int(v) ? in.segments[s][1] : in.segments[s][0];
      dirs.push_back({std::atan2(in.points[w][1] - in.points[v][1], in.points[w][0] - in.points[v][0]), s});
    }
    std::sort(dirs.begin(), dirs.end());
    bool small = false;
    for (std::size_t k = 0; k < dirs.size(); ++k) {
      const auto& d0 = dirs[k];
      const auto& d1 = dirs[(k + 1) % dirs.size()];
      double a = (d1.first - d0.first) * 180 / M_PI;
      if (k + 1 == dirs.size()) a += 360;
      r.smallest = std::min(r.smallest, a);
      if (a < 60) {
        small = true;
        r.apexes.push_back({v, std::min(seg_length(d0.second), seg_length(d1.second))});
      }
    }
    if (small) ++r.small_vertices;
  }
  return r;
}

} // namespace planar_detail

namespace {
TriangulateResult triangulate_checked(const PlanarMesh& in, const TriangulateOptions& opt) {
  Triangulation t(in, opt);
  insert_input(t);
  const planar_detail::InputAngles angles = planar_detail::input_angles(in);
  t.res.smallest_input_angle = angles.smallest;
  t.res.small_input_angles = angles.small_vertices;
  mark_holes(t);
  check_size_bound(t);
  if (opt.lattice > 0) insert_lattice(t);
  refine(t);
  fill_regions(t);
  output_triangles(t);
  for (std::size_t s = 0; s < in.segments.size(); ++s) output_subsegments(t, s);
  output_point_markers(t);
  t.res.mesh.holes = in.holes;
  mark_near_small_angles(t, angles.apexes);
  report_quality(t);
  return std::move(t.res);
}
} // namespace

TriangulateResult triangulate_pslg(const PlanarMesh& in, const TriangulateOptions& opt) {
  check_input(in, opt);
  try {
    return triangulate_checked(in, opt);
  } catch (const CGAL::Failure_exception& e) {
    throw Error("refinement went beyond double precision: the PSLG has features too small for the size of their "
                "coordinates (CGAL's check '" + e.expression() + "' failed)");
  }
}

double default_lattice_side(const PlanarMesh& in) {
  std::vector<double> lengths;
  for (const auto& s : in.segments) {
    const Point2 &a = in.points[std::size_t(s[0])], &b = in.points[std::size_t(s[1])];
    const double l = std::hypot(b[0] - a[0], b[1] - a[1]);
    if (l > 0 && std::isfinite(l)) lengths.push_back(l);
  }
  if (lengths.empty() || in.points.empty()) return 0;
  std::sort(lengths.begin(), lengths.end());
  // Half the median, at least twice the 10th percentile: a lattice cell
  // then meets about two segments of its curve, and two pixels of a
  // staircase (the 10th percentile alone gave 2.5-6.6 times main's quads
  // through the default chain on the bundled images, for 0-1.4 degrees
  // more mean mu); not finer than 2048 x 2048 nodes.
  const auto box = planar_detail::bounding_box(in);
  return std::max({lengths[lengths.size() / 2] / 2, 2 * lengths[lengths.size() / 10],
                   std::max(box[2] - box[0], box[3] - box[1]) / 2048});
}

double default_max_side(const PlanarMesh& in) {
  if (in.points.empty()) return 0;
  const auto box = planar_detail::bounding_box(in);
  return std::min(box[2] - box[0], box[3] - box[1]) / 10;
}

Json TriangulateResult::to_json() const {
  Json j = Json::object();
  j["input_vertices"] = input_vertices;
  j["input_segments"] = input_segments;
  j["holes"] = holes;
  j["regions"] = regions;
  j["vertices"] = mesh.points.size();
  j["triangles"] = mesh.elements.size();
  j["steiner_points"] = steiner_points;
  j["lattice_points"] = lattice_points;
  j["subsegments"] = mesh.segments.size();
  j["min_angle_bound"] = min_angle_bound;
  j["min_angle"] = min_angle;
  j["min_angle_away_from_small_input_angles"] = min_angle_away_from_small_input_angles;
  j["smallest_input_angle"] = smallest_input_angle;
  j["small_input_angles"] = small_input_angles;
  j["below_bound_near_small_input_angles"] = below_bound_near_small_angles;
  j["regions_outside_domain"] = regions_outside_domain;
  j["limit_reached"] = limit_reached;
  return j;
}

std::string TriangulateResult::failed_guarantee() const {
  if (limit_reached) return "refinement stopped at the vertex limit (--max-vertices): the angle/size bounds are not met everywhere";
  if (min_angle_bound > 0 && min_angle_away_from_small_input_angles < min_angle_bound - 1e-6)
    return "smallest angle away from small input angles is " + std::to_string(min_angle_away_from_small_input_angles) +
           " degrees, below the bound";
  return "";
}

} // namespace imgmesh
