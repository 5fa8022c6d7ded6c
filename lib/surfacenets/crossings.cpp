// Which triangles of the surface-nets mesh cross (surface_nets.hpp:
// crossing_pairs), of any labels, found locally on the lattice.
//
// Why testing each quad against its lattice neighbourhood misses no
// crossing: every vertex lies in its cell, the closed cube [c - 1, c]^3 of
// continuous index around its corner c (smoothing clamps it there,
// untangling moves it toward c - 0.5, inside; the constructor checks it).
// A quad's corners are a voxel face's, spanning a lattice box lo..hi with
// hi - lo <= 1 per axis, so its four points, and with them its two
// triangles (convexity), lie in the box [lo - 1, hi], the union of its
// corners' cells; the affine map to world coordinates keeps that. So two
// triangles meet only if their quads' boxes meet: lo_g - 1 <= hi_f and
// lo_f - 1 <= hi_g on every axis, hence lo_g in [lo_f - 2, hi_f + 1], the
// rows (y, z) and the x range searched below. Boxes that do not meet are a
// whole voxel apart (integer bounds), far beyond the rounding of world
// coordinates. When every vertex lies strictly inside its cell (smoothing's
// margin, the rest positions), its quad's triangles lie inside the open box
// (lo - 1, hi), and two open boxes with integer bounds meet only when
// lo_g <= hi_f and lo_f <= hi_g: the faces share a corner, lo_g in
// [lo_f - 1, hi_f], a search a quarter the size (reach 0 below, 1 for
// closed cells). Candidates are then filtered by their points' boxes, and
// the pairs left go to lib/mesh's exact test (triangles_cross).
#include "mesh/embedding.hpp"
#include "surfacenets/surface_nets_detail.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <thread>

