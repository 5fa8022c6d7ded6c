#include "surface/certificate.hpp"
#include "surface/star.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace imgmesh::surface_detail {

std::vector<Facet> restricted_facets(const Tr& tr) {
  // Counted first: the vectors are as large as the mesh, and growing them
  // by doubling would hold up to three times that at the peak.
  std::size_t count = 0;
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it)
    count += it->first->facet.restricted(it->second);
  std::vector<std::pair<std::array<int, 3>, Facet>> out;
  out.reserve(count);
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it) {
    if (!it->first->facet.restricted(it->second)) continue;
    std::array<int, 3> ids;
    for (int m = 1; m < 4; ++m) ids[m - 1] = it->first->vertex((it->second + m) & 3)->info().id;
    std::sort(ids.begin(), ids.end());
    out.emplace_back(ids, *it);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Facet> fs;
  fs.reserve(out.size());
  for (auto& p : out) fs.push_back(p.second);
  return fs;
}

namespace {
// The triangles at each vertex, in triangle order (counted, then placed):
// 4 bytes a corner, where (edge, triangle) pairs sorted took 16 a corner
// beside the triangulation at the run's peak. The triangles at edge (a, b)
// are those of a that hold b, so they come in triangle order too.
struct VertexTriangles {
  const std::vector<std::array<int, 3>>& triangles;
  std::vector<std::uint32_t> start, tris;
  VertexTriangles(std::size_t nv, const std::vector<std::array<int, 3>>& ts)
      : triangles(ts), start(nv + 1, 0), tris(3 * ts.size()) {
    for (const auto& t : ts)
      for (int v : t) ++start[std::size_t(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> at(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < ts.size(); ++t)
      for (int v : ts[t]) tris[at[std::size_t(v)]++] = std::uint32_t(t);
  }
  template <class F> void at_edge(int a, int b, F f) const {
    for (std::uint32_t i = start[std::size_t(a)]; i < start[std::size_t(a) + 1]; ++i) {
      const auto& t = triangles[tris[i]];
      if (t[0] == b || t[1] == b || t[2] == b) f(int(tris[i]));
    }
  }
};
} // namespace

ExpectedTopology expected_topology(const CubeGrid& grid) {
  ExpectedTopology e;
  e.boundary = voxel_boundary(grid.g);
  e.topology = mesh_topology(e.boundary);
  for (const ComponentTopology& c : e.topology.components) {
    // Corner (i, j, k) is the centre of the cube whose lowest sample is
    // (i-1, j-1, k-1); it is active, being on the voxel boundary.
    const std::array<std::size_t, 3> k = e.boundary.corner(c.first_vertex);
    long cube[3];
    for (int a = 0; a < 3; ++a) cube[a] = std::clamp(long(k[a]) - 1, 0L, grid.n[a] - 2);
    e.s_component.push_back(grid.comp_of(cube[0], cube[1], cube[2]));
  }
  // From here on only the corners and their faces bits are read
  // (certify_surface): the quads are not held through the run (brain label
  // 4: 2.9 MB).
  std::vector<int>().swap(e.boundary.corners);
  std::vector<std::size_t>().swap(e.boundary.offsets);
  return e;
}

Certificate certify(const Tr& tr, std::size_t vertex_count, const CubeGrid& grid, const ExpectedTopology& expected,
                    bool intersections) {
  Certificate cert;
  SurfaceMesh& mesh = cert.mesh;
  std::vector<Facet> fs = restricted_facets(tr);
  // Sized exactly (the vertices counted first): growing by doubling would
  // hold up to twice the mesh at the run's peak.
  std::vector<int> index(vertex_count, -1);
  std::size_t used = 0;
  for (const Facet& f : fs)
    for (int m = 1; m < 4; ++m) {
      int& id = index[std::size_t(f.first->vertex((f.second + m) & 3)->info().id)];
      if (id < 0) id = 0, ++used;
    }
  std::fill(index.begin(), index.end(), -1);
  mesh.points.reserve(used);
  cert.vertex_comp.reserve(used);
  mesh.triangles.reserve(fs.size());
  for (const Facet& f : fs) {
    std::array<int, 3> t;
    const std::array<Vh, 3> vs = facet_vertices(f.first, f.second);
    for (int m = 0; m < 3; ++m) {
      int& id = index[vs[m]->info().id];
      if (id < 0) {
        id = int(mesh.points.size());
        mesh.points.push_back(vec(vs[m]->point()));
        cert.vertex_comp.push_back(vs[m]->info().comp);
      }
      t[m] = id;
    }
    // Outward: along grad f at the surface centre.
    const Vec3 n = cross(sub(mesh.points[t[1]], mesh.points[t[0]]), sub(mesh.points[t[2]], mesh.points[t[0]]));
    const FacetInfo& fi = f.first->facet[f.second];
    if (dot(n, Vec3{fi.grad[0], fi.grad[1], fi.grad[2]}) < 0) std::swap(t[1], t[2]);
    mesh.triangles.push_back(t);
  }
  // The check (mesh_topology) is the run's peak, beside the triangulation:
  // the facets packed, the rest let go of first.
  std::vector<int>().swap(index);
  cert.facets.reserve(fs.size());
  for (const Facet& f : fs) cert.facets.emplace_back(f);
  std::vector<Facet>().swap(fs);
  // Make orientation consistent per mesh component (BFS), by majority.
  {
    const std::size_t nt = mesh.triangles.size();
    const VertexTriangles at(mesh.points.size(), mesh.triangles);
    std::vector<int> flip(nt, -1);
    for (std::size_t s0 = 0; s0 < nt; ++s0) {
      if (flip[s0] >= 0) continue;
      std::vector<int> members{int(s0)}, stack{int(s0)};
      flip[s0] = 0;
      while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        auto tt = mesh.triangles[t];
        if (flip[t]) std::swap(tt[1], tt[2]);
        for (int k = 0; k < 3; ++k) {
          const int a = tt[k], b = tt[(k + 1) % 3];
          at.at_edge(a, b, [&](int u) {
            if (u == t || flip[u] >= 0) return;
            // u must traverse the edge as (b, a).
            const auto& tu = mesh.triangles[u];
            bool forward = false;
            for (int m = 0; m < 3; ++m) forward = forward || (tu[m] == a && tu[(m + 1) % 3] == b);
            flip[u] = forward ? 1 : 0;
            members.push_back(u);
            stack.push_back(u);
          });
        }
      }
      long long agree = 0;
      for (int t : members) agree += flip[t] ? -1 : 1;
      if (agree < 0)
        for (int t : members) flip[t] = 1 - flip[t];
    }
    for (std::size_t t = 0; t < nt; ++t)
      if (flip[t] == 1) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    // Roughness at the edges of exactly two triangles, from the first
    // (a guarantee measured on the output), while the triangles at each
    // vertex are at hand: built again in measure_guarantees, they made its
    // peak beside the certificate and the triangulation.
    auto unit_normal = [&](std::size_t k) {
      const auto& t = mesh.triangles[k];
      Vec3 n = cross(sub(mesh.points[t[1]], mesh.points[t[0]]), sub(mesh.points[t[2]], mesh.points[t[0]]));
      const double nl = norm(n);
      if (nl > 0) n = {n[0] / nl, n[1] / nl, n[2] / nl};
      return n;
    };
    for (std::size_t k = 0; k < nt; ++k)
      for (int e = 0; e < 3; ++e) {
        int n = 0, other = -1;
        at.at_edge(mesh.triangles[k][e], mesh.triangles[k][(e + 1) % 3], [&](int u) {
          ++n;
          if (u != int(k)) other = u;
        });
        if (n == 2 && other > int(k))
          cert.max_roughness =
              std::max(cert.max_roughness, std::acos(std::clamp(dot(unit_normal(k), unit_normal(std::size_t(other))), -1.0, 1.0)));
      }
  }
  check_certificate(cert, grid, expected, intersections);
  // After the check, which is the run's peak (beside the triangulation),
  // in pages of their own: the check's scratch, freed in pieces, would not
  // hold them.
  release_free_memory();
  cert.centers.reserve(cert.facets.size());
  for (const PackedFacet& f : cert.facets) cert.centers.push_back(facet_center(f.facet()));
  return cert;
}

void check_certificate(Certificate& cert, const CubeGrid& grid, const ExpectedTopology& expected, bool intersections) {
  // The mesher's local frame as a grid: voxel centre i at i * spacing.
  Geometry local;
  local.size = grid.g.size;
  local.spacing = grid.g.spacing;
  cert.check = SurfaceCertificate();  // the last one let go of first: this is the run's peak
  CertificateOptions options;
  options.intersections = intersections;
  cert.check = certify_surface(cert.mesh.points, cert.mesh.triangles, local, expected.boundary, expected.topology, options);
  cert.ok = cert.check.ok();
  // What to repair: the S components under every failing mesh component
  // (its vertices' sites) and of every failing bdCA(X) component.
  const MeshTopology& t = cert.check.topology;
  std::set<int> bad;
  for (std::size_t v = 0; v < cert.mesh.points.size(); ++v) {
    const int m = t.component_of[v];
    if (m >= 0 && !cert.check.component_ok[std::size_t(m)] && cert.vertex_comp[v] >= 0) bad.insert(cert.vertex_comp[v]);
  }
  const auto& boundary = cert.check.correspondence.boundary;
  for (std::size_t b = 0; b < boundary.size(); ++b)
    if (boundary[b].verdict != "ok" && expected.s_component[b] >= 0) bad.insert(expected.s_component[b]);
  cert.bad.assign(bad.begin(), bad.end());
}

MeasuredGuarantees measure_guarantees(const Tr& tr, const SurfaceSampler& sampler, const Certificate& cert) {
  const SurfaceMesh& mesh = cert.mesh;
  const std::vector<Vec3>& centers = cert.centers;
  const std::vector<PackedFacet>& fs = cert.facets;
  const TriangleQualityReport q = triangle_quality_report(mesh);
  double max_f = 0, max_dist = 0;
  for (const Vec3& p : mesh.points) max_f = std::max(max_f, std::abs(sampler.value(p)));
  {
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
      const auto& t = mesh.triangles[k];
      const Vec3 n = cross(sub(mesh.points[t[1]], mesh.points[t[0]]), sub(mesh.points[t[2]], mesh.points[t[0]]));
      const double nl = norm(n);
      if (nl > 0) max_dist = std::max(max_dist, std::abs(dot(n, sub(centers[k], mesh.points[t[0]]))) / nl);
    }
  }
  // Geometric error estimate: |f| at the triangles' centroids (f
  // interpolates g, the signed distance to the voxel boundary, world units).
  double max_centroid = 0;
  for (const auto& t : mesh.triangles) {
    Vec3 c;
    for (int i = 0; i < 3; ++i) c[i] = (mesh.points[t[0]][i] + mesh.points[t[1]][i] + mesh.points[t[2]][i]) / 3;
    max_centroid = std::max(max_centroid, std::abs(sampler.value(c)));
  }
  // Restricted Delaunay property: each surface centre's nearest site is a
  // vertex of its facet (its ball is empty).
  long long rd_violations = 0;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Vec3& x = centers[k];
    const double r2 = dist2(x, mesh.points[mesh.triangles[k][0]]);
    Vh nv = nearest_vertex(tr, Point(x[0], x[1], x[2]), fs[k].facet().first);
    if (dist2(x, vec(nv->point())) < r2 * (1 - 1e-9)) ++rd_violations;
  }
  MeasuredGuarantees m;
  m.quality = q;
  m.max_abs_f_at_vertices = max_f;
  m.max_roughness = cert.max_roughness;
  m.max_distance_to_plane = max_dist;
  m.max_abs_f_at_centroids = max_centroid;
  m.restricted_delaunay_violations = rd_violations;
  return m;
}

