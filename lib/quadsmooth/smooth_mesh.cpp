// The quad-mesh state: the conformity check and stars, the set-up of fixed,
// sliding and feature vertices, patch save/restore, new vertices and quads,
// and the compaction back into the PlanarMesh.
#include "quad/half_plane_clip.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace imgmesh::quadsmooth_detail {

// Checks the input contract (see check_quad_mesh) and returns the stars.
Stars conforming_stars(const PlanarMesh& m, const std::string& path) {
  const long long n = static_cast<long long>(m.points.size());
  if (m.elements.empty()) throw Error("mesh has no elements", path);
  for (const auto& p : m.points)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) throw Error("non-finite point coordinate", path);
  Stars s;
  s.start.assign(std::size_t(n) + 1, 0);
  for (std::size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = m.elements[e];
    auto where = [&] { return "element " + std::to_string(e + m.first_index); };  // built only to throw
    if (el.size() != 3 && el.size() != 4) throw Error(where() + " has " + std::to_string(el.size()) + " nodes (want 3 or 4)", path);
    for (std::size_t i = 0; i < el.size(); ++i) {
      if (el[i] < 0 || el[i] >= n) throw Error(where() + ": node id out of range", path);
      for (std::size_t j = 0; j < i; ++j)
        if (el[i] == el[j]) throw Error(where() + ": repeated node", path);
    }
    const auto& P = m.points;
    double area2 = 0;
    for (std::size_t i = 0; i < el.size(); ++i) {
      const Point2 &p = P[el[i]], &q = P[el[(i + 1) % el.size()]];
      area2 += p[0] * q[1] - p[1] * q[0];
    }
    if (!(area2 > 0)) throw Error(where() + " is clockwise or degenerate (want counter-clockwise)", path);
    for (int v : el) ++s.start[v + 1];
  }
  for (std::size_t v = 0; v < std::size_t(n); ++v) s.start[v + 1] += s.start[v];
  s.next.resize(s.start[n]);
  s.elem.resize(s.start[n]);
  std::vector<int> fill(s.start.begin(), s.start.end() - 1);
  for (std::size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = m.elements[e];
    for (std::size_t i = 0; i < el.size(); ++i) {
      const int a = el[i];
      s.next[fill[a]] = el[(i + 1) % el.size()];
      s.elem[fill[a]++] = int(e);
    }
  }
  // An edge in at most two elements with opposite orientations: no directed
  // edge twice (a third use would repeat one of the two directions).
  for (int a = 0; a < n; ++a)
    for (int i = s.start[a]; i < s.start[a + 1]; ++i)
      for (int j = i + 1; j < s.start[a + 1]; ++j) {
        if (s.next[i] != s.next[j]) continue;
        const int b = s.next[i];
        const std::string where = "edge " + std::to_string(std::min(a, b) + m.first_index) + "-" +
                                  std::to_string(std::max(a, b) + m.first_index);
        int uses = 0;
        for (int k = s.start[a]; k < s.start[a + 1]; ++k) uses += s.next[k] == b;
        for (int k = s.start[b]; k < s.start[b + 1]; ++k) uses += s.next[k] == a;
        if (uses > 2) throw Error(where + " is shared by more than two elements", path);
        throw Error(where + ": neighbouring elements are oriented inconsistently", path);
      }
  for (const auto& sg : m.segments)
    if (sg[0] < 0 || sg[0] >= n || sg[1] < 0 || sg[1] >= n) throw Error("segment id out of range", path);
  return s;
}

