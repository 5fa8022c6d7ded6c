// The certificate by correspondence in 3D (match_components): mesh
// components placed on bdCA(X)'s by the distance of every vertex to the
// voxel faces, matched one to one; and the result type it shares with the
// 2D form (topology_planar.cpp), its verdicts, JSON and message.
//
// Distances: bdCA(X) is a union of unit squares on the lattice of voxel
// corners, each known by its lowest corner and normal axis
// (VoxelBoundary::faces), so the squares near a point are found by looking
// up the corners in a box around it (rows of the sorted lattice ids), and
// the distance to a square is separable: clamp each index coordinate to the
// square, scale by the spacing (the direction matrix is orthonormal).
#include "mesh/topology.hpp"

#include "mesh/topology_detail.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

namespace imgmesh {

namespace {

class QuadSearch {
public:
  QuadSearch(const Geometry& grid, const VoxelBoundary& b, const MeshTopology& bt) : grid_(grid), b_(b), bt_(bt) {}

  // f(component, squared world distance) for every square of bdCA(X) within
  // r (world units) of p; possibly several times for one component.
  template <class F> void near(const Vec3& p, double r, F f) const {
    const Vec3 ci = grid_.continuous_index(p);
    double l[3];
    long long lo[3], hi[3];
    double box = 1;
    for (int a = 0; a < 3; ++a) {
      l[a] = ci[a] + 0.5;  // corner i sits at voxel index i - 1/2
      const double ra = r / grid_.spacing[a];
      if (!std::isfinite(l[a]) || !(l[a] + ra >= 0) || !(l[a] - ra - 1 <= double(b_.lattice[a]))) return;
      lo[a] = std::max(0LL, (long long)std::ceil(l[a] - ra) - 1);
      hi[a] = std::min((long long)b_.lattice[a] - 1, (long long)std::floor(l[a] + ra));
      if (lo[a] > hi[a]) return;
      box *= double(hi[a] - lo[a] + 1);
    }
    const double r2 = r * r;
    auto visit = [&](std::size_t v) {
      const std::uint8_t bits = b_.faces[v];
      if (!(bits & 7)) return;
      const auto c = b_.corner(v);
      for (int a = 0; a < 3; ++a) {
        if (!(bits & (VoxelBoundary::kNormalAxis << a))) continue;
        double d2 = 0;
        for (int x = 0; x < 3; ++x) {
          const double from = double(c[std::size_t(x)]), to = x == a ? from : from + 1;
          const double d = (l[x] - std::clamp(l[x], from, to)) * grid_.spacing[x];
          d2 += d * d;
        }
        if (d2 <= r2) f(bt_.component_of[v], d2);
      }
    };
    const auto& ids = b_.lattice_ids;
    // A box with more lattice points than there are corners: every corner.
    if (box > double(ids.size())) {
      for (std::size_t v = 0; v < ids.size(); ++v) visit(v);
      return;
    }
    const std::uint64_t W = b_.lattice[0], H = b_.lattice[1];
    auto it = ids.begin();
    for (long long k = lo[2]; k <= hi[2]; ++k)
      for (long long j = lo[1]; j <= hi[1]; ++j) {
        const std::uint64_t row = (std::uint64_t(k) * H + std::uint64_t(j)) * W;
        it = std::lower_bound(it, ids.end(), row + std::uint64_t(lo[0]));
        for (; it != ids.end() && *it <= row + std::uint64_t(hi[0]); ++it) visit(std::size_t(it - ids.begin()));
      }
  }

private:
  const Geometry& grid_;
  const VoxelBoundary& b_;
  const MeshTopology& bt_;
};

// A bdCA(X) component a mesh component may lie on, and its farthest vertex.
struct Candidate {
  int component;
  double d2;  // the farthest vertex so far, squared
  std::size_t vertex;
};

// Placement: each mesh component's candidates are the components within the
// tolerance of its first vertex, less those that a later vertex is beyond
// the tolerance of. Per vertex, a search within a small radius first (a
// vertex on S is within half a voxel diagonal), then within the tolerance
// for the candidates not yet found.
void place_vertices(ComponentCorrespondence& r, const MeshTopology& mesh, const std::vector<Vec3>& points,
                    const QuadSearch& search, double tol, double small, std::vector<std::vector<Candidate>>& cands) {
  std::vector<char> started(mesh.components.size(), 0);
  std::vector<double> best;  // per candidate of the current vertex: nearest square, squared
  for (std::size_t v = 0; v < points.size(); ++v) {
    const int m = mesh.component_of[v];
    if (m < 0) continue;
    auto& ms = r.mesh[std::size_t(m)];
    ++ms.vertices;
    auto& cs = cands[std::size_t(m)];
    if (!started[std::size_t(m)]) {
      started[std::size_t(m)] = 1;
      ms.far_vertex = v;
      ms.far_point = points[v];
      search.near(points[v], tol, [&](int c, double d2) {
        if (c < 0) return;
        auto it = std::find_if(cs.begin(), cs.end(), [&](const Candidate& k) { return k.component == c; });
        if (it == cs.end()) cs.push_back({c, d2, v});
        else it->d2 = std::min(it->d2, d2);
      });
      std::sort(cs.begin(), cs.end(), [](const Candidate& a, const Candidate& b) { return a.component < b.component; });
      continue;
    }
    if (cs.empty()) continue;  // unplaced already
    best.assign(cs.size(), std::numeric_limits<double>::infinity());
    auto record = [&](int c, double d2) {
      for (std::size_t i = 0; i < cs.size(); ++i)
        if (cs[i].component == c) best[i] = std::min(best[i], d2);
    };
    search.near(points[v], small, record);
    if (std::any_of(best.begin(), best.end(), [](double d) { return std::isinf(d); })) search.near(points[v], tol, record);
    std::vector<Candidate> kept;
    for (std::size_t i = 0; i < cs.size(); ++i) {
      if (std::isinf(best[i])) continue;
      kept.push_back(cs[i]);
      if (best[i] > kept.back().d2) kept.back().d2 = best[i], kept.back().vertex = v;
    }
    if (kept.empty()) {
      ms.far_vertex = v;
      ms.far_point = points[v];
      ms.near = cs.front().component;
    }
    cs.swap(kept);
  }
}

// Each placed mesh component to its nearest candidate (by its farthest
// vertex); equally near candidates are a tie.
void choose(ComponentCorrespondence& r, const std::vector<Vec3>& points, const std::vector<std::vector<Candidate>>& cands) {
  for (std::size_t m = 0; m < r.mesh.size(); ++m) {
    auto& ms = r.mesh[m];
    const auto& cs = cands[m];
    if (cs.empty()) { ms.verdict = "unplaced"; continue; }
    const auto best = std::min_element(cs.begin(), cs.end(), [](const Candidate& a, const Candidate& b) { return a.d2 < b.d2; });
    for (const Candidate& c : cs)
      if (c.d2 == best->d2) ms.tied.push_back(c.component);
    if (ms.tied.size() > 1) { ms.verdict = "tie"; continue; }
    ms.tied.clear();
    ms.boundary = best->component;
    ms.placed = ms.vertices;
    ms.distance = std::sqrt(best->d2);
    ms.far_vertex = best->vertex;
    ms.far_point = points[best->vertex];
  }
}

// Signed volume of each bdCA(X) component in voxels: the divergence theorem
// with the field (x, 0, 0) over its squares normal to x.
void boundary_volumes(ComponentCorrespondence& r, const VoxelBoundary& b, const MeshTopology& bt) {
  for (std::size_t v = 0; v < b.faces.size(); ++v) {
    const std::uint8_t bits = b.faces[v];
    if (!(bits & VoxelBoundary::kNormalAxis) || bt.component_of[v] < 0) continue;
    const long long x = (long long)(b.lattice_ids[v] % b.lattice[0]);
    r.boundary[std::size_t(bt.component_of[v])].volume += bits & VoxelBoundary::kPlus ? x : -x;
  }
}

// One to one and the same Euler characteristic, for the components placed.
void pair_up(ComponentCorrespondence& r) {
  for (std::size_t m = 0; m < r.mesh.size(); ++m)
    if (r.mesh[m].boundary >= 0) r.boundary[std::size_t(r.mesh[m].boundary)].matched_by.push_back(int(m));
  for (auto& b : r.boundary) b.verdict = b.matched_by.empty() ? "unmatched" : b.matched_by.size() > 1 ? "matched twice" : "ok";
  for (auto& m : r.mesh) {
    if (!m.verdict.empty()) continue;
    if (r.boundary[std::size_t(m.boundary)].matched_by.size() > 1) m.verdict = "matched twice";
    else if (m.euler != r.boundary[std::size_t(m.boundary)].euler) m.verdict = "euler differs";
    else m.verdict = "ok";
  }
}

} // namespace

Vec3 corner_position(const Geometry& grid, const VoxelBoundary& b, std::size_t v) {
  const auto c = b.corner(v);
  return grid.world(double(c[0]) - 0.5, double(c[1]) - 0.5, double(c[2]) - 0.5);
}

ComponentCorrespondence match_components(const MeshTopology& mesh, const std::vector<Vec3>& points,
                                         const Geometry& grid, const VoxelBoundary& boundary,
                                         const MeshTopology& bt, double tolerance) {
  if (mesh.component_of.size() != points.size() || bt.component_of.size() != boundary.lattice_ids.size() ||
      boundary.faces.size() != boundary.lattice_ids.size())
    throw Error("match_components: vertex labels do not fit the points");
  if (!(tolerance > 0) || !std::isfinite(tolerance)) throw Error("match_components: the tolerance must be positive");
  ComponentCorrespondence r;
  r.tolerance = tolerance;
  r.mesh.resize(mesh.components.size());
  r.boundary.resize(bt.components.size());
  for (std::size_t c = 0; c < mesh.components.size(); ++c) r.mesh[c].euler = mesh.components[c].euler;
  for (std::size_t c = 0; c < bt.components.size(); ++c) r.boundary[c].euler = bt.components[c].euler;
  boundary_volumes(r, boundary, bt);
  std::vector<std::vector<Candidate>> cands(mesh.components.size());
  const double small = std::min(tolerance, 0.75 * std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]}));
  place_vertices(r, mesh, points, QuadSearch(grid, boundary, bt), tolerance, small, cands);
  choose(r, points, cands);
  pair_up(r);
  return r;
}

