// Polyline_simplification_2 over a constrained triangulation with a
// constraint hierarchy. Its removal test (is_removable) refuses to remove a
// vertex when any vertex of the triangulation lies in or on the triangle the
// removal sweeps, so curves never cross, and points inserted as plain
// vertices (the obstacles: img2poly's regional points) never change side.
// The cost is the largest distance from the original points to the new
// segment and the stop threshold E^2, so every simplified segment is within
// E of its original stretch; the stretch is then within E of the segment too
// (its projection onto the segment covers it), which bounds the Hausdorff
// distance both ways.
#include "planar/curve_simplification.hpp"

#include "util/error.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyline_simplification_2/Squared_distance_cost.h>
#include <CGAL/Polyline_simplification_2/Stop_above_cost_threshold.h>
#include <CGAL/Polyline_simplification_2/simplify.h>

#include <cmath>

namespace imgmesh {
namespace {
namespace PS = CGAL::Polyline_simplification_2;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = PS::Vertex_base_2<K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using TDS = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, TDS, CGAL::Exact_predicates_tag>;
using CT = CGAL::Constrained_triangulation_plus_2<CDT>;

double segment_distance(const K::Point_2& a, const K::Point_2& b, const K::Point_2& p) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double px = p.x() - a.x(), py = p.y() - a.y();
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? (px * dx + py * dy) / l2 : 0;
  t = std::max(0.0, std::min(1.0, t));
  return std::hypot(px - t * dx, py - t * dy);
}
} // namespace

SimplifyReport simplify_polylines(PolylineSet& set, const std::vector<Point2>& obstacles, double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) throw Error("the tolerance must be a finite number >= 0");
  CT ct;
  {
    std::vector<K::Point_2> pts;
    pts.reserve(obstacles.size());
    for (const auto& p : obstacles) pts.emplace_back(p[0], p[1]);
    ct.insert(pts.begin(), pts.end());  // spatially sorted bulk insertion
  }
  std::vector<CT::Constraint_id> ids;
  ids.reserve(set.lines.size());
  for (std::size_t i = 0; i < set.lines.size(); ++i) {
    std::vector<K::Point_2> pts;
    pts.reserve(set.lines[i].size());
    for (const auto& p : set.lines[i]) pts.emplace_back(p[0], p[1]);
    ids.push_back(ct.insert_constraint(pts.begin(), pts.end(), set.closed[i] != 0));
  }
  SimplifyReport rep;
  rep.removed = PS::simplify(ct, PS::Squared_distance_cost(), PS::Stop_above_cost_threshold(tolerance * tolerance),
                             false);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    std::vector<Point2> out;
    auto b = ct.vertices_in_constraint_begin(ids[i]), e = ct.vertices_in_constraint_end(ids[i]);
    for (auto v = b; v != e; ++v) {
      out.push_back({(*v)->point().x(), (*v)->point().y()});
      auto next = std::next(v);
      if (next == e) break;
      // The original points between two kept vertices, against their segment.
      CT::Points_in_constraint_iterator pp(v), rr(next);
      for (++pp; pp != rr; ++pp)
        rep.hausdorff = std::max(rep.hausdorff, segment_distance((*v)->point(), (*next)->point(), *pp));
    }
    if (set.closed[i] && out.size() > 1 && out.front() == out.back()) out.pop_back();
    set.lines[i] = std::move(out);
  }
  return rep;
}

} // namespace imgmesh