QuadMesh::QuadMesh(PlanarMesh& m, const SmoothOptions& opt, const Stars& stars)
    : mesh(m), points(m.points),
      split_below(std::sin(std::clamp(opt.split_below, 0.0, 45.0) * (3.14159265358979323846 / 180))) {
  const int n = int(points.size());
  vertex_quads.assign(n, {});
  fixed.assign(n, 0);
  vertex_dead.assign(n, 0);
  active.assign(n, 1);
  std::vector<int> quad_of_elem(mesh.elements.size(), -1);
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& el = mesh.elements[e];
    if (el.size() != 4) continue;
    quad_of_elem[e] = int(quads.size());
    quads.push_back({el[0], el[1], el[2], el[3]});
    quad_element.push_back(int(e));
  }
  // Feature edges: used once (boundary), between elements of different
  // region attribute, or listed as segments.
  auto region = [&](int e) {
    return mesh.element_attributes.empty() || mesh.element_attributes[e].empty() ? 0.0 : mesh.element_attributes[e][0];
  };
  for (int v = 0; v < n; ++v) {
    vertex_quads[v].reserve(stars.start[v + 1] - stars.start[v]);
    for (int i = stars.start[v]; i < stars.start[v + 1]; ++i) {
      const int e = stars.elem[i];
      if (quad_of_elem[e] >= 0) vertex_quads[v].push_back(quad_of_elem[e]);
      else fixed[v] = 1;  // triangles stay as they are
      const int t = stars.twin(v, stars.next[i]);
      if (t < 0 || region(t) != region(e)) features.insert(edge_key(v, stars.next[i]));
    }
  }
  quad_dead.assign(quads.size(), 0);
  tried.assign(quads.size(), 0);
  quad_sin_mu.resize(quads.size());
  for (std::size_t q = 0; q < quads.size(); ++q) quad_sin_mu[q] = sin_mu_of(quads[q]);
  for (const auto& s : mesh.segments) features.insert(edge_key(s[0], s[1]));
  // Segment markers of feature edges, to tell one input segment from the next.
  std::unordered_map<std::uint64_t, int> seg_marker;
  for (std::size_t i = 0; i < mesh.segments.size(); ++i)
    seg_marker[edge_key(mesh.segments[i][0], mesh.segments[i][1])] =
        mesh.segment_markers.empty() ? 0 : mesh.segment_markers[i];

  std::vector<std::vector<int>> fnb(n);  // feature neighbours
  for (std::uint64_t k : features) {
    const int a = int(k >> 32), b = int(k & 0xffffffffu);
    fnb[a].push_back(b);
    fnb[b].push_back(a);
  }
  std::vector<char> can_slide(n, 0);
  for (int v = 0; v < n; ++v) {
    if (!fnb[v].empty()) fixed[v] = 1;
    // A marked vertex off every feature edge is an input point: keep it.
    // Marked vertices on feature edges (Triangle marks the boundary) follow
    // the feature rules below, so they may slide.
    if (!mesh.point_markers.empty() && mesh.point_markers[v] != 0) fixed[v] = 1;
    if (fnb[v].size() == 2 && opt.slide_boundary && !vertex_quads[v].empty()) {
      const int u = fnb[v][0], w = fnb[v][1];
      // Only inside one straight input segment: collinear (exactly), v between
      // u and w, same segment marker on both sides, and only quads around.
      const auto mu = seg_marker.find(edge_key(u, v)), mw = seg_marker.find(edge_key(v, w));
      const bool same_marker = (mu == seg_marker.end() ? 0 : mu->second) == (mw == seg_marker.end() ? 0 : mw->second);
      const Point2 &pu = points[u], &pv = points[v], &pw = points[w];
      const double dot = (pu[0] - pv[0]) * (pw[0] - pv[0]) + (pu[1] - pv[1]) * (pw[1] - pv[1]);
      can_slide[v] = orientation(pu, pv, pw) == 0 && dot < 0 && same_marker;
    }
  }
  // Vertices on triangles stay fixed even if they could slide.
  for (const auto& el : mesh.elements)
    if (el.size() != 4)
      for (int v : el) can_slide[v] = 0;
  // Chains of sliding vertices end at fixed vertices A and B; slides are
  // computed from A and B, which never move, so no rounding accumulates.
  std::vector<char> seen(n, 0);
  for (int v = 0; v < n; ++v) {
    if (!can_slide[v] || seen[v]) continue;
    std::vector<int> chain{v};
    seen[v] = 1;
    int ends[2];
    for (int side = 0; side < 2; ++side) {
      int prev = v, cur = fnb[v][side];
      while (can_slide[cur] && !seen[cur]) {
        seen[cur] = 1;
        chain.push_back(cur);
        const int nxt = fnb[cur][0] == prev ? fnb[cur][1] : fnb[cur][0];
        prev = cur;
        cur = nxt;
      }
      ends[side] = cur;
    }
    if (ends[0] == ends[1] || can_slide[ends[0]] || can_slide[ends[1]]) continue;  // closed straight loop: impossible, be safe
    for (int c : chain) {
      // Every vertex of the chain must be collinear with the ends, exactly.
      if (orientation(points[ends[0]], points[c], points[ends[1]]) != 0) { chain.clear(); break; }
    }
    for (int c : chain) slides.push_back({c, ends[0], ends[1], fnb[c][0], fnb[c][1]});
  }
  std::size_t nf = 0;
  for (int v = 0; v < n; ++v) nf += fixed[v] && !vertex_quads[v].empty();
  fixed_vertices = nf;
}

