// poly2tri's engine: CGAL constrained Delaunay triangulation + Delaunay
// refinement, then Triangle's conventions on the result (region attributes,
// segment markers carried to the subsegments and their vertices).
#include "planar/triangulate.hpp"

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
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace imgmesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
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

double distance_to_segment(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0;
  return std::hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
}

// The bounding box of the input points.
std::array<double, 4> bounding_box(const PlanarMesh& in) {
  double x0 = in.points[0][0], y0 = in.points[0][1], x1 = x0, y1 = y0;
  for (const auto& p : in.points) {
    x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]);
    y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
  }
  return {x0, y0, x1, y1};
}

// The points of an equilateral-triangle lattice of side h (rows along x,
// from the corner of the input's bounding box) that lie in a domain face of
// cdt and at least h/2 from every input segment and vertex.
std::vector<K::Point_2> lattice_in_domain(const PlanarMesh& in, const CDT& cdt, double h, std::size_t limit) {
  const auto box = bounding_box(in);
  const double x0 = box[0], y0 = box[1], x1 = box[2], y1 = box[3];
  const double row = h * std::sqrt(3.0) / 2;
  const double columns = std::floor((x1 - x0) / h) + 1, rows = std::floor((y1 - y0) / row) + 1;
  if (columns * rows > double(limit))
    throw UsageError("the lattice side is too small: its points alone exceed --max-vertices");
  // Buckets of side h: a segment (a vertex is one of length 0) goes into the
  // 3 x 3 cells around samples taken every h/2 along it, which covers every
  // cell with a point within h/2 of it.
  std::unordered_map<long long, std::vector<std::array<int, 2>>> buckets;
  const auto cell = [&](double x, double y) {
    return (long long)std::floor((y - y0) / h) * (1LL << 31) + (long long)std::floor((x - x0) / h);
  };
  auto add = [&](std::array<int, 2> s) {
    const Point2 &a = in.points[s[0]], &b = in.points[s[1]];
    const int samples = int(std::ceil(2 * std::hypot(b[0] - a[0], b[1] - a[1]) / h));
    for (int k = 0; k <= samples; ++k) {
      const double t = samples ? double(k) / samples : 0;
      const double x = a[0] + t * (b[0] - a[0]), y = a[1] + t * (b[1] - a[1]);
      for (int dy : {-1, 0, 1})
        for (int dx : {-1, 0, 1}) {
          auto& bucket = buckets[cell(x + dx * h, y + dy * h)];
          if (bucket.empty() || bucket.back() != s) bucket.push_back(s);
        }
    }
  };
  for (const auto& s : in.segments) add(s);
  for (int v = 0; v < int(in.points.size()); ++v) add({v, v});

  std::vector<K::Point_2> out;
  Face_handle hint;
  for (int j = 0; j < int(rows); ++j)
    for (int i = 0; i < int(columns); ++i) {
      const Point2 p{x0 + h / 2 + (j % 2 ? h / 2 : 0) + i * h, y0 + row / 2 + j * row};
      if (p[0] >= x1 || p[1] >= y1) continue;
      const auto b = buckets.find(cell(p[0], p[1]));
      if (b != buckets.end() &&
          std::any_of(b->second.begin(), b->second.end(), [&](const std::array<int, 2>& s) {
            return distance_to_segment(p, in.points[s[0]], in.points[s[1]]) < h / 2;
          }))
        continue;
      const K::Point_2 q(p[0], p[1]);
      hint = cdt.locate(q, hint);
      if (!cdt.is_infinite(hint) && hint->is_in_domain()) out.push_back(q);
    }
  return out;
}

