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
#include "util/hash.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyline_simplification_2/Squared_distance_cost.h>
#include <CGAL/Polyline_simplification_2/Stop_above_cost_threshold.h>
#include <CGAL/Polyline_simplification_2/simplify.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace imgmesh {
namespace {
namespace PS = CGAL::Polyline_simplification_2;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = PS::Vertex_base_2<K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using TDS = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, TDS, CGAL::Exact_predicates_tag>;
using CT = CGAL::Constrained_triangulation_plus_2<CDT>;

// Squared_distance_cost, but a removal that would make an angle below
// `min_angle` between the new segment and another constrained edge at either
// end is not offered (cost undefined); it is reconsidered whenever a
// neighbour goes. Thin spikes keep their square ends instead of collapsing
// into slivers that force tiny triangles downstream.
//
// Pixel staircases give many equal costs, and the queue breaks ties by the
// order it was filled in; tie (>= 0, far below the threshold) times a hash of
// the vertex's coordinates in [0, 1) is added so that no two costs are
// equal. Costs only grow, so the distance bound still holds.
struct AngleAwareCost {
  double cos_max;  // cos(min_angle)
  double tie;
  static double hash01(const K::Point_2& p) {
    std::uint64_t bx, by;
    const double x = p.x(), y = p.y();
    std::memcpy(&bx, &x, 8);
    std::memcpy(&by, &y, 8);
    std::uint64_t h = bx * 0x9E3779B97F4A7C15ull ^ (by + 0x632BE59BD9B4E019ull + (bx << 6) + (bx >> 2));
    return unit01(mix64(h));
  }
  bool ok_at(const CT& ct, CT::Vertex_handle a, CT::Vertex_handle skip, CT::Vertex_handle b) const {
    const double bx = b->point().x() - a->point().x(), by = b->point().y() - a->point().y();
    const double lb = std::hypot(bx, by);
    auto e = ct.incident_edges(a), end = e;
    if (e == nullptr) return true;
    do {
      if (ct.is_infinite(*e) || !ct.is_constrained(*e)) continue;
      const auto f = e->first;
      const int i = e->second;
      const CT::Vertex_handle x = f->vertex(CT::cw(i)) == a ? f->vertex(CT::ccw(i)) : f->vertex(CT::cw(i));
      if (x == skip || x == b) continue;
      const double xx = x->point().x() - a->point().x(), xy = x->point().y() - a->point().y();
      if ((bx * xx + by * xy) > cos_max * lb * std::hypot(xx, xy)) return false;
    } while (++e != end);
    return true;
  }
  boost::optional<double> operator()(const CT& ct, CT::Vertices_in_constraint_iterator v) const {
    const boost::optional<double> d = PS::Squared_distance_cost()(ct, v);
    if (!d) return d;
    auto pv = v, nv = v;  // CGAL's constraint iterators are not std::prev-able
    --pv;
    ++nv;
    const CT::Vertex_handle u = *pv, w = *nv;
    if (!ok_at(ct, u, *v, w) || !ok_at(ct, w, *v, u)) return boost::none;
    return *d + tie * hash01((*v)->point());
  }
};

double segment_distance(const K::Point_2& a, const K::Point_2& b, const K::Point_2& p) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double px = p.x() - a.x(), py = p.y() - a.y();
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? (px * dx + py * dy) / l2 : 0;
  t = std::max(0.0, std::min(1.0, t));
  return std::hypot(px - t * dx, py - t * dy);
}
} // namespace

SimplifyReport simplify_polylines(PolylineSet& set, const std::vector<Point2>& obstacles, double tolerance,
                                  double min_angle) {
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
  const double cos_max = std::cos(std::clamp(min_angle, 0.0, 90.0) * M_PI / 180);
  // CGAL keeps its constraints in a set ordered by address, so its queue
  // is filled in heap-layout order; AngleAwareCost's tie-break makes every
  // cost distinct, so the order of removals (and the output) does not
  // depend on it. (One PS::simplify call per constraint would too, but each
  // call scans the whole triangulation: quadratic on a grey image.)
  rep.removed = PS::simplify(ct, AngleAwareCost{cos_max, tolerance * tolerance * 1e-9},
                             PS::Stop_above_cost_threshold(tolerance * tolerance), false);
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