int QuadMesh::quad_with_edge(int a, int b) const {
  for (int q : vertex_quads[a]) {
    const Quad& E = quads[q];
    for (int k = 0; k < 4; ++k)
      if (E[k] == a && E[(k + 1) & 3] == b) return q;
  }
  return -1;
}

Fan QuadMesh::fixed_fan(int v, int q0) const {
  auto corner = [&](int q) {
    int i = 0;
    while (quads[q][i] != v) ++i;
    return i;
  };
  Fan f{0, 0, false};
  double angle = 0;
  auto add = [&](int q) {
    const int i = corner(q);
    const Point2 &o = points[v], &x = points[quads[q][(i + 1) & 3]], &z = points[quads[q][(i + 3) & 3]];
    const double ux = x[0] - o[0], uy = x[1] - o[1], wx = z[0] - o[0], wy = z[1] - o[1];
    angle += std::atan2(std::fabs(ux * wy - uy * wx), ux * wx + uy * wy);
    ++f.count;
  };
  // Counter-clockwise across the edge v-z of (v, x, y, z), then clockwise
  // across v-x, each way until a feature edge or the mesh boundary.
  add(q0);
  for (int q = q0;;) {
    const int z = quads[q][(corner(q) + 3) & 3];
    const int nx = is_feature(v, z) ? -1 : quad_with_edge(v, z);
    if (nx < 0) break;
    if (nx == q0) { f.closed = true; break; }
    add(nx);
    q = nx;
  }
  if (!f.closed)
    for (int q = q0;;) {
      const int x = quads[q][(corner(q) + 1) & 3];
      const int nx = is_feature(v, x) ? -1 : quad_with_edge(x, v);
      if (nx < 0) break;
      add(nx);
      q = nx;
    }
  f.ideal = f.closed ? 4 : std::max(1, int(std::lround(angle * (2 / 3.14159265358979323846))));
  return f;
}

void QuadMesh::save_patch(std::initializer_list<int> core, Patch& pt) { save_patch(core.begin(), core.size(), pt); }

void QuadMesh::save_patch(const std::vector<int>& core, Patch& pt) { save_patch(core.data(), core.size(), pt); }

void QuadMesh::save_patch(const int* core, std::size_t ncore, Patch& pt) {
  if (++stamp_id == 1) {
    vertex_stamp.assign(points.size(), 0);
    quad_stamp.assign(quads.size(), 0);
  }
  pt.quads.clear();
  pt.verts.clear();
  auto addv = [&](int v) {
    if (vertex_stamp[v] != stamp_id) { vertex_stamp[v] = stamp_id; pt.verts.push_back(v); }
  };
  for (std::size_t i = 0; i < ncore; ++i) addv(core[i]);
  pt.ncore = pt.verts.size();
  for (std::size_t i = 0; i < pt.ncore; ++i)
    for (int q : vertex_quads[pt.verts[i]])
      for (int x : quads[q]) addv(x);
  for (int v : pt.verts)
    for (int q : vertex_quads[v])
      if (quad_stamp[q] != stamp_id) { quad_stamp[q] = stamp_id; pt.quads.push_back(q); }
  pt.q.clear(); pt.qdead.clear(); pt.vq.clear(); pt.p.clear(); pt.vdead.clear();
  for (int q : pt.quads) { pt.q.push_back(quads[q]); pt.qdead.push_back(quad_dead[q]); }
  for (int v : pt.verts) { pt.vq.push_back(vertex_quads[v]); pt.p.push_back(points[v]); pt.vdead.push_back(vertex_dead[v]); }
}