bool count_voxel_sides(const Certificate& cert, const CubeGrid& grid, VoxelSides& out) {
  const auto& state = cert.check.state;
  for (int c : {SurfaceCertificate::kClosed, SurfaceCertificate::kManifold, SurfaceCertificate::kOriented})
    if (state[std::size_t(c)] != 1) return false;
  Geometry local;  // the mesher's frame, as check_certificate's
  local.size = grid.g.size;
  local.spacing = grid.g.spacing;
  const MeshTopology& t = cert.check.topology;
  std::vector<int> component;
  component.reserve(cert.mesh.triangles.size());
  for (const auto& tri : cert.mesh.triangles) component.push_back(t.component_of[std::size_t(tri[0])]);
  // Outside the box of the samples given every sample is +T: background.
  const std::array<Index3, 2> box{grid.g.box_lo(), grid.g.box_hi()};
  out = voxel_sides(cert.mesh.points, cert.mesh.triangles, component, t.components.size(), local,
                    [&grid](std::size_t i, std::size_t j, std::size_t k) { return grid.g(i, j, k) < 0; }, &box);
  return true;
}

Candidates fallback_points(const Tr& tr, const SurfaceSampler& sampler, int comp) {
  const CubeGrid& grid = sampler.grid();
  std::vector<std::pair<double, Facet>> mine;
  for (const Facet& f : restricted_facets(tr))
    if (f.first->vertex((f.second + 1) & 3)->info().comp == comp) mine.emplace_back(f.first->facet[f.second].r2, f);
  std::stable_sort(mine.begin(), mine.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const std::size_t take = std::min<std::size_t>(mine.size(), std::max<std::size_t>(1, mine.size() / 10));
  Candidates pts;
  for (std::size_t k = 0; k < take; ++k) pts.emplace_back(facet_center(mine[k].second), mine[k].first);
  // Farthest mixed-edge crossing (linear estimate, then refined).
  double far = -1;
  Vec3 fa{}, fb{};
  std::size_t count = 0, stride = 1;
  for (const ActiveCube& kc : grid.comp) count += kc.comp() == comp;
  stride = std::max<std::size_t>(1, count / 4000);
  std::size_t k = 0;
  for (const ActiveCube& kc : grid.sorted_cubes()) {
    if (kc.comp() != comp || (k++ % stride)) continue;
    const auto [x, y, z] = grid.cube_of_key(kc.key());
    for (int a = 0; a < 3; ++a) {
      long p[3] = {x, y, z}, q[3] = {x, y, z};
      q[a] += 1;
      if (grid.neg(p[0], p[1], p[2]) == grid.neg(q[0], q[1], q[2])) continue;
      const Vec3 pa{p[0] * grid.s[0], p[1] * grid.s[1], p[2] * grid.s[2]};
      const Vec3 pb{q[0] * grid.s[0], q[1] * grid.s[1], q[2] * grid.s[2]};
      const double ga = grid.g(p[0], p[1], p[2]), gb = grid.g(q[0], q[1], q[2]);
      const double t = ga / (ga - gb);
      const Vec3 m{pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1]), pa[2] + t * (pb[2] - pa[2])};
      Vh nv = tr.nearest_vertex(Point(m[0], m[1], m[2]));
      const double dd = dist2(m, vec(nv->point()));
      if (dd > far) {
        far = dd;
        fa = pa;
        fb = pb;
      }
    }
  }
  Vec3 x;
  if (far > 0 && sampler.bisect(fa, fb, sampler.value(fa), x)) pts.emplace_back(x, far);
  return pts;
}

} // namespace imgmesh::surface_detail
