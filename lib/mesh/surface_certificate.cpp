// certify_surface: a short driver over the checks surface_certificate.hpp
// lists, each a function here; the geometry through SurfaceGeometry
// (embedding.cpp, CGAL), the placing and pairing through match_components
// (correspondence.cpp).
#include "mesh/surface_certificate.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace imgmesh {

namespace {

using C = SurfaceCertificate;

std::string number_text(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

// "mesh component 3" or "mesh components 0, 2 and 5" (the first ten), for
// the components where flag holds.
template <class Flag> std::string components_where(std::size_t n, Flag flag) {
  std::vector<std::size_t> cs;
  for (std::size_t c = 0; c < n; ++c)
    if (flag(c)) cs.push_back(c);
  std::string s = cs.size() == 1 ? "mesh component " : "mesh components ";
  for (std::size_t i = 0; i < cs.size() && i < 10; ++i)
    s += (i == 0 ? "" : i + 1 == cs.size() ? " and " : ", ") + std::to_string(cs[i]);
  if (cs.size() > 10) s += " and " + std::to_string(cs.size() - 10) + " more";
  return s;
}

void set(C& c, int check, bool held, const std::string& why = "") {
  c.state[std::size_t(check)] = held ? 1 : 0;
  if (!held) c.why[std::size_t(check)] = why;
}

// closed, manifold and the consistent half of oriented, from the topology.
void check_combinatorics(C& c) {
  const MeshTopology& t = c.topology;
  const std::size_t n = t.components.size();
  if (n == 0) {
    set(c, C::kClosed, false, "no triangle");
    return;
  }
  set(c, C::kClosed, t.closed,
      std::to_string(t.boundary_edges) + " edge(s) in one triangle only, on " +
          components_where(n, [&](std::size_t k) { return !t.components[k].closed; }));
  set(c, C::kManifold, t.manifold,
      std::to_string(t.nonmanifold_edges) + " edge(s) in more than two triangles, " +
          std::to_string(t.nonmanifold_vertices) + " vertex(es) whose triangles are not one fan, on " +
          components_where(n, [&](std::size_t k) { return !t.components[k].manifold; }));
  if (!t.manifold) return;  // orientation is a manifold's
  const bool orientable = std::all_of(t.components.begin(), t.components.end(),
                                      [](const ComponentTopology& k) { return k.orientable; });
  set(c, C::kOriented, t.oriented,
      std::to_string(t.inconsistent_edges) + " edge(s) crossed the same way by both its triangles, on " +
          components_where(n, [&](std::size_t k) { return !t.components[k].oriented; }) +
          (orientable ? "" : " (not all orientable)"));
}

// The outward half of oriented: signed volumes against the nesting (depth:
// per component, how many others enclose it).
void check_outward(C& c, const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                   std::vector<int> depth) {
  const MeshTopology& t = c.topology;
  const std::size_t n = t.components.size();
  c.volume.assign(n, 0.0);
  for (const auto& tri : triangles) {
    const int k = t.component_of[std::size_t(tri[0])];
    // About the component's first vertex: the volume of far meshes keeps its digits.
    const Vec3& o = points[t.components[std::size_t(k)].first_vertex];
    Vec3 a, b, d;
    for (int i = 0; i < 3; ++i) {
      a[i] = points[std::size_t(tri[0])][i] - o[i];
      b[i] = points[std::size_t(tri[1])][i] - o[i];
      d[i] = points[std::size_t(tri[2])][i] - o[i];
    }
    c.volume[std::size_t(k)] += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
                                 a[2] * (b[0] * d[1] - b[1] * d[0])) / 6;
  }
  c.depth = std::move(depth);
  std::string why;
  for (std::size_t k = 0; k < n && why.empty(); ++k) {
    const bool outer = c.depth[k] % 2 == 0;
    if (outer ? c.volume[k] > 0 : c.volume[k] < 0) continue;
    why = "mesh component " + std::to_string(k) + " points " + (c.volume[k] > 0 ? "outward" : c.volume[k] < 0 ? "inward" : "nowhere") +
          " (signed volume " + number_text(c.volume[k]) + ") and " + std::to_string(c.depth[k]) +
          " other component(s) enclose it: " + (outer ? "an outer surface points out" : "a cavity's surface points in");
  }
  set(c, C::kOriented, why.empty(), why);
}

void check_intersections(C& c, const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                         std::size_t cap) {
  const SelfIntersections& s = c.intersections = summarize_intersections(soup_crossing_pairs(points, triangles, cap), cap);
  if (s.pairs == 0) return set(c, C::kIntersections, true);
  auto comp = [&](std::size_t t) { return std::to_string(c.topology.component_of[std::size_t(triangles[t][0])]); };
  std::string why;
  if (s.degenerate)
    why = std::to_string(s.degenerate) + " degenerate triangle(s) (collinear corners)" +
          (s.first[0] == s.first[1] ? ", the first triangle " + std::to_string(s.first[0]) + " of mesh component " + comp(s.first[0]) : "");
  const std::size_t crossing = s.pairs - s.degenerate;
  if (crossing)
    why += (why.empty() ? "" : "; ") + std::string(s.capped ? "at least " : "") + std::to_string(crossing) +
           " pair(s) of triangles meet other than in a shared edge or vertex" +
           (s.first[0] != s.first[1] ? ", the first triangles " + std::to_string(s.first[0]) + " and " +
                                           std::to_string(s.first[1]) + " of mesh components " + comp(s.first[0]) +
                                           " and " + comp(s.first[1])
                                     : "");
  set(c, C::kIntersections, false, why);
}

// Each matched pair oriented alike: the mesh's nesting is the voxels'.
void check_nesting(C& c) {
  for (std::size_t m = 0; m < c.correspondence.mesh.size(); ++m) {
    auto& ms = c.correspondence.mesh[m];
    if (ms.verdict != "ok" && ms.verdict != "euler differs") continue;
    if ((c.volume[m] > 0) != (c.correspondence.boundary[std::size_t(ms.boundary)].volume > 0)) ms.verdict = "nesting differs";
  }
}

// placed, matched and topology from the verdicts; per component ok.
void settle(C& c) {
  const auto& r = c.correspondence;
  auto any = [&](std::initializer_list<const char*> mesh, std::initializer_list<const char*> image) {
    for (const auto& m : r.mesh)
      for (const char* v : mesh) if (m.verdict == v) return true;
    for (const auto& b : r.boundary)
      for (const char* v : image) if (b.verdict == v) return true;
    return false;
  };
  set(c, C::kPlaced, !any({"unplaced"}, {}), r.failed_guarantee({"unplaced"}));
  set(c, C::kMatched, !any({"tie", "matched twice", "nesting differs"}, {"unmatched", "matched twice"}),
      r.failed_guarantee({"tie", "nesting differs", "unmatched", "matched twice"}));
  bool same = true;
  for (const auto& m : r.mesh) same = same && (m.boundary < 0 || m.euler == r.boundary[std::size_t(m.boundary)].euler);
  set(c, C::kTopology, same, r.failed_guarantee({"euler differs"}));
  if (!same && c.why[C::kTopology].empty()) c.why[C::kTopology] = "a mesh component's Euler characteristic differs from its bdCA(X) component's";
  const std::size_t n = c.topology.components.size();
  c.component_ok.assign(n, 1);
  for (std::size_t m = 0; m < n; ++m) {
    const ComponentTopology& k = c.topology.components[m];
    const bool outward = c.volume.empty() || (c.depth[m] % 2 == 0 ? c.volume[m] > 0 : c.volume[m] < 0);
    c.component_ok[m] = k.closed && k.manifold && k.oriented && outward && r.mesh[m].verdict == "ok";
  }
}

} // namespace

