#include "surface/criteria.hpp"

#include "surface/restricted_delaunay.hpp"
#include "surface/topo_disk.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh {

// k = 0.06 (thesis 7.6.3-7.6.4; doc/thesis-errata.md).
double min_ratio_bound() { return (1 + 0.06) * (1 + 0.06); }
double min_roughness_bound() { return 2 * (std::asin(0.06) + std::asin(2 * 0.06 / std::sqrt(3.0))); }

} // namespace imgmesh

namespace imgmesh::surface_detail {

double ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = std::sqrt(dist2(b, c)), lb = std::sqrt(dist2(c, a)), lc = std::sqrt(dist2(a, b));
  const double area2 = norm(cross(sub(b, a), sub(c, a)));  // twice the area
  const double lmin = std::min({la, lb, lc});
  if (area2 <= 0 || lmin <= 0) return INFINITY;
  return la * lb * lc / (2 * area2) / lmin;
}

bool distance_refines(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& x, double max_distance) {
  Vec3 nrm = cross(sub(b, a), sub(c, a));
  const double nl = norm(nrm);
  return nl > 0 && std::abs(dot(nrm, sub(x, a))) / nl > max_distance;
}

bool centroid_refines(const SurfaceSampler& f, const Vec3& a, const Vec3& b, const Vec3& c, double max_distance) {
  const Vec3 g{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
  return std::abs(f.value(g)) > 2 * max_distance;
}

bool roughness_within(std::vector<std::pair<int, Vec3>>& normals, double g) {
  std::sort(normals.begin(), normals.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t i = 0; i + 1 < normals.size();) {
    std::size_t j = i;
    while (j < normals.size() && normals[j].first == normals[i].first) ++j;
    if (j - i == 2) {  // other counts are TopoDisk's business
      const double c = std::clamp(dot(normals[i].second, normals[i + 1].second), -1.0, 1.0);
      if (std::acos(c) > g) return false;
    }
    i = j;
  }
  return true;
}

bool Smooth::operator()(const Tr& tr, Vh v, double g, Facet* worst) {
  restricted_around(tr, v, facets_, cells_);
  return (*this)(v, facets_, g, worst);
}

bool Smooth::operator()(Vh v, const std::vector<Facet>& facets, double g, Facet* worst) {
  normals_.clear();  // (other vertex of the edge, oriented unit normal)
  double best = -1;
  for (const Facet& f : facets) {
    const FacetInfo& fi = f.first->facet[f.second];
    if (!(fi.state & kRestricted)) continue;
    const std::array<Vh, 3> fv = facet_vertices(f.first, f.second);
    const Vec3 a = vec(fv[0]->point()), b = vec(fv[1]->point()), c = vec(fv[2]->point());
    Vec3 n = cross(sub(b, a), sub(c, a));
    const double nl = norm(n);
    if (nl <= 0) continue;
    const Vec3 gr{fi.grad[0], fi.grad[1], fi.grad[2]};
    const double s = dot(n, gr) < 0 ? -1 / nl : 1 / nl;
    n = {n[0] * s, n[1] * s, n[2] * s};
    for (int m = 1; m < 4; ++m) {
      Vh w = f.first->vertex((f.second + m) & 3);
      if (w != v) normals_.emplace_back(w->info().id, n);
    }
    if (fi.r2 > best) {
      best = fi.r2;
      *worst = f;
    }
  }
  return roughness_within(normals_, g);
}

} // namespace imgmesh::surface_detail
