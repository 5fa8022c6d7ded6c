// The certificate (after DELMESH): the restricted facets as an oriented
// triangle mesh, certified against the voxel boundary bdCA(X) by
// certify_surface (mesh/surface_certificate.hpp, the code meshinfo --image
// runs: closed, manifold, outward, no self-intersection, components placed
// and matched one to one, each with the same Euler characteristic); the
// guarantees measured on the output; and the fallback's points where a
// component fails. Queries: DELMESH inserts what the fallback returns.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"
#include "mesh/surface_certificate.hpp"
#include "mesh/topology.hpp"
#include "mesh/triangle_quality.hpp"
#include "mesh/voxel_sides.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace imgmesh::surface_detail {

// The restricted facets in a deterministic order (by vertex ids).
std::vector<Facet> restricted_facets(const Tr& tr);

// bdCA(X) for X = {g < 0}: its corners and their faces bits (the quads,
// once counted, are dropped), components and Euler characteristics, and per
// component the S
// component (cube-grid numbering) of the active cube around one of its
// corners, to name what the repairs refine.
struct ExpectedTopology {
  VoxelBoundary boundary;
  MeshTopology topology;
  std::vector<int> s_component;  // per topology component
};
ExpectedTopology expected_topology(const CubeGrid& grid);

// A Delaunay facet in 8 bytes, not 16: its cell's address with the facet's
// index in the two low bits (cells are 8-byte aligned). Per triangle of the
// certificate's mesh, which is built beside the triangulation at the run's
// peak.
class PackedFacet {
public:
  explicit PackedFacet(const Facet& f) : bits_(reinterpret_cast<std::uintptr_t>(&*f.first) | std::uintptr_t(f.second)) {}
  Facet facet() const {
    return Facet(Tds::Cell_range::s_iterator_to(*reinterpret_cast<Tds::Cell*>(bits_ & ~std::uintptr_t(3))), int(bits_ & 3));
  }

private:
  static_assert(alignof(Tds::Cell) >= 4, "two low bits of a cell's address for the facet's index");
  std::uintptr_t bits_;
};

struct Certificate {
  SurfaceMesh mesh;                 // local coordinates, outward per component
  std::vector<Vec3> centers;        // per triangle: its surface centre
  std::vector<PackedFacet> facets;  // per triangle: its Delaunay facet
  std::vector<int> vertex_comp;     // per mesh vertex: the S component of its site
  double max_roughness = 0;         // of mesh (radians), for measure_guarantees
  SurfaceCertificate check;         // of mesh against bdCA(X) (its topology, correspondence, checks)
  std::vector<int> bad;             // S components to repair, ascending
  bool ok = false;                  // check.ok()
};

// The restricted Delaunay surface of W as a mesh (vertices in id order of
// first use, triangles in restricted_facets() order, each oriented along
// grad f, then consistently per component by majority) and its check.
// `vertex_count`: one more than the largest vertex id. intersections
// false: that check is left to the caller (check_surface_intersections on
// cert.mesh, then ok again from check), which no repair needs: a failure of
// it alone leaves no S component to repair.
Certificate certify(const Tr& tr, std::size_t vertex_count, const CubeGrid& grid, const ExpectedTopology& expected,
                    bool intersections = true);

// The check alone, on cert.mesh (local coordinates of `grid`) and
// cert.vertex_comp: sets check, bad and ok.
void check_certificate(Certificate& cert, const CubeGrid& grid, const ExpectedTopology& expected,
                       bool intersections = true);

// The guarantees measured on the output (local coordinates).
struct MeasuredGuarantees {
  TriangleQualityReport quality;
  double max_abs_f_at_vertices = 0, max_roughness = 0, max_distance_to_plane = 0, max_abs_f_at_centroids = 0;
  long long restricted_delaunay_violations = 0;  // surface centres whose nearest site is not their facet's
};
MeasuredGuarantees measure_guarantees(const Tr& tr, const SurfaceSampler& f, const Certificate& cert);

// The voxel centres next to bdCA(X) on the wrong side of cert.mesh
// (mesh/voxel_sides.hpp: exact side tests on the mesh, not the
// triangulation's cells), foreground where g < 0; false (out untouched) when
// the mesh is not closed, manifold and oriented.
bool count_voxel_sides(const Certificate& cert, const CubeGrid& grid, VoxelSides& out);

// The fallback's points on S component `comp`: the surface centres of the
// largest tenth of its restricted facets (read from `tr` as it is now) and
// the mixed-edge crossing farthest from W. Denser samples end as an
// epsilon-sample, where the restricted Delaunay surface is homeomorphic to S
// (Amenta-Bern, CDRR).
Candidates fallback_points(const Tr& tr, const SurfaceSampler& f, int comp);

} // namespace imgmesh::surface_detail