void QuadMesh::rollback(Patch& pt) {
  // The saved items first (that drops every reference to the new ones),
  // then the new ones, which are the latest of all.
  const std::size_t new_verts = pt.verts.size() - pt.p.size(), new_quads = pt.quads.size() - pt.q.size();
  pt.verts.resize(pt.p.size());
  pt.quads.resize(pt.q.size());
  for (std::size_t i = 0; i < pt.verts.size(); ++i) {
    const int v = pt.verts[i];
    vertex_quads[v] = pt.vq[i];
    points[v] = pt.p[i];
    vertex_dead[v] = pt.vdead[i];
  }
  for (std::size_t i = 0; i < pt.quads.size(); ++i) {
    const int q = pt.quads[i];
    quads[q] = pt.q[i];
    quad_dead[q] = pt.qdead[i];
    quad_sin_mu[q] = sin_mu_of(quads[q]);
  }
  for (std::size_t i = 0; i < new_verts; ++i) drop_vertex();
  for (std::size_t i = 0; i < new_quads; ++i) drop_quad();
}

double QuadMesh::patch_worst(const Patch& pt) const {
  double w = 2;
  for (int q : pt.quads)
    if (!quad_dead[q]) w = std::min(w, quad_sin_mu[q]);
  return w;
}

void QuadMesh::set_quad(int q, const Quad& nq) {
  tried[q] = 0;
  for (int x : quads[q]) remove_from(x, q);
  quads[q] = nq;
  for (int x : nq) vertex_quads[x].push_back(q);
  quad_sin_mu[q] = sin_mu_of(nq);
}

std::vector<double> QuadMesh::patch_sines(const Patch& pt) const {
  std::vector<double> s;
  for (int q : pt.quads)
    if (!quad_dead[q]) s.push_back(quad_sin_mu[q]);
  std::sort(s.begin(), s.end());
  return s;
}

bool lex_better(const std::vector<double>& now, const std::vector<double>& before) {
  const std::size_t n = std::min(now.size(), before.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (now[i] > before[i] * (1 + 1e-9) + 1e-15) return true;
    if (now[i] < before[i] * (1 - 1e-9)) return false;
  }
  return false;
}

int QuadMesh::add_vertex(const Point2& p) {
  const int v = int(points.size());
  points.push_back(p);
  if (!mesh.point_attributes.empty()) mesh.point_attributes.emplace_back(mesh.point_attributes[0].size(), 0.0);
  if (!mesh.point_markers.empty()) mesh.point_markers.push_back(0);
  vertex_quads.emplace_back();
  fixed.push_back(0);
  vertex_dead.push_back(0);
  active.push_back(1);
  vertex_stamp.push_back(stamp_id);
  return v;
}

void QuadMesh::drop_vertex() {
  points.pop_back();
  if (!mesh.point_attributes.empty()) mesh.point_attributes.pop_back();
  if (!mesh.point_markers.empty()) mesh.point_markers.pop_back();
  vertex_quads.pop_back(); fixed.pop_back(); vertex_dead.pop_back(); active.pop_back(); vertex_stamp.pop_back();
}

int QuadMesh::add_quad(int like) {
  const int q = int(quads.size());
  // Copies: push_back may reallocate.
  const std::vector<int> el = mesh.elements[quad_element[like]];
  mesh.elements.push_back(el);
  if (!mesh.element_attributes.empty()) {
    const std::vector<double> attr = mesh.element_attributes[quad_element[like]];
    mesh.element_attributes.push_back(attr);
  }
  quads.push_back(quads[like]);
  quad_element.push_back(int(mesh.elements.size()) - 1);
  quad_dead.push_back(0);
  quad_sin_mu.push_back(0);
  quad_stamp.push_back(stamp_id);
  tried.push_back(0);
  for (int x : quads[q]) vertex_quads[x].push_back(q);
  return q;
}