double default_place_tolerance(const Geometry& grid) {
  return std::sqrt(grid.spacing[0] * grid.spacing[0] + grid.spacing[1] * grid.spacing[1] + grid.spacing[2] * grid.spacing[2]);
}

const char* SurfaceCertificate::name(int check) {
  static const char* const names[kChecks] = {"closed", "manifold", "oriented", "intersections",
                                             "placed", "matched", "topology"};
  return check >= 0 && check < kChecks ? names[check] : "none";
}

int SurfaceCertificate::first_failed() const {
  for (int k = 0; k < kChecks; ++k)
    if (state[std::size_t(k)] != 1) return k;
  return kChecks;
}

std::string SurfaceCertificate::failure() const {
  const int k = first_failed();
  if (k == kChecks) return "";
  const std::string& w = why[std::size_t(k)];
  return std::string(name(k)) + ": " + (state[std::size_t(k)] < 0 ? "not checked" : w.empty() ? "fails" : w);
}

Json SurfaceCertificate::to_json() const {
  Json j = Json::object();
  j["verdict"] = ok() ? "ok" : name(first_failed());
  if (!ok()) j["failure"] = failure();
  j["place_tolerance"] = correspondence.tolerance;
  Json checks = Json::object();
  for (int k = 0; k < kChecks; ++k) checks[name(k)] = state[std::size_t(k)] < 0 ? Json() : Json(state[std::size_t(k)] == 1);
  j["checks"] = checks;
  if (state[kIntersections] >= 0) {
    j["intersecting_pairs"] = intersections.pairs - intersections.degenerate;
    j["degenerate_triangles"] = intersections.degenerate;
  }
  if (!volume.empty()) {
    Json cs = Json::array();
    for (std::size_t k = 0; k < volume.size(); ++k) {
      Json o = Json::object();
      o["signed_volume"] = volume[k];
      o["enclosed_by"] = depth[k];
      cs.push_back(o);
    }
    j["components"] = cs;
  }
  return j;
}

