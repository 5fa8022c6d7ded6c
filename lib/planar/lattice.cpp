// poly2tri's lattices of Steiner points (TriangulateOptions::lattice): an
// equilateral one, or a square one graded by a size field. CGAL-free: the
// triangulation answers only whether a point is in the domain.
#include "planar/triangulate_detail.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace imgmesh::planar_detail {

std::array<double, 4> bounding_box(const PlanarMesh& in) {
  double x0 = in.points[0][0], y0 = in.points[0][1], x1 = x0, y1 = y0;
  for (const auto& p : in.points) {
    x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]);
    y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
  }
  return {x0, y0, x1, y1};
}

Point2 closest_on_segment(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0;
  return {a[0] + t * dx, a[1] + t * dy};
}

double distance_to_segment(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 c = closest_on_segment(p, a, b);
  return std::hypot(c[0] - p[0], c[1] - p[1]);
}

namespace {

[[noreturn]] void too_many_points() {
  throw UsageError("the lattice side is too small: its points alone exceed --max-vertices");
}

// The input's segments (a vertex is one of length 0) in buckets of side h:
// each goes into the 3 x 3 cells around samples taken every h/2 along it,
// which covers every cell with a point within h/2 of it.
class SegmentBuckets {
public:
  // Cells from (x0, y0), the corner of the input's bounding box.
  SegmentBuckets(const PlanarMesh& in, double h, double x0, double y0) : in_(in), h_(h), x0_(x0), y0_(y0) {
    for (const auto& s : in.segments) add(s);
    for (int v = 0; v < int(in.points.size()); ++v) add({v, v});
  }
  // Whether a segment or vertex is closer than h/2 to p.
  bool near(const Point2& p) const {
    const auto b = buckets_.find(cell(p[0], p[1]));
    return b != buckets_.end() && std::any_of(b->second.begin(), b->second.end(), [&](const std::array<int, 2>& s) {
             return distance_to_segment(p, in_.points[s[0]], in_.points[s[1]]) < h_ / 2;
           });
  }

private:
  long long cell(double x, double y) const {
    return (long long)std::floor((y - y0_) / h_) * (1LL << 31) + (long long)std::floor((x - x0_) / h_);
  }
  void add(std::array<int, 2> s) {
    const Point2 &a = in_.points[s[0]], &b = in_.points[s[1]];
    const int samples = int(std::ceil(2 * std::hypot(b[0] - a[0], b[1] - a[1]) / h_));
    for (int k = 0; k <= samples; ++k) {
      const double t = samples ? double(k) / samples : 0;
      const double x = a[0] + t * (b[0] - a[0]), y = a[1] + t * (b[1] - a[1]);
      for (int dy : {-1, 0, 1})
        for (int dx : {-1, 0, 1}) {
          auto& bucket = buckets_[cell(x + dx * h_, y + dy * h_)];
          if (bucket.empty() || bucket.back() != s) bucket.push_back(s);
        }
    }
  }
  const PlanarMesh& in_;
  double h_, x0_, y0_;
  std::unordered_map<long long, std::vector<std::array<int, 2>>> buckets_;
};

} // namespace

std::vector<Point2> equilateral_lattice(const PlanarMesh& in, double h, std::size_t limit, const InDomain& in_domain) {
  const auto box = bounding_box(in);
  const double x0 = box[0], y0 = box[1], x1 = box[2], y1 = box[3];
  const double row = h * std::sqrt(3.0) / 2;
  const double columns = std::floor((x1 - x0) / h) + 1, rows = std::floor((y1 - y0) / row) + 1;
  if (columns * rows > double(limit)) too_many_points();
  const SegmentBuckets buckets(in, h, x0, y0);
  std::vector<Point2> out;
  for (int j = 0; j < int(rows); ++j)
    for (int i = 0; i < int(columns); ++i) {
      const Point2 p{x0 + h / 2 + (j % 2 ? h / 2 : 0) + i * h, y0 + row / 2 + j * row};
      if (p[0] >= x1 || p[1] >= y1 || buckets.near(p)) continue;
      if (in_domain(p)) out.push_back(p);
    }
  return out;
}

