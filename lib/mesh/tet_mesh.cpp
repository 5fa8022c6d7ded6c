#include "mesh/tet_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <set>
#include <string>

namespace imgmesh {

namespace {
using P = std::array<double, 3>;
P sub(const P& a, const P& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const P& a, const P& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
P cross(const P& a, const P& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }

// The four faces of a positive tetrahedron, outward: opposite a, b, c, d.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// A tetrahedron's face as it lies in it (outward), keyed by its sorted
// vertex ids. The faces of a mesh are sorted by key rather than hashed:
// no allocation per face (on 660,000 tetrahedra, hash maps took most of
// the checks' time).
struct Face {
  std::array<int, 3> key;  // sorted
  std::array<int, 3> tri;
  int region = 0;          // its tetrahedron's (region_interfaces)
  bool operator<(const Face& o) const { return key < o.key; }
};
void add_faces(const std::array<int, 4>& q, std::vector<Face>& faces, int region = 0) {
  for (const auto& f : kFace) {
    Face face{{}, {q[std::size_t(f[0])], q[std::size_t(f[1])], q[std::size_t(f[2])]}, region};
    face.key = face.tri;
    std::sort(face.key.begin(), face.key.end());
    faces.push_back(face);
  }
}
// Calls visit(first, count) on each run of faces with one key.
template <class Visit> void for_each_face(std::vector<Face>& faces, Visit visit) {
  std::sort(faces.begin(), faces.end());
  for (std::size_t i = 0, j = 0; i < faces.size(); i = j) {
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    visit(&faces[i], j - i);
  }
}
// The parity of a triangle's vertex order against its sorted order.
bool even(const std::array<int, 3>& t) {
  int inversions = (t[0] > t[1]) + (t[0] > t[2]) + (t[1] > t[2]);
  return inversions % 2 == 0;
}
} // namespace

double tet_orient(const P& a, const P& b, const P& c, const P& d) { return dot(sub(b, a), cross(sub(c, a), sub(d, a))); }

double tet_circumradius(const P& a, const P& b, const P& c, const P& d) {
  const P u = sub(b, a), v = sub(c, a), w = sub(d, a);
  const double det = 2 * dot(u, cross(v, w));
  if (det == 0) return std::numeric_limits<double>::infinity();
  const P vw = cross(v, w), wu = cross(w, u), uv = cross(u, v);
  P o;
  for (int i = 0; i < 3; ++i) o[i] = (dot(u, u) * vw[i] + dot(v, v) * wu[i] + dot(w, w) * uv[i]) / det;
  return std::sqrt(dot(o, o));
}

double tet_radius_edge_ratio(const P& a, const P& b, const P& c, const P& d) {
  const P all[4] = {a, b, c, d};
  double lmin2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const P e = sub(all[i], all[j]);
      lmin2 = std::min(lmin2, dot(e, e));
    }
  if (lmin2 == 0) return std::numeric_limits<double>::infinity();
  return tet_circumradius(a, b, c, d) / std::sqrt(lmin2);
}

std::array<double, 6> tet_dihedral_cosines(const P& a, const P& b, const P& c, const P& d) {
  const P p[4] = {a, b, c, d};
  std::array<double, 6> cosines{};
  int n = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      int k = 0;
      while (k == i || k == j) ++k;
      const int l = 6 - i - j - k;
      // The angle between the two faces at edge ij: between the parts of
      // pk - pi and pl - pi orthogonal to the edge.
      const P e = sub(p[j], p[i]);
      const double ee = dot(e, e);
      P u = sub(p[k], p[i]), v = sub(p[l], p[i]);
      const double su = ee > 0 ? dot(u, e) / ee : 0, sv = ee > 0 ? dot(v, e) / ee : 0;
      for (int m = 0; m < 3; ++m) {
        u[m] -= su * e[m];
        v[m] -= sv * e[m];
      }
      const double nu = std::sqrt(dot(u, u)), nv = std::sqrt(dot(v, v));
      cosines[std::size_t(n++)] = nu > 0 && nv > 0 ? std::clamp(dot(u, v) / (nu * nv), -1.0, 1.0) : 1;
    }
  return cosines;
}

double dihedral_degrees(double cosine) { return std::acos(cosine) * 180 / M_PI; }

double smallest_dihedral_below(const std::array<double, 3>& a, const std::array<double, 3>& b,
                               const std::array<double, 3>& c, const std::array<double, 3>& d, double bound) {
  const auto cosines = tet_dihedral_cosines(a, b, c, d);
  const double top = *std::max_element(cosines.begin(), cosines.end());
  return top > std::cos(bound * M_PI / 180) - 1e-9 ? dihedral_degrees(top) : bound;
}