void tally_votes(ComponentCorrespondence& r, std::vector<std::pair<int, int>>& votes) {
  std::sort(votes.begin(), votes.end());
  for (std::size_t i = 0; i < votes.size();) {
    std::size_t j = i;
    while (j < votes.size() && votes[j] == votes[i]) ++j;
    auto& ms = r.mesh[std::size_t(votes[i].first)];
    ms.placed += j - i;
    if (j - i > ms.votes) { ms.votes = j - i; ms.boundary = votes[i].second; }
    i = j;
  }
  for (std::size_t m = 0; m < r.mesh.size(); ++m)
    if (r.mesh[m].boundary >= 0) r.boundary[std::size_t(r.mesh[m].boundary)].matched_by.push_back(int(m));
  for (auto& b : r.boundary) b.verdict = b.matched_by.empty() ? "unmatched" : b.matched_by.size() > 1 ? "matched twice" : "ok";
  for (auto& m : r.mesh) {
    if (m.boundary < 0) m.verdict = "unplaced";
    else if (r.boundary[std::size_t(m.boundary)].matched_by.size() > 1) m.verdict = "matched twice";
    else if (m.euler != r.boundary[std::size_t(m.boundary)].euler) m.verdict = "euler differs";
    else m.verdict = "ok";
  }
}