// The points of the square lattice of side h (nodes at the cell centres of
// the input's bounding box) that lie in a domain face of cdt, graded by a
// size field: each segment asks for its own length (clamped to [h,
// max_side]) along it, growing by `grading` per unit of distance away from
// it (the smallest ask wins: a grading-Lipschitz field). A node whose size
// is s stays only if it is a node of the lattice of side 2^k h, k the
// largest with 2^k h <= s and <= max_side, and lies at least 2^k h / 2 from
// every segment and vertex (Delaunay refinement fills that band). So the
// lattice follows the curves' own sampling (a long side of the image
// rectangle asks for coarse cells, a finely sampled curve for fine ones).
// With `narrow` (and grading > 0) the nodes are those of the lattice of
// side h / 2 too, and where the domain is narrower than the field asks for
// (a node between two sides of it, 2 d across, d its distance to the
// nearer) the field is at most that width: the lattice then fits a row of
// nodes wherever the finer side does, where it left the space between
// close curves to Delaunay refinement (on 128 x 128 label slices through
// the default chain: mean Joe's mu 27.8-27.9 -> 30.1-30.5, 1.6 x quads).
// The distances come from a vector distance transform on the nodes
// (Danielsson: each node takes the nearest of the segments its neighbours
// are nearest to, seeded exactly within a cell of every segment), the size
// field from the same sweeps; grading 0: the uniform lattice of side h.
std::vector<K::Point_2> square_lattice_in_domain(const PlanarMesh& in, const CDT& cdt, double h, double grading,
                                                 double max_side, bool narrow, std::size_t limit) {
  const auto box = bounding_box(in);
  const double x0 = box[0], y0 = box[1], x1 = box[2], y1 = box[3];
  // The nodes: x0 + h / 2 + i hf (those of even i and j make the lattice of
  // side h). The half side costs four times the nodes: not past 2048 x 2048
  // of them (default_lattice_side's own bound), where it is left out.
  const auto count = [&](double step) {
    return (std::floor((x1 - x0 - h / 2) / step) + 2) * (std::floor((y1 - y0 - h / 2) / step) + 2);
  };
  const double hf = narrow && grading > 0 && count(h / 2) <= 2048.0 * 2048 ? h / 2 : h;
  const double columns = std::floor((x1 - x0 - h / 2) / hf) + 2, rows = std::floor((y1 - y0 - h / 2) / hf) + 2;
  // A uniform lattice has about as many points as nodes; a graded one is
  // counted once made. Past 3e7 nodes the distance transform alone would
  // take gigabytes.
  if ((grading <= 0 && columns * rows > double(limit)) || columns * rows > 3e7)
    throw UsageError("the lattice side is too small: its points alone exceed --max-vertices");
  const long W = long(columns), H = long(rows);
  const std::size_t n_nodes = std::size_t(W * H);
  std::vector<int> nearest(n_nodes, -1);  // segment id; vertices come after the segments
  std::vector<double> dist(n_nodes, std::numeric_limits<double>::infinity());
  std::vector<double> size(n_nodes, grading > 0 ? std::numeric_limits<double>::infinity() : h);
  const std::size_t ns = in.segments.size();
  const auto ends = [&](int s) -> std::array<int, 2> {
    return std::size_t(s) < ns ? in.segments[std::size_t(s)] : std::array<int, 2>{s - int(ns), s - int(ns)};
  };
  const double coarsest = max_side > h ? max_side : h;
  std::vector<double> ask(ns + in.points.size(), h);  // the size each segment asks for along it
  for (std::size_t s = 0; s < ns; ++s) {
    const Point2 &a = in.points[std::size_t(in.segments[s][0])], &b = in.points[std::size_t(in.segments[s][1])];
    ask[s] = std::clamp(std::hypot(b[0] - a[0], b[1] - a[1]), h, coarsest);
  }
  const auto node = [&](long i, long j) { return Point2{x0 + h / 2 + double(i) * hf, y0 + h / 2 + double(j) * hf}; };
  const auto offer = [&](long i, long j, int s) {
    if (i < 0 || j < 0 || i >= W || j >= H) return;
    const auto e = ends(s);
    const double d = distance_to_segment(node(i, j), in.points[std::size_t(e[0])], in.points[std::size_t(e[1])]);
    const std::size_t n = std::size_t(j * W + i);
    if (d < dist[n]) { dist[n] = d; nearest[n] = s; }
    if (grading > 0) size[n] = std::min(size[n], ask[std::size_t(s)] + grading * d);
  };
  // Seeds: the nodes of the 4 x 4 cells around samples every hf/2 along each
  // segment (every node within hf of it).
  for (int s = 0; s < int(ns + in.points.size()); ++s) {
    const auto e = ends(s);
    const Point2 &a = in.points[std::size_t(e[0])], &b = in.points[std::size_t(e[1])];
    const int samples = int(std::ceil(2 * std::hypot(b[0] - a[0], b[1] - a[1]) / hf));
    for (int k = 0; k <= samples; ++k) {
      const double t = samples ? double(k) / samples : 0;
      const long i = long(std::floor((a[0] + t * (b[0] - a[0]) - x0 - h / 2) / hf));
      const long j = long(std::floor((a[1] + t * (b[1] - a[1]) - y0 - h / 2) / hf));
      for (long dj = -1; dj <= 2; ++dj)
        for (long di = -1; di <= 2; ++di) offer(i + di, j + dj, s);
    }
  }
  // Forward then backward raster sweeps over the 8 neighbours: their nearest
  // segments, and their sizes plus the grading times the step.
  const auto from = [&](long i, long j, long a, long b) {
    if (a < 0 || b < 0 || a >= W || b >= H) return;
    const std::size_t m = std::size_t(b * W + a);
    if (nearest[m] >= 0) offer(i, j, nearest[m]);
    const std::size_t n = std::size_t(j * W + i);
    size[n] = std::min(size[n], size[m] + grading * hf * std::hypot(double(a - i), double(b - j)));
  };
  const auto sweeps = [&](const auto& f) {
    for (int sweep = 0; sweep < 2; ++sweep) {
      for (long j = 0; j < H; ++j)
        for (long i = 0; i < W; ++i)
          for (const auto& d : {std::array<long, 2>{-1, 0}, {-1, -1}, {0, -1}, {1, -1}}) f(i, j, i + d[0], j + d[1]);
      for (long j = H - 1; j >= 0; --j)
        for (long i = W - 1; i >= 0; --i)
          for (const auto& d : {std::array<long, 2>{1, 0}, {1, 1}, {0, 1}, {-1, 1}}) f(i, j, i + d[0], j + d[1]);
    }
  };
  if (grading > 0) sweeps(from);
  if (hf < h) {
    // A node is between two sides of the domain when the directions to its
    // nearest points on its own nearest segment and on a neighbour's are
    // more than 120 degrees apart (the two sides of a convex corner of 60
    // degrees or more are not). There the size is at most 2 d, the width,
    // and the field grows from it by the grading as from a segment.
    std::vector<double> width(n_nodes, std::numeric_limits<double>::infinity());
    const auto towards = [&](const Point2& p, int s) {  // unit vector from p to its nearest point on s
      const auto e = ends(s);
      const Point2 &a = in.points[std::size_t(e[0])], &b = in.points[std::size_t(e[1])];
      const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
      const double t = len2 > 0 ? std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0;
      const double ux = a[0] + t * dx - p[0], uy = a[1] + t * dy - p[1], l = std::hypot(ux, uy);
      return l > 0 ? std::array<double, 2>{ux / l, uy / l} : std::array<double, 2>{0, 0};
    };
    for (long j = 0; j < H; ++j)
      for (long i = 0; i < W; ++i) {
        const std::size_t n = std::size_t(j * W + i);
        if (nearest[n] < 0 || !(dist[n] > 0)) continue;
        const Point2 p = node(i, j);
        const auto u = towards(p, nearest[n]);
        bool between = false;
        for (long b = std::max(0L, j - 1); b <= std::min(H - 1, j + 1) && !between; ++b)
          for (long a = std::max(0L, i - 1); a <= std::min(W - 1, i + 1) && !between; ++a) {
            const int s = nearest[std::size_t(b * W + a)];
            if (s < 0 || s == nearest[n]) continue;
            const auto v = towards(p, s);
            between = u[0] * v[0] + u[1] * v[1] < -0.5;
          }
        if (between) width[n] = std::max(hf, 2 * dist[n]);
      }
    sweeps([&](long i, long j, long a, long b) {
      if (a < 0 || b < 0 || a >= W || b >= H) return;
      const std::size_t n = std::size_t(j * W + i), m = std::size_t(b * W + a);
      width[n] = std::min(width[n], width[m] + grading * hf * std::hypot(double(a - i), double(b - j)));
    });
    for (std::size_t n = 0; n < n_nodes; ++n) size[n] = std::min(size[n], width[n]);
  }
  int top = 0;  // the coarsest level
  while (std::ldexp(hf, top + 1) <= coarsest * (1 + 1e-12)) ++top;
  std::vector<K::Point_2> out;
  Face_handle hint;
  for (long j = 0; j < H; ++j)
    for (long i = 0; i < W; ++i) {
      const Point2 p = node(i, j);
      const std::size_t n = std::size_t(j * W + i);
      if (p[0] >= x1 || p[1] >= y1) continue;
      int k = 0;
      while (k < top && std::ldexp(hf, k + 1) <= size[n]) ++k;
      if (i % (1L << k) != 0 || j % (1L << k) != 0 || dist[n] < std::ldexp(hf, k) / 2) continue;
      const K::Point_2 q(p[0], p[1]);
      hint = cdt.locate(q, hint);
      if (!cdt.is_infinite(hint) && hint->is_in_domain()) out.push_back(q);
    }
  if (out.size() > limit) throw UsageError("the lattice side is too small: its points alone exceed --max-vertices");
  return out;
}

} // namespace