void QuadMesh::drop_quad() {
  mesh.elements.pop_back();
  if (!mesh.element_attributes.empty()) mesh.element_attributes.pop_back();
  quads.pop_back(); quad_element.pop_back(); quad_dead.pop_back(); quad_sin_mu.pop_back(); quad_stamp.pop_back();
  tried.pop_back();
}

void QuadMesh::compact() {
  // In place, by moves: no element or attribute list is copied (10^6 of
  // them would be as many allocations).
  std::vector<int> newid(points.size(), -1);
  int k = 0;
  for (std::size_t v = 0; v < points.size(); ++v)
    if (!vertex_dead[v]) newid[v] = k++;
  // Elements: the quads from `quads`, others as they were.
  std::vector<int> quad_of_elem(mesh.elements.size(), -1);
  for (std::size_t q = 0; q < quads.size(); ++q) quad_of_elem[quad_element[q]] = int(q);
  const bool attrs = !mesh.element_attributes.empty();
  std::size_t kept = 0;
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const int q = quad_of_elem[e];
    if (q >= 0 && quad_dead[q]) continue;
    std::vector<int>& el = mesh.elements[e];
    if (q >= 0) el.assign(quads[q].begin(), quads[q].end());
    for (int& x : el) x = newid[x];
    if (kept != e) {
      mesh.elements[kept] = std::move(el);
      if (attrs) mesh.element_attributes[kept] = std::move(mesh.element_attributes[e]);
    }
    ++kept;
  }
  mesh.elements.resize(kept);
  if (attrs) mesh.element_attributes.resize(kept);
  if (k == int(points.size())) return;
  const bool pattrs = !mesh.point_attributes.empty(), pmarks = !mesh.point_markers.empty();
  for (std::size_t v = 0; v < points.size(); ++v) {
    if (vertex_dead[v] || newid[v] == int(v)) continue;
    points[newid[v]] = points[v];
    if (pattrs) mesh.point_attributes[newid[v]] = std::move(mesh.point_attributes[v]);
    if (pmarks) mesh.point_markers[newid[v]] = mesh.point_markers[v];
  }
  points.resize(k);
  if (pattrs) mesh.point_attributes.resize(k);
  if (pmarks) mesh.point_markers.resize(k);
  for (auto& sg : mesh.segments) sg = {newid[sg[0]], newid[sg[1]]};  // segment ends never die
}

// Where every quad around x is strictly convex with the others standing
// (the placement rule, doc/tri2quad.md section 1): x moves to the centroid
// of that region, clipped from the box of its star; false if it is empty.
bool place_in_star(QuadMesh& qm, int x) {
  std::vector<Point2>& P = qm.points;
  std::vector<HalfPlane> hp;
  double lo[2] = {P[x][0], P[x][1]}, hi[2] = {P[x][0], P[x][1]};
  for (int q : qm.vertex_quads[x]) {
    const Quad& Qd = qm.quads[q];
    int k = 0;
    while (Qd[k] != x) ++k;
    const int n = Qd[(k + 1) & 3], o = Qd[(k + 2) & 3], p = Qd[(k + 3) & 3];
    // The turns at p, x and n of (x, n, o, p).
    hp.push_back({P[o], P[p]});
    hp.push_back({P[n], P[p]});
    hp.push_back({P[n], P[o]});
    for (int v : Qd)
      for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], P[v][d]); hi[d] = std::max(hi[d], P[v][d]); }
  }
  const std::vector<Point2> region = clip({{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}}, hp);
  if (region.empty()) return false;
  P[x] = centroid(region);
  for (int q : qm.vertex_quads[x]) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return true;
}

} // namespace imgmesh::quadsmooth_detail