bool ComponentCorrespondence::matches() const {
  for (const auto& m : mesh) if (m.verdict != "ok") return false;
  for (const auto& b : boundary) if (b.verdict != "ok") return false;
  return true;
}

Json ComponentCorrespondence::to_json() const {
  Json j = Json::object();
  j["matches"] = matches();
  // Planar: mesh regions placed by their faces against pixel regions.
  j["planar"] = planar;
  if (!planar) j["place_tolerance"] = tolerance;
  Json ms = Json::array();
  for (const auto& m : mesh) {
    Json o = Json::object();
    if (planar) o["label"] = m.label;
    o["boundary_component"] = m.boundary;
    o["euler"] = m.euler;
    if (m.boundary >= 0) o["boundary_euler"] = boundary[std::size_t(m.boundary)].euler;
    o[planar ? "faces" : "vertices"] = m.vertices;
    o["placed"] = m.placed;
    if (planar) o["votes"] = m.votes;
    else {
      o["max_distance"] = m.distance;
      o["far_vertex"] = m.far_vertex;
      if (!m.tied.empty()) o["tied"] = m.tied;
    }
    o["verdict"] = m.verdict;
    ms.push_back(o);
  }
  j["mesh_components"] = ms;
  Json bs = Json::array();
  for (const auto& b : boundary) {
    Json o = Json::object();
    if (planar) o["label"] = b.label;
    o["euler"] = b.euler;
    if (!planar) o["volume_voxels"] = b.volume;
    o["matched_by"] = b.matched_by;
    o["verdict"] = b.verdict;
    bs.push_back(o);
  }
  j["boundary_components"] = bs;
  return j;
}