SurfaceCertificate certify_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                   const Geometry& grid, const VoxelBoundary& boundary, const MeshTopology& bt,
                                   const CertificateOptions& options) {
  SurfaceCertificate c;
  c.state.fill(-1);
  const double tol = options.place_tolerance > 0 ? options.place_tolerance : default_place_tolerance(grid);
  c.topology = mesh_topology(points.size(), triangles);
  // CGAL's boxes and predicates need numbers (the readers refuse NaN already).
  for (std::size_t v = 0; v < points.size(); ++v)
    if (c.topology.component_of[v] >= 0 &&
        !(std::isfinite(points[v][0]) && std::isfinite(points[v][1]) && std::isfinite(points[v][2])))
      throw Error("vertex " + std::to_string(v) + " has a coordinate that is not a finite number");
  check_combinatorics(c);
  c.correspondence = match_components(c.topology, points, grid, boundary, bt, tol);
  const bool geometry = c.state[C::kClosed] == 1 && c.state[C::kManifold] == 1 && c.state[C::kOriented] == 1;
  if (geometry) {
    // The intersections first, on the triangles alone (no Surface_mesh
    // beside them): the mesher calls this at its peak.
    if (options.intersections)
      check_intersections(c, points, triangles, options.intersections_cap);
    else
      set(c, C::kIntersections, true);
    // The nesting from the caller when it knows it, else by rays (along
    // lines, nesting_depths: no CGAL mesh or tree unless one grazes).
    const std::size_t n = c.topology.components.size();
    std::vector<int> depth = n > 1 && options.nesting ? options.nesting(c.topology) : std::vector<int>();
    if (depth.size() != n) {
      depth.assign(n, 0);
      if (n > 1) {
        std::vector<int> component(triangles.size());
        for (std::size_t t = 0; t < triangles.size(); ++t) component[t] = c.topology.component_of[std::size_t(triangles[t][0])];
        depth = nesting_depths(points, triangles, component, n, c.topology.component_of);
      }
    }
    check_outward(c, points, triangles, std::move(depth));
    check_nesting(c);
  }
  settle(c);
  return c;
}

void check_surface_intersections(SurfaceCertificate& c, const std::vector<Vec3>& points,
                                 const std::vector<std::array<int, 3>>& triangles, std::size_t cap) {
  if (c.state[C::kIntersections] < 0) return;
  check_intersections(c, points, triangles, cap);
}

} // namespace imgmesh
