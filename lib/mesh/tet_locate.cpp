#include "mesh/tet_locate.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace imgmesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Pt = K::Point_3;

Pt pt(const Vec3& p) { return {p[0], p[1], p[2]}; }

// The index range [lo, hi] of voxel centres within the points' box (empty
// when lo > hi on an axis).
void index_box(const Geometry& g, const std::array<Vec3, 4>& p, std::array<long long, 3>& lo, std::array<long long, 3>& hi) {
  std::array<double, 3> a{1e300, 1e300, 1e300}, b{-1e300, -1e300, -1e300};
  for (const Vec3& q : p) {
    const Vec3 c = g.continuous_index(q);
    for (int i = 0; i < 3; ++i) a[i] = std::min(a[i], c[i]), b[i] = std::max(b[i], c[i]);
  }
  for (int i = 0; i < 3; ++i) {
    // A rounding's room either side: the exact tests decide.
    lo[i] = std::max(0LL, (long long)std::ceil(a[i] - 1e-6));
    hi[i] = std::min((long long)g.size[std::size_t(i)] - 1, (long long)std::floor(b[i] + 1e-6));
  }
}

} // namespace

VoxelCentreLocation locate_voxel_centres(const TetMesh& m, const LabelImage& x) {
  const auto orient = K().orientation_3_object();
  // Per voxel: bit 1 in a tetrahedron of its own region, bit 2 of another.
  std::vector<unsigned char> in(x.data.size(), 0);
  auto contains = [&](const std::array<Pt, 4>& t, const Pt& p) {
    return orient(p, t[1], t[2], t[3]) != CGAL::NEGATIVE && orient(t[0], p, t[2], t[3]) != CGAL::NEGATIVE &&
           orient(t[0], t[1], p, t[3]) != CGAL::NEGATIVE && orient(t[0], t[1], t[2], p) != CGAL::NEGATIVE;
  };
  const long long n = (long long)m.points.size();
  // Calls visit(voxel index, i, j, k) for each voxel centre in tetrahedron t.
  auto each_centre = [&](std::size_t t, auto visit) {
    const auto& q = m.tets[t];
    if (std::any_of(q.begin(), q.end(), [n](int v) { return v < 0 || v >= n; })) return;
    std::array<Vec3, 4> p;
    std::array<Pt, 4> c;
    for (int i = 0; i < 4; ++i) p[i] = m.points[std::size_t(q[i])], c[i] = pt(p[i]);
    if (orient(c[0], c[1], c[2], c[3]) != CGAL::POSITIVE) return;
    std::array<long long, 3> lo, hi;
    index_box(x, p, lo, hi);
    for (long long k = lo[2]; k <= hi[2]; ++k)
      for (long long j = lo[1]; j <= hi[1]; ++j)
        for (long long i = lo[0]; i <= hi[0]; ++i)
          if (contains(c, pt(x.world(double(i), double(j), double(k)))))
            visit(x.index(std::size_t(i), std::size_t(j), std::size_t(k)));
  };
  auto region = [&](std::size_t t) { return t < m.tet_region.size() ? m.tet_region[t] : 1; };
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    each_centre(t, [&](std::size_t v) { in[v] |= region(t) == x.data[v] ? 1 : 2; });
  VoxelCentreLocation r;
  r.checked = x.data.size();
  std::size_t first = x.data.size();
  for (std::size_t v = 0; v < in.size(); ++v) {
    const bool other = in[v] & 2, outside = x.data[v] != 0 && !in[v];
    r.outside += outside;
    r.in_other += other;
    if ((outside || other) && first == x.data.size()) first = v;
  }
  if (first == x.data.size()) return r;
  r.first = {first % x.size[0], first / x.size[0] % x.size[1], first / x.size[0] / x.size[1]};
  r.first_label = x.data[first];
  if (in[first] & 2)
    for (std::size_t t = 0; t < m.tets.size() && r.first_region < 0; ++t)
      each_centre(t, [&](std::size_t v) {
        if (v == first && region(t) != x.data[v]) r.first_region = region(t);
      });
  return r;
}

std::string VoxelCentreLocation::failure() const {
  if (!wrong()) return "";
  std::string s = std::to_string(wrong()) + " of " + std::to_string(checked) + " voxel centres not in a tetrahedron of their own label (" +
                  std::to_string(outside) + " in none, " + std::to_string(in_other) + " in another region's); the first, voxel (" +
                  std::to_string(first[0]) + ", " + std::to_string(first[1]) + ", " + std::to_string(first[2]) + ") of label " +
                  std::to_string(first_label);
  return s + (first_region >= 0 ? ", in a tetrahedron of region " + std::to_string(first_region) : ", in none");
}

Json VoxelCentreLocation::to_json() const {
  Json j = Json::object();
  j["checked"] = checked;
  j["wrong"] = wrong();
  j["in_no_tetrahedron"] = outside;
  j["in_another_region"] = in_other;
  if (wrong()) {
    j["first_voxel"] = std::vector<std::size_t>{first[0], first[1], first[2]};
    j["first_label"] = first_label;
    j["first_region"] = first_region;
  }
  return j;
}

} // namespace imgmesh