double refinement_badness(const std::array<std::array<double, 3>, 4>& p, double r2, double ratio_bound,
                          double size_bound, double sliver_angle, double floor, bool& sliver) {
  sliver = false;
  auto d2 = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
  };
  double lmin2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i + 1; j < 4; ++j) lmin2 = std::min(lmin2, d2(p[i], p[j]));
  const double ratio = std::sqrt(r2 / lmin2), size = std::sqrt(r2);
  double bad = 0;
  if (ratio > ratio_bound) bad = 1 + ratio / ratio_bound;
  if (size_bound > 0 && size > size_bound) bad = std::max(bad, 1 + size / size_bound);
  if (bad == 0 && sliver_angle > 0 && size >= floor) {
    const double lo = smallest_dihedral_below(p[0], p[1], p[2], p[3], sliver_angle);
    if (lo < sliver_angle) {
      bad = 1 - lo / sliver_angle;
      sliver = true;
    }
  }
  return bad;
}

std::array<double, 6> tet_dihedral_angles(const P& a, const P& b, const P& c, const P& d) {
  std::array<double, 6> angles = tet_dihedral_cosines(a, b, c, d);
  for (double& x : angles) x = dihedral_degrees(x);
  return angles;
}

TetQualityReport tet_quality(const TetMesh& m) {
  TetQualityReport r;
  r.tetrahedra = m.tets.size();
  if (m.tets.empty()) return r;
  r.min_dihedral = 180;
  double sum_ratio = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& q = m.tets[t];
    const P &a = m.points[std::size_t(q[0])], &b = m.points[std::size_t(q[1])], &c = m.points[std::size_t(q[2])],
            &d = m.points[std::size_t(q[3])];
    const double ratio = tet_radius_edge_ratio(a, b, c, d);
    r.max_radius_edge_ratio = std::max(r.max_radius_edge_ratio, ratio);
    sum_ratio += ratio;
    r.max_circumradius = std::max(r.max_circumradius, tet_circumradius(a, b, c, d));
    const double edges[6] = {0.6, 1, 1.5, 2, 3, 5};
    std::size_t bin = 0;
    while (bin + 1 < 6 && ratio >= edges[bin + 1]) ++bin;
    ++r.ratio_histogram[bin];
    const auto cosines = tet_dihedral_cosines(a, b, c, d);  // two acos, not six
    const auto [cmin, cmax] = std::minmax_element(cosines.begin(), cosines.end());
    const double lo = dihedral_degrees(*cmax), hi = dihedral_degrees(*cmin);
    r.min_dihedral = std::min(r.min_dihedral, lo);
    r.max_dihedral = std::max(r.max_dihedral, hi);
    if (lo < 10) ++r.under_10_degrees;
    ++r.min_dihedral_histogram[std::min<std::size_t>(8, std::size_t(lo / 10))];
    const double vol = tet_orient(a, b, c, d) / 6;
    const int region = t < m.tet_region.size() ? m.tet_region[t] : 1;
    r.volume_by_region[region] += vol;
    TetQualityReport::Region& g = r.by_region[region];
    ++g.tetrahedra;
    g.max_radius_edge_ratio = std::max(g.max_radius_edge_ratio, ratio);
    g.min_dihedral = std::min(g.min_dihedral, lo);
    r.total_volume += vol;
  }
  r.mean_radius_edge_ratio = sum_ratio / double(m.tets.size());
  return r;
}

Json TetQualityReport::to_json() const {
  Json j = Json::object();
  j["tetrahedra"] = tetrahedra;
  j["max_radius_edge_ratio"] = max_radius_edge_ratio;
  j["mean_radius_edge_ratio"] = mean_radius_edge_ratio;
  j["max_circumradius"] = max_circumradius;
  j["min_dihedral_degrees"] = min_dihedral;
  j["max_dihedral_degrees"] = max_dihedral;
  j["share_dihedral_under_10"] = share_under_10();
  Json h = Json::array();
  for (std::size_t n : min_dihedral_histogram) h.push_back(n);
  j["min_dihedral_histogram_10deg"] = h;
  Json rh = Json::array();
  for (std::size_t n : ratio_histogram) rh.push_back(n);
  j["radius_edge_histogram"] = rh;  // [0.6,1) [1,1.5) [1.5,2) [2,3) [3,5) >=5
  Json vol = Json::object();
  for (const auto& [region, v] : volume_by_region) vol[std::to_string(region)] = v;
  j["volume_by_region"] = vol;
  j["volume"] = total_volume;
  return j;
}