// The square lattice: the nodes of side h at the cell centres of the input's
// bounding box, graded by a size field: each segment asks for its own length
// (clamped to [h, max_side]) along it, growing by `grading` per unit of
// distance away from it (the smallest ask wins: a grading-Lipschitz field). A
// node whose size is s stays only if it is a node of the lattice of side 2^k
// h, k the largest with 2^k h <= s and <= max_side, and lies at least 2^k h /
// 2 from every segment and vertex (Delaunay refinement fills that band). So
// the lattice follows the curves' own sampling (a long side of the image
// rectangle asks for coarse cells, a finely sampled curve for fine ones).
// With `narrow` (and grading > 0) the nodes are those of the lattice of side
// h / 2 too, and where the domain is narrower than the field asks for (a node
// between two sides of it, 2 d across, d its distance to the nearer) the
// field is at most that width: the lattice then fits a row of nodes wherever
// the finer side does, where it left the space between close curves to
// Delaunay refinement (on 128 x 128 label slices through the default chain:
// mean Joe's mu 27.8-27.9 -> 30.1-30.5, 1.6 x quads). The distances come from
// a vector distance transform on the nodes (Danielsson: each node takes the
// nearest of the segments its neighbours are nearest to, seeded exactly
// within a cell of every segment), the size field from the same sweeps;
// grading 0: the uniform lattice of side h.
namespace {

// The nodes x0 + h / 2 + i hf, y0 + h / 2 + j hf (those of even i and j make
// the lattice of side h) and the fields on them.
struct NodeFields {
  const PlanarMesh& in;
  double x0, y0, h, hf, grading;
  long W, H;
  std::vector<int> nearest;  // segment id; vertices come after the segments
  std::vector<double> dist, size;
  std::vector<double> ask;  // the size each segment asks for along it