TriangulateResult triangulate_pslg(const PlanarMesh& in, const TriangulateOptions& opt) {
  TriangulateResult res;
  if (in.points.size() < 3) throw Error("a PSLG needs at least 3 vertices");
  if (!(opt.min_angle >= 0 && opt.min_angle <= 34))
    throw UsageError("the minimum angle must be between 0 and 34 degrees (refinement may not end beyond)");
  for (const auto& p : in.points)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) throw Error("a vertex has a non-finite coordinate");

  CDT cdt;
  std::vector<Vertex_handle> vh(in.points.size());
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    vh[i] = cdt.insert(K::Point_2(in.points[i][0], in.points[i][1]));
    // Duplicate points collapse onto one vertex; the first id wins.
    if (vh[i]->info().input < 0) {
      vh[i]->info().input = int(i);
      if (!in.point_markers.empty()) vh[i]->info().marker = in.point_markers[i];
    }
  }
  res.input_vertices = cdt.number_of_vertices();
  res.input_segments = in.segments.size();
  res.holes = in.holes.size();
  res.regions = in.regions.size();
  res.min_angle_bound = opt.min_angle;
  for (std::size_t s = 0; s < in.segments.size(); ++s) {
    const auto [a, b] = in.segments[s];
    if (vh[a] == vh[b])
      throw Error("segment " + std::to_string(s + in.first_index) + " has zero length");
    try {
      cdt.insert_constraint(vh[a], vh[b]);
    } catch (const CDT::Intersection_of_constraints_exception&) {
      throw Error("segment " + std::to_string(s + in.first_index) + " (" + std::to_string(a + in.first_index) +
                  ", " + std::to_string(b + in.first_index) +
                  ") crosses or overlaps another segment (the PSLG must not self-intersect)");
    }
  }

  // Input angles between segments at each vertex: below 60 degrees the
  // mesher protects the corner with clusters and cannot promise the bound there.
  std::vector<std::vector<std::size_t>> at(in.points.size());
  for (std::size_t s = 0; s < in.segments.size(); ++s) {
    at[in.segments[s][0]].push_back(s);
    at[in.segments[s][1]].push_back(s);
  }
  // Apexes of small angles, with the radius of the disc where the bound may fail.
  std::vector<std::pair<std::size_t, double>> apexes;
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
      res.smallest_input_angle = std::min(res.smallest_input_angle, a);
      if (a < 60) {
        small = true;
        apexes.push_back({v, std::min(seg_length(d0.second), seg_length(d1.second))});
      }
    }
    if (small) ++res.small_input_angles;
  }

  std::vector<K::Point_2> seeds;
  for (const auto& h : in.holes) seeds.emplace_back(h[0], h[1]);
  using Mesher = CGAL::Delaunay_mesher_2<CDT, QualityCriteria>;
  Mesher::mark_facets(cdt, seeds.begin(), seeds.end(), false);
  // A size bound that asks for more vertices than --max-vertices is refused
  // at once, not after minutes of refinement (a triangle of the bound is at
  // most max_area, or an equilateral one of side max_edge; vertices are
  // about half the triangles).
  if (opt.max_area > 0 || opt.max_edge > 0) {
    double area = 0;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
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
  if (opt.lattice > 0) {
    std::vector<K::Point_2> lattice;
    try {
      lattice = opt.square_lattice
                    ? square_lattice_in_domain(in, cdt, opt.lattice, opt.grading, opt.max_side, opt.narrow, opt.max_vertices)
                    : lattice_in_domain(in, cdt, opt.lattice, opt.max_vertices);
    } catch (const UsageError&) {
      if (!opt.lattice_optional) throw;
    }
    cdt.insert(lattice.begin(), lattice.end());
    res.lattice_points = cdt.number_of_vertices() - res.input_vertices;
  }
  const double B = opt.min_angle > 0 ? std::pow(std::sin(opt.min_angle * M_PI / 180), 2) : 0;
  QualityCriteria criteria(B, opt.max_edge > 0 ? opt.max_edge : 0, opt.max_area);
  Mesher mesher(cdt, criteria);
  mesher.set_seeds(seeds.begin(), seeds.end(), false);
  mesher.init();
  if (opt.min_angle > 0 || opt.max_area > 0 || opt.max_edge > 0) {
    std::size_t steps = 0;
    while (!mesher.is_refinement_done()) {
      mesher.step_by_step_refine_mesh();
      // Every step: a small --max-vertices must hold too (a step adds one vertex).
      if (cdt.number_of_vertices() > opt.max_vertices) {
        res.limit_reached = true;
        break;
      }
      if (++steps % 4096 == 0 && opt.progress) opt.progress(cdt.number_of_vertices());
    }
  }

  // Regions: flood fill across unconstrained edges, in the order given
  // (a later regional point overrides an earlier one, as in Triangle).
  for (std::size_t r = 0; r < in.regions.size(); ++r) {
    const auto& reg = in.regions[r];
    Face_handle f = cdt.locate(K::Point_2(reg.point[0], reg.point[1]));
    if (f == Face_handle() || cdt.is_infinite(f) || !f->is_in_domain()) {
      ++res.regions_outside_domain;
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
        if (cdt.is_infinite(n) || !n->is_in_domain() || n->info().region == int(r)) continue;
        n->info().region = int(r);
        stack.push_back(n);
      }
    }
  }

  // Output vertices: those of domain triangles.
  PlanarMesh& m = res.mesh;
  m.first_index = in.first_index;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
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

  // Each input segment is now a chain of constrained edges; walk it from a
  // to b (the split points are midpoints, inexact, so "on the segment" is a
  // tolerance test), giving its subsegments and their vertices its marker.
  for (std::size_t s = 0; s < in.segments.size(); ++s) {
    const Vertex_handle va = vh[in.segments[s][0]], vb = vh[in.segments[s][1]];
    const int marker = in.segment_markers.empty() ? 0 : in.segment_markers[s];
    const double ax = va->point().x(), ay = va->point().y();
    const double dx = vb->point().x() - ax, dy = vb->point().y() - ay;
    const double len2 = dx * dx + dy * dy;
    Vertex_handle cur = va;
    double tcur = 0;
    for (std::size_t guard = 0; cur != vb; ++guard) {
      Vertex_handle best;
      double best_d = 1e300, best_t = 0;
      auto circ = cdt.incident_edges(cur), end = circ;
      do {
        if (cdt.is_infinite(*circ) || !cdt.is_constrained(*circ)) continue;
        const Face_handle f = circ->first;
        const int i = circ->second;
        Vertex_handle w = f->vertex(CDT::cw(i)) == cur ? f->vertex(CDT::ccw(i)) : f->vertex(CDT::cw(i));
        const double px = w->point().x() - ax, py = w->point().y() - ay;
        const double t = (px * dx + py * dy) / len2;
        const double d = std::abs(px * dy - py * dx) / std::sqrt(len2);  // distance to the line
        if (t > tcur && t <= 1 + 1e-9 && d < best_d) {
          best = w;
          best_d = d;
          best_t = t;
        }
      } while (++circ != end);
      if (best == Vertex_handle() || best_d > 1e-6 * std::sqrt(len2) || guard > cdt.number_of_vertices())
        throw Error("internal: segment " + std::to_string(s + in.first_index) + " is not a chain of mesh edges");
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
  for (std::size_t s = 0; s < in.segments.size(); ++s)
    for (int e : {0, 1}) {
      auto v = vh[in.segments[s][e]];
      if (v->info().marker == 0 && !in.segment_markers.empty()) v->info().marker = in.segment_markers[s];
    }
  m.point_markers.assign(m.points.size(), 0);
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (v->info().id >= 0) m.point_markers[v->info().id] = v->info().marker;
  m.holes = in.holes;

  // "Near a small input angle": within the disc around the apex whose radius
  // is the shorter of the two segments, where CGAL's clusters (like
  // Triangle) give up the bound. Marked by a walk over the mesh from the apex.
  for (std::size_t k = 0; k < apexes.size(); ++k) {
    const auto [v, r] = apexes[k];
    const Vertex_handle apex = vh[v];
    const K::Point_2 c = apex->point();
    std::vector<Vertex_handle> stack{apex};
    apex->info().near_small_angle = true;
    apex->info().visit = int(k);
    while (!stack.empty()) {
      Vertex_handle u = stack.back();
      stack.pop_back();
      auto circ = cdt.incident_vertices(u), end = circ;
      do {
        if (cdt.is_infinite(circ) || circ->info().visit == int(k)) continue;
        if (std::sqrt(CGAL::to_double(CGAL::squared_distance(circ->point(), c))) > r * (1 + 1e-9)) continue;
        circ->info().visit = int(k);
        circ->info().near_small_angle = true;
        stack.push_back(circ);
      } while (++circ != end);
    }
  }

  // Quality report.
  res.steiner_points = cdt.number_of_vertices() - res.input_vertices;
  res.min_angle = 180;
  res.min_angle_away_from_small_input_angles = 180;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    const auto &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
    const double mn = std::min({angle_deg(a, b, c), angle_deg(b, c, a), angle_deg(c, a, b)});
    res.min_angle = std::min(res.min_angle, mn);
    bool near = false;
    for (int i = 0; i < 3; ++i) near |= f->vertex(i)->info().near_small_angle;
    if (!near)
      res.min_angle_away_from_small_input_angles = std::min(res.min_angle_away_from_small_input_angles, mn);
    else if (mn < opt.min_angle)
      ++res.below_bound_near_small_angles;
  }
  return res;
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
  const auto box = bounding_box(in);
  return std::max({lengths[lengths.size() / 2] / 2, 2 * lengths[lengths.size() / 10],
                   std::max(box[2] - box[0], box[3] - box[1]) / 2048});
}

double default_max_side(const PlanarMesh& in) {
  if (in.points.empty()) return 0;
  const auto box = bounding_box(in);
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