namespace imgmesh {
namespace surfacenets_detail {
namespace {

constexpr double kCellSlack = 1e-6;  // in voxels: rounding of world <-> index

float down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// Boxes as (min x, y, z, max x, y, z), closed.
template <class T> bool boxes_meet(const std::array<T, 6>& a, const std::array<T, 6>& b) {
  for (std::size_t i = 0; i < 3; ++i)
    if (a[i + 3] < b[i] || b[i + 3] < a[i]) return false;
  return true;
}

std::array<double, 6> triangle_box(const InterfaceMesh& m, std::size_t t) {
  std::array<double, 6> b{};
  for (std::size_t a = 0; a < 3; ++a) {
    b[a] = b[a + 3] = m.points[std::size_t(m.triangles[t][0])][a];
    for (std::size_t i = 1; i < 3; ++i) {
      const double x = m.points[std::size_t(m.triangles[t][i])][a];
      b[a] = std::min(b[a], x);
      b[a + 3] = std::max(b[a + 3], x);
    }
  }
  return b;
}

std::array<std::size_t, 2> ascending(std::size_t a, std::size_t b) { return {std::min(a, b), std::max(a, b)}; }

} // namespace

// 1 when vertex v lies in its closed cell only (within the rounding), 0
// when strictly inside it; throws when outside.
int CrossingSearch::reach_of(std::size_t v) const {
  const Vec3 p = m_.grid.continuous_index(m_.points[v]);
  const auto c = m_.corner(v);
  int reach = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    const double lo = double(c[a]) - 1, hi = double(c[a]);
    if (!(p[a] >= lo - kCellSlack && p[a] <= hi + kCellSlack))
      throw Error("crossing search: vertex " + std::to_string(v) + " lies outside its voxel-corner cell");
    if (!(p[a] > lo + kCellSlack && p[a] < hi - kCellSlack)) reach = 1;
  }
  return reach;
}

CrossingSearch::CrossingSearch(const InterfaceMesh& m, unsigned threads) : m_(m), threads_(std::max(1u, threads)) {
  for (std::size_t v = 0; v < m.points.size(); ++v) reach_ = std::max(reach_, reach_of(v));
  const std::size_t n = m.quads.size(), rows = m.lattice[1] * m.lattice[2];
  if (n > std::numeric_limits<std::uint32_t>::max()) throw Error("crossing search: more than 2^32 quads");
  lo_.resize(n);
  hi_.resize(n);
  box_.resize(n);
  degenerate_.resize(2 * n);
  row_begin_.assign(rows + 1, 0);
  for (std::size_t f = 0; f < n; ++f) {
    for (std::size_t i = 0; i < 4; ++i) {
      const auto c = m.corner(std::size_t(m.quads[f][i]));
      for (std::size_t a = 0; a < 3; ++a) {
        lo_[f][a] = i ? std::min(lo_[f][a], std::int32_t(c[a])) : std::int32_t(c[a]);
        hi_[f][a] = i ? std::max(hi_[f][a], std::int32_t(c[a])) : std::int32_t(c[a]);
      }
    }
    for (std::size_t a = 0; a < 3; ++a)
      if (hi_[f][a] - lo_[f][a] > 1) throw Error("crossing search: quad " + std::to_string(f) + " is not a voxel face");
    ++row_begin_[std::size_t(lo_[f][1]) + m.lattice[1] * std::size_t(lo_[f][2]) + 1];
    update(f);
  }
  // Counting sort by row, then by x within each row (K(X)'s face order
  // already is: the sort only runs on other input).
  for (std::size_t r = 0; r < rows; ++r) row_begin_[r + 1] += row_begin_[r];
  order_.resize(n);
  std::vector<std::size_t> next(row_begin_.begin(), row_begin_.end() - 1);
  for (std::size_t f = 0; f < n; ++f)
    order_[next[std::size_t(lo_[f][1]) + m.lattice[1] * std::size_t(lo_[f][2])]++] = std::uint32_t(f);
  auto by_x = [this](std::uint32_t a, std::uint32_t b) { return lo_[a][0] < lo_[b][0]; };
  for (std::size_t r = 0; r < rows; ++r) {
    const auto b = order_.begin() + std::ptrdiff_t(row_begin_[r]), e = order_.begin() + std::ptrdiff_t(row_begin_[r + 1]);
    if (!std::is_sorted(b, e, by_x)) std::stable_sort(b, e, by_x);
  }
  position_.resize(n);
  for (std::size_t i = 0; i < n; ++i) position_[order_[i]] = std::uint32_t(i);
}

void CrossingSearch::update(std::size_t f) {
  if (reach_ == 0)
    for (int v : m_.quads[f]) reach_ = std::max(reach_, reach_of(std::size_t(v)));
  for (std::size_t a = 0; a < 3; ++a) {
    double lo = m_.points[std::size_t(m_.quads[f][0])][a], hi = lo;
    for (std::size_t i = 1; i < 4; ++i) {
      lo = std::min(lo, m_.points[std::size_t(m_.quads[f][i])][a]);
      hi = std::max(hi, m_.points[std::size_t(m_.quads[f][i])][a]);
    }
    box_[f][a] = down(lo);
    box_[f][a + 3] = up(hi);
  }
  for (std::size_t t = 2 * f; t < 2 * f + 2; ++t) degenerate_[t] = triangle_degenerate(m_.points, m_.triangles[t]);
}

// Every quad g whose box meets f's (f itself included); forward: only
// those of f's row (y, z) and after (some before f, in its row).
template <class Visit> void CrossingSearch::for_each_neighbour(std::size_t f, bool forward, Visit&& visit) const {
  const auto &lo = lo_[f], &hi = hi_[f];
  const std::int32_t ny = std::int32_t(m_.lattice[1]), nz = std::int32_t(m_.lattice[2]), r = reach_;
  for (std::int32_t z = std::max(0, forward ? lo[2] : lo[2] - 1 - r); z <= std::min(nz - 1, hi[2] + r); ++z)
    for (std::int32_t y = std::max(0, forward && z == lo[2] ? lo[1] : lo[1] - 1 - r); y <= std::min(ny - 1, hi[1] + r); ++y) {
      const std::size_t row = std::size_t(y) + std::size_t(ny) * std::size_t(z);
      const auto e = order_.begin() + std::ptrdiff_t(row_begin_[row + 1]);
      auto it = std::lower_bound(order_.begin() + std::ptrdiff_t(row_begin_[row]), e, lo[0] - 1 - r,
                                 [this](std::uint32_t g, std::int32_t x) { return lo_[g][0] < x; });
      for (; it != e && lo_[*it][0] <= hi[0] + r; ++it) {
        const auto& h = hi_[*it];
        if (h[0] >= lo[0] - r && h[1] >= lo[1] - r && h[2] >= lo[2] - r) visit(std::size_t(*it));
      }
    }
}

std::vector<std::array<std::size_t, 2>> CrossingSearch::pairs(const std::vector<std::size_t>& quads) const {
  return search(quads, false);
}

std::vector<std::array<std::size_t, 2>> CrossingSearch::all_pairs() const {
  std::vector<std::size_t> all(m_.quads.size());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = f;
  return search(all, true);
}

// The pairs with a triangle of `quads`; all: they are every quad. Threads
// take contiguous slices of `quads`; the pairs are sorted at the end, so
// the result does not depend on their number.
std::vector<std::array<std::size_t, 2>> CrossingSearch::search(const std::vector<std::size_t>& quads, bool all) const {
  std::vector<std::uint8_t> listed(m_.quads.size(), std::uint8_t(all));
  for (std::size_t f : quads) listed[f] = 1;
  const std::size_t slices = std::min<std::size_t>(threads_, quads.size() / 256 + 1);  // a slice worth a thread
  std::vector<std::vector<std::array<std::size_t, 2>>> found(slices);
  std::vector<std::exception_ptr> failed(slices);
  auto run = [&](std::size_t k) {
    try {
      for (std::size_t i = quads.size() * k / slices; i < quads.size() * (k + 1) / slices; ++i)
        search_quad(quads[i], listed, all, found[k]);
    } catch (...) {
      failed[k] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t k = 1; k < slices; ++k) pool.emplace_back(run, k);
  run(0);
  for (auto& t : pool) t.join();
  for (const auto& e : failed)
    if (e) std::rethrow_exception(e);
  std::vector<std::array<std::size_t, 2>> out;
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  std::sort(out.begin(), out.end());
  return out;
}

void CrossingSearch::search_quad(std::size_t f, const std::vector<std::uint8_t>& listed, bool all,
                                 std::vector<std::array<std::size_t, 2>>& out) const {
  const std::array<std::size_t, 2> s{2 * f, 2 * f + 1};
  const std::array<std::array<double, 6>, 2> sb{triangle_box(m_, s[0]), triangle_box(m_, s[1])};
  // f's triangles against triangle t; a degenerate one is paired with
  // itself only (as CGAL's self_intersections does).
  auto test = [&](std::size_t t) {
    if (degenerate_[t]) return;
    const std::array<double, 6> tb = triangle_box(m_, t);
    for (std::size_t i = 0; i < 2; ++i)
      if (s[i] != t && !degenerate_[s[i]] && boxes_meet(sb[i], tb) && triangles_cross(m_.points, m_.triangles[s[i]], m_.triangles[t]))
        out.push_back(ascending(s[i], t));
  };
  for (std::size_t t : s)
    if (degenerate_[t]) out.push_back({t, t});
  test(s[1]);  // f's two triangles
  for_each_neighbour(f, all, [&](std::size_t g) {
    // A pair of listed quads once, from its first in order_.
    if (g == f || (listed[g] && position_[g] < position_[f]) || !boxes_meet(box_[f], box_[g])) return;
    test(2 * g);
    test(2 * g + 1);
  });
}

} // namespace surfacenets_detail

std::vector<std::array<std::size_t, 2>> crossing_pairs(const InterfaceMesh& mesh, unsigned threads) {
  return surfacenets_detail::CrossingSearch(mesh, threads).all_pairs();
}

} // namespace imgmesh
