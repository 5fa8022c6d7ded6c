// The certificate (after DELMESH): the restricted facets as an oriented
// triangle mesh, its components matched one to one, by place, with those of
// the voxel boundary bdCA(X), each with the same Euler characteristic; the
// guarantees measured on the output; and the fallback's points where a
// component does not match. Queries: DELMESH inserts what the fallback
// returns. Counts with lib/mesh's topology module, as meshinfo does.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"
#include "mesh/topology.hpp"
#include "mesh/triangle_quality.hpp"

#include <map>
#include <vector>

namespace imgmesh::surface_detail {

// The restricted facets in a deterministic order (by vertex ids).
std::vector<Facet> restricted_facets(const Tr& tr);

// bdCA(X) for X = {g < 0}, and its Euler characteristic per S component
// (the cube grid's numbering: each voxel-boundary component goes to the S
// component of the active cube around one of its corners).
struct ExpectedTopology {
  MeshTopology topology;
  std::vector<long long> by_component;
};
ExpectedTopology expected_topology(const CubeGrid& grid);

struct Certificate {
  SurfaceMesh mesh;                 // local coordinates, outward per component
  std::vector<Vec3> centers;        // per triangle: its surface centre
  std::vector<Facet> facets;        // per triangle: its Delaunay facet
  std::vector<int> tri_comp;        // per triangle: its mesh component
  std::map<int, std::vector<int>> mesh_comps;  // S component -> its mesh components (-1: on none)
  MeshTopology topology;            // of mesh
  // S components with other than one mesh component, and -1 when a mesh
  // component lies on no S component.
  std::vector<int> bad;
  bool ok = false;  // bad empty, closed oriented manifold, sorted Euler characteristics equal
};

// The restricted Delaunay surface of W as a mesh (vertices in id order of
// first use, triangles in restricted_facets() order, each oriented along
// grad f, then consistently per component by majority) and its check.
// `vertex_count`: one more than the largest vertex id.
Certificate certify(const Tr& tr, std::size_t vertex_count, const ExpectedTopology& expected);

// The S components whose single mesh component has another Euler
// characteristic than bdCA(X)'s (when `bad` is empty: sorted lists can
// agree while components are in each other's places).
std::vector<int> euler_mismatches(const Certificate& cert, const ExpectedTopology& expected);

// The guarantees measured on the output (local coordinates).
struct MeasuredGuarantees {
  TriangleQualityReport quality;
  double max_abs_f_at_vertices = 0, max_roughness = 0, max_distance_to_plane = 0, max_abs_f_at_centroids = 0;
  long long restricted_delaunay_violations = 0;  // surface centres whose nearest site is not their facet's
};
MeasuredGuarantees measure_guarantees(const Tr& tr, const SurfaceSampler& f, const Certificate& cert);

// The fallback's points on S component `comp`: the surface centres of the
// largest tenth of its restricted facets `fs` and the mixed-edge crossing
// farthest from W. Denser samples end as an epsilon-sample, where the
// restricted Delaunay surface is homeomorphic to S (Amenta-Bern, CDRR).
Candidates fallback_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Facet>& fs, int comp);

} // namespace imgmesh::surface_detail