namespace {

std::string point_text(const Vec3& p) {
  char b[96];
  std::snprintf(b, sizeof b, "(%.6g, %.6g, %.6g)", p[0], p[1], p[2]);
  return b;
}

std::string number_text(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

std::string list_text(const std::vector<int>& xs) {
  std::string s;
  for (std::size_t i = 0; i < xs.size(); ++i)
    s += (i == 0 ? "" : i + 1 == xs.size() ? " and " : ", ") + std::to_string(xs[i]);
  return s;
}

} // namespace

std::string ComponentCorrespondence::failed_guarantee(const std::vector<std::string>& verdicts) const {
  // One line: the first failures, then how many more (the JSON has them all).
  constexpr std::size_t kNamed = 10;
  std::string s;
  std::size_t failures = 0;
  auto add = [&](const std::string& x) {
    if (failures++ < kNamed) s += (s.empty() ? "" : "; ") + x;
  };
  auto wanted = [&](const std::string& v) {
    return v != "ok" && (verdicts.empty() || std::find(verdicts.begin(), verdicts.end(), v) != verdicts.end());
  };
  // 3D: mesh components against bdCA(X)'s; planar: regions of one label.
  auto mesh_name = [&](std::size_t i) {
    return planar ? "mesh region " + std::to_string(i) + " (label " + std::to_string(mesh[i].label) + ")"
                  : "mesh component " + std::to_string(i);
  };
  auto image_name = [&](std::size_t i) {
    return planar ? "pixel region " + std::to_string(i) + " (label " + std::to_string(boundary[i].label) + ")"
                  : "bdCA(X) component " + std::to_string(i);
  };
  const std::string tol = number_text(tolerance);
  for (std::size_t i = 0; i < mesh.size(); ++i) {
    const auto& m = mesh[i];
    const std::string name = mesh_name(i);
    if (!wanted(m.verdict)) continue;
    if (m.verdict == "unplaced" && planar) add(name + ": no face lies on a pixel of its label");
    else if (m.verdict == "unplaced" && m.near < 0)
      add(name + ": vertex " + std::to_string(m.far_vertex) + " at " + point_text(m.far_point) +
          " is farther than " + tol + " (the place tolerance) from bdCA(X)");
    else if (m.verdict == "unplaced")
      add(name + ": vertex " + std::to_string(m.far_vertex) + " at " + point_text(m.far_point) +
          " is farther than " + tol + " (the place tolerance) from " + image_name(std::size_t(m.near)) +
          ", which its earlier vertices lie near");
    else if (m.verdict == "tie")
      add(name + ": as near to bdCA(X) components " + list_text(m.tied) + " (a tie, not broken)");
    else if (m.verdict == "nesting differs")
      add(name + ": oriented as " +
          (boundary[std::size_t(m.boundary)].volume > 0 ? std::string("a cavity's surface") : std::string("an outer surface")) +
          ", its " + image_name(std::size_t(m.boundary)) + " is " +
          (boundary[std::size_t(m.boundary)].volume > 0 ? "an outer surface" : "a cavity's surface"));
    else if (m.verdict == "euler differs")
      add(name + ": euler " + std::to_string(m.euler) + ", its " + image_name(std::size_t(m.boundary)) + " has " +
          std::to_string(boundary[std::size_t(m.boundary)].euler));
  }
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    const auto& b = boundary[i];
    const std::string name = image_name(i);
    if (!wanted(b.verdict)) continue;
    if (b.verdict == "unmatched")
      add(name + " (euler " + std::to_string(b.euler) + (planar ? "): no mesh region" : "): no mesh component"));
    else if (b.verdict == "matched twice") {
      std::string who;
      for (int m : b.matched_by) who += (who.empty() ? "" : ", ") + std::to_string(m);
      add(name + (planar ? ": matched by mesh regions " : ": matched by mesh components ") + who);
    }
  }
  if (failures > kNamed) s += "; and " + std::to_string(failures - kNamed) + " more";
  return s;
}

} // namespace imgmesh
