#include "meshinfo/label_report.hpp"

#include "mesh/topology.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace imgmesh {

namespace {

using P3 = std::array<double, 3>;

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The triangle's smallest angle in degrees (0 when degenerate).
double smallest_angle(const P3& a, const P3& b, const P3& c) {
  const P3* v[3] = {&a, &b, &c};
  double least = 180;
  for (int i = 0; i < 3; ++i) {
    const P3 u = sub(*v[(i + 1) % 3], *v[i]), w = sub(*v[(i + 2) % 3], *v[i]);
    const double nu = std::sqrt(dot(u, u)), nw = std::sqrt(dot(w, w));
    if (nu == 0 || nw == 0) return 0;
    least = std::min(least, std::acos(std::clamp(dot(u, w) / (nu * nw), -1.0, 1.0)) * 180 / M_PI);
  }
  return least;
}

// Triangles as one piece: their count, area, smallest angle.
struct Sums {
  std::size_t triangles = 0;
  double area = 0, volume6 = 0, min_angle = 180;
};

// Edge-connected pieces of a set of triangles.
std::size_t pieces(const std::vector<std::array<int, 3>>& tris) {
  std::vector<std::size_t> parent(tris.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<std::pair<int, int>, std::size_t> first;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = tris[t][std::size_t(e)], b = tris[t][std::size_t((e + 1) % 3)];
      const auto [it, fresh] = first.try_emplace({std::min(a, b), std::max(a, b)}, t);
      if (!fresh) parent[find(t)] = find(it->second);
    }
  std::size_t n = 0;
  for (std::size_t t = 0; t < tris.size(); ++t) n += find(t) == t;
  return n;
}

} // namespace

Json label_report(const std::vector<P3>& points, const std::vector<std::array<int, 3>>& triangles,
                  const std::vector<std::array<std::int32_t, 2>>& pairs) {
  std::map<std::int32_t, std::vector<std::array<int, 3>>> of_label;  // oriented out of the label (0: of the union)
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::array<int, 3>>> of_pair;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto [behind, front] = pairs[t];
    const std::array<int, 3>& f = triangles[t];
    const std::array<int, 3> r{f[0], f[2], f[1]};
    of_label[behind].push_back(behind == 0 ? r : f);
    of_label[front].push_back(front == 0 ? f : r);
    of_pair[{std::max(behind, front), std::min(behind, front)}].push_back(f);
  }
  const P3 o = points.empty() ? P3{0, 0, 0} : points[0];  // volumes about a vertex: less rounding far from 0
  auto sums = [&](const std::vector<std::array<int, 3>>& tris) {
    Sums s;
    for (const auto& f : tris) {
      const P3 &a = points[std::size_t(f[0])], &b = points[std::size_t(f[1])], &c = points[std::size_t(f[2])];
      const P3 n = cross(sub(b, a), sub(c, a));
      ++s.triangles;
      s.area += std::sqrt(dot(n, n)) / 2;
      s.volume6 += dot(sub(a, o), cross(sub(b, o), sub(c, o)));
      s.min_angle = std::min(s.min_angle, smallest_angle(a, b, c));
    }
    return s;
  };
  Json labels = Json::array();
  for (const auto& [label, tris] : of_label) {
    const Sums s = sums(tris);
    const MeshTopology t = mesh_topology(points.size(), tris);
    Json j = Json::object();
    j["label"] = label;
    j["triangles"] = s.triangles;
    j["components"] = t.components.size();
    j["euler"] = t.euler_list();
    j["closed"] = t.closed;
    j["manifold"] = t.manifold;
    j["oriented"] = t.oriented;
    j["area"] = s.area;
    j["volume"] = s.volume6 / 6;
    j["min_angle"] = s.min_angle;
    labels.push_back(j);
  }
  Json interfaces = Json::array();
  for (const auto& [pair, tris] : of_pair) {
    const Sums s = sums(tris);
    Json j = Json::object();
    j["pair"] = std::to_string(pair.first) + "|" + std::to_string(pair.second);
    j["triangles"] = s.triangles;
    j["patches"] = pieces(tris);
    j["area"] = s.area;
    j["min_angle"] = s.min_angle;
    interfaces.push_back(j);
  }
  Json out = Json::object();
  out["labels"] = labels;
  out["interfaces"] = interfaces;
  return out;
}

} // namespace imgmesh