  std::size_t index(long i, long j) const { return std::size_t(j * W + i); }
  Point2 node(long i, long j) const { return Point2{x0 + h / 2 + double(i) * hf, y0 + h / 2 + double(j) * hf}; }
  std::array<int, 2> ends(int s) const {
    const std::size_t ns = in.segments.size();
    return std::size_t(s) < ns ? in.segments[std::size_t(s)] : std::array<int, 2>{s - int(ns), s - int(ns)};
  }
  // Segment s as a candidate nearest to node (i, j), and its ask there.
  void offer(long i, long j, int s) {
    if (i < 0 || j < 0 || i >= W || j >= H) return;
    const auto e = ends(s);
    const double d = distance_to_segment(node(i, j), in.points[std::size_t(e[0])], in.points[std::size_t(e[1])]);
    const std::size_t n = index(i, j);
    if (d < dist[n]) { dist[n] = d; nearest[n] = s; }
    if (grading > 0) size[n] = std::min(size[n], ask[std::size_t(s)] + grading * d);
  }
};

// The node step: h, or h / 2 with `narrow` (four times the nodes: not past
// 2048 x 2048 of them, default_lattice_side's own bound, where it is left out).
double node_step(const std::array<double, 4>& box, double h, double grading, bool narrow) {
  const auto count = [&](double step) {
    return (std::floor((box[2] - box[0] - h / 2) / step) + 2) * (std::floor((box[3] - box[1] - h / 2) / step) + 2);
  };
  return narrow && grading > 0 && count(h / 2) <= 2048.0 * 2048 ? h / 2 : h;
}

NodeFields make_fields(const PlanarMesh& in, const std::array<double, 4>& box, double h, double hf, double grading,
                       double coarsest, std::size_t limit) {
  const double columns = std::floor((box[2] - box[0] - h / 2) / hf) + 2;
  const double rows = std::floor((box[3] - box[1] - h / 2) / hf) + 2;
  // A uniform lattice has about as many points as nodes; a graded one is
  // counted once made. Past 3e7 nodes the distance transform alone would
  // take gigabytes.
  if ((grading <= 0 && columns * rows > double(limit)) || columns * rows > 3e7) too_many_points();
  NodeFields f{in, box[0], box[1], h, hf, grading, long(columns), long(rows), {}, {}, {}, {}};
  const std::size_t n_nodes = std::size_t(f.W * f.H);
  f.nearest.assign(n_nodes, -1);
  f.dist.assign(n_nodes, std::numeric_limits<double>::infinity());
  f.size.assign(n_nodes, grading > 0 ? std::numeric_limits<double>::infinity() : h);
  const std::size_t ns = in.segments.size();
  f.ask.assign(ns + in.points.size(), h);
  for (std::size_t s = 0; s < ns; ++s) {
    const Point2 &a = in.points[std::size_t(in.segments[s][0])], &b = in.points[std::size_t(in.segments[s][1])];
    f.ask[s] = std::clamp(std::hypot(b[0] - a[0], b[1] - a[1]), h, coarsest);
  }
  return f;
}

// Seeds: the nodes of the 4 x 4 cells around samples every hf/2 along each
// segment (every node within hf of it).
void seed_near_segments(NodeFields& f) {
  for (int s = 0; s < int(f.in.segments.size() + f.in.points.size()); ++s) {
    const auto e = f.ends(s);
    const Point2 &a = f.in.points[std::size_t(e[0])], &b = f.in.points[std::size_t(e[1])];
    const int samples = int(std::ceil(2 * std::hypot(b[0] - a[0], b[1] - a[1]) / f.hf));
    for (int k = 0; k <= samples; ++k) {
      const double t = samples ? double(k) / samples : 0;
      const long i = long(std::floor((a[0] + t * (b[0] - a[0]) - f.x0 - f.h / 2) / f.hf));
      const long j = long(std::floor((a[1] + t * (b[1] - a[1]) - f.y0 - f.h / 2) / f.hf));
      for (long dj = -1; dj <= 2; ++dj)
        for (long di = -1; di <= 2; ++di) f.offer(i + di, j + dj, s);
    }
  }
}

// Two forward then backward raster sweeps calling step(i, j, a, b) for node
// (i, j) and each neighbour (a, b) already swept (possibly off the grid).
template <class Step> void sweeps(long W, long H, const Step& step) {
  for (int sweep = 0; sweep < 2; ++sweep) {
    for (long j = 0; j < H; ++j)
      for (long i = 0; i < W; ++i)
        for (const auto& d : {std::array<long, 2>{-1, 0}, {-1, -1}, {0, -1}, {1, -1}}) step(i, j, i + d[0], j + d[1]);
    for (long j = H - 1; j >= 0; --j)
      for (long i = W - 1; i >= 0; --i)
        for (const auto& d : {std::array<long, 2>{1, 0}, {1, 1}, {0, 1}, {-1, 1}}) step(i, j, i + d[0], j + d[1]);
  }
}

// Each node takes its neighbours' nearest segments, and their sizes plus the
// grading times the step.
void propagate(NodeFields& f) {
  sweeps(f.W, f.H, [&](long i, long j, long a, long b) {
    if (a < 0 || b < 0 || a >= f.W || b >= f.H) return;
    const std::size_t m = f.index(a, b);
    if (f.nearest[m] >= 0) f.offer(i, j, f.nearest[m]);
    const std::size_t n = f.index(i, j);
    f.size[n] = std::min(f.size[n], f.size[m] + f.grading * f.hf * std::hypot(double(a - i), double(b - j)));
  });
}

// A node is between two sides of the domain when the directions to its
// nearest points on its own nearest segment and on a neighbour's are more
// than 120 degrees apart (the two sides of a convex corner of 60 degrees or
// more are not). There the size is at most 2 d, the width, and the field
// grows from it by the grading as from a segment.
void cap_at_width(NodeFields& f) {
  std::vector<double> width(f.size.size(), std::numeric_limits<double>::infinity());
  const auto towards = [&](const Point2& p, int s) {  // unit vector from p to its nearest point on s
    const auto e = f.ends(s);
    const Point2 c = closest_on_segment(p, f.in.points[std::size_t(e[0])], f.in.points[std::size_t(e[1])]);
    const double ux = c[0] - p[0], uy = c[1] - p[1], l = std::hypot(ux, uy);
    return l > 0 ? std::array<double, 2>{ux / l, uy / l} : std::array<double, 2>{0, 0};
  };
  for (long j = 0; j < f.H; ++j)
    for (long i = 0; i < f.W; ++i) {
      const std::size_t n = f.index(i, j);
      if (f.nearest[n] < 0 || !(f.dist[n] > 0)) continue;
      const Point2 p = f.node(i, j);
      const auto u = towards(p, f.nearest[n]);
      bool between = false;
      for (long b = std::max(0L, j - 1); b <= std::min(f.H - 1, j + 1) && !between; ++b)
        for (long a = std::max(0L, i - 1); a <= std::min(f.W - 1, i + 1) && !between; ++a) {
          const int s = f.nearest[f.index(a, b)];
          if (s < 0 || s == f.nearest[n]) continue;
          const auto v = towards(p, s);
          between = u[0] * v[0] + u[1] * v[1] < -0.5;
        }
      if (between) width[n] = std::max(f.hf, 2 * f.dist[n]);
    }
  sweeps(f.W, f.H, [&](long i, long j, long a, long b) {
    if (a < 0 || b < 0 || a >= f.W || b >= f.H) return;
    const std::size_t n = f.index(i, j), m = f.index(a, b);
    width[n] = std::min(width[n], width[m] + f.grading * f.hf * std::hypot(double(a - i), double(b - j)));
  });
  for (std::size_t n = 0; n < f.size.size(); ++n) f.size[n] = std::min(f.size[n], width[n]);
}

// The nodes that stay (the level their size allows, far enough from the
// segments) within the box and the domain.
std::vector<Point2> select_nodes(const NodeFields& f, double x1, double y1, double coarsest, const InDomain& in_domain) {
  int top = 0;  // the coarsest level
  while (std::ldexp(f.hf, top + 1) <= coarsest * (1 + 1e-12)) ++top;
  std::vector<Point2> out;
  for (long j = 0; j < f.H; ++j)
    for (long i = 0; i < f.W; ++i) {
      const Point2 p = f.node(i, j);
      const std::size_t n = f.index(i, j);
      if (p[0] >= x1 || p[1] >= y1) continue;
      int k = 0;
      while (k < top && std::ldexp(f.hf, k + 1) <= f.size[n]) ++k;
      if (i % (1L << k) != 0 || j % (1L << k) != 0 || f.dist[n] < std::ldexp(f.hf, k) / 2) continue;
      if (in_domain(p)) out.push_back(p);
    }
  return out;
}

} // namespace

std::vector<Point2> square_lattice(const PlanarMesh& in, double h, double grading, double max_side, bool narrow,
                                   std::size_t limit, const InDomain& in_domain) {
  const auto box = bounding_box(in);
  const double hf = node_step(box, h, grading, narrow);
  const double coarsest = max_side > h ? max_side : h;
  NodeFields f = make_fields(in, box, h, hf, grading, coarsest, limit);
  seed_near_segments(f);
  if (grading > 0) propagate(f);
  if (hf < h) cap_at_width(f);
  std::vector<Point2> out = select_nodes(f, box[2], box[3], coarsest, in_domain);
  if (out.size() > limit) too_many_points();
  return out;
}

} // namespace imgmesh::planar_detail