TetConformity tet_conformity(const TetMesh& m) {
  TetConformity c;
  const int n = int(m.points.size());
  std::vector<Face> faces;
  faces.reserve(m.tets.size() * 4);
  std::vector<std::array<int, 4>> sorted;
  sorted.reserve(m.tets.size());
  for (const auto& q : m.tets) {
    if (std::any_of(q.begin(), q.end(), [n](int v) { return v < 0 || v >= n; })) {
      ++c.bad_ids;
      continue;
    }
    if (!(tet_orient(m.points[std::size_t(q[0])], m.points[std::size_t(q[1])], m.points[std::size_t(q[2])],
                     m.points[std::size_t(q[3])]) > 0))
      ++c.nonpositive;
    auto s = q;
    std::sort(s.begin(), s.end());
    sorted.push_back(s);
    add_faces(q, faces);
  }
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i) c.duplicates += sorted[i] == sorted[i - 1];
  for_each_face(faces, [&c](const Face* f, std::size_t count) {
    if (count == 1) ++c.boundary_faces;
    else if (count == 2) {
      ++c.interior_faces;
      if (even(f[0].tri) == even(f[1].tri)) ++c.inconsistent_faces;
    } else ++c.overfull_faces;
  });
  return c;
}

Json TetConformity::to_json() const {
  Json j = Json::object();
  j["conforming"] = ok();
  j["nonpositive_tetrahedra"] = nonpositive;
  j["duplicate_tetrahedra"] = duplicates;
  j["faces_in_more_than_two"] = overfull_faces;
  j["faces_same_orientation_twice"] = inconsistent_faces;
  j["bad_vertex_ids"] = bad_ids;
  j["interior_faces"] = interior_faces;
  j["boundary_faces"] = boundary_faces;
  return j;
}

std::vector<std::array<int, 3>> tet_boundary(const TetMesh& m, int region) {
  std::vector<Face> faces;
  faces.reserve(m.tets.size() * 4);
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    if (region == 0 || (t < m.tet_region.size() ? m.tet_region[t] : 1) == region) add_faces(m.tets[t], faces);
  std::vector<std::array<int, 3>> out;
  for_each_face(faces, [&out](const Face* f, std::size_t count) {
    if (count == 1) out.push_back(f->tri);
  });
  std::sort(out.begin(), out.end());
  return out;
}

void region_interfaces(const TetMesh& m, std::vector<std::array<int, 3>>& triangles,
                       std::vector<std::array<std::int32_t, 2>>& pairs) {
  std::vector<Face> faces;
  faces.reserve(m.tets.size() * 4);
  for (std::size_t t = 0; t < m.tets.size(); ++t) add_faces(m.tets[t], faces, t < m.tet_region.size() ? m.tet_region[t] : 1);
  for_each_face(faces, [&](const Face* f, std::size_t count) {
    if (count > 2) return;
    const Face& hi = count == 1 || f[0].region > f[1].region ? f[0] : f[1];  // tri: outward from its tetrahedron
    const int lo = count == 1 ? 0 : std::min(f[0].region, f[1].region);
    if (hi.region == lo) return;
    triangles.push_back(hi.tri);
    pairs.push_back({std::int32_t(hi.region), std::int32_t(lo)});
  });
}

std::string boundary_mismatch(const TetMesh& m) {
  // A triangle up to rotation (its smallest vertex first, the cycle kept),
  // and as a set of vertices.
  auto oriented = [](std::array<int, 3> t) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
  };
  auto sorted = [](std::array<int, 3> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  auto region = [](const std::vector<int>& r, std::size_t k) { return k < r.size() ? r[k] : 1; };
  std::set<int> regions;
  for (std::size_t t = 0; t < m.tets.size(); ++t) regions.insert(region(m.tet_region, t));
  // Every region's boundary faces, oriented out of it, and all of them as sets.
  std::set<std::pair<int, std::array<int, 3>>> out_of;
  std::set<std::array<int, 3>> faces;
  for (const int r : regions)
    for (const auto& f : tet_boundary(m, r)) {
      out_of.insert({r, oriented(f)});
      faces.insert(sorted(f));
    }
  std::set<std::array<int, 3>> stated;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const int r = region(m.triangle_region, t);
    if (!out_of.count({r, oriented(m.triangles[t])}))
      return "triangle " + std::to_string(t) + " (region " + std::to_string(r) +
             ") is not a face of region " + std::to_string(r) + "'s boundary oriented out of it";
    if (!stated.insert(sorted(m.triangles[t])).second)
      return "triangle " + std::to_string(t) + " (region " + std::to_string(r) + ") states a boundary face twice";
  }
  if (stated.size() != faces.size())
    return std::to_string(faces.size() - stated.size()) + " face(s) of the regions' boundaries not among the triangles";
  return "";
}

} // namespace imgmesh
