// Every label's surface of an InterfaceMesh certified by lib/mesh against
// bdCA of its indicator, and the voxel centres' sides (Catch2 checks).
#pragma once
#include "surfacenets/surface_nets.hpp"

#include "mesh/surface_certificate.hpp"
#include "mesh/topology.hpp"
#include "mesh/voxel_sides.hpp"
#include "wellcomposed/label_images.hpp"

#include <catch2/catch.hpp>

namespace imgmesh::test {

// lib/mesh's certificate on every nonzero label's surface against bdCA of
// its indicator, and (sides) the voxel centres' sides.
inline void certify_labels(const InterfaceMesh& m, const LabelImage& img, bool sides = true) {
  for (std::int32_t l : labels_of(img)) {
    if (l == 0) continue;
    INFO("label " << l);
    const auto tris = label_triangles(m, l);
    const BinaryImage b = indicator(img, l);
    const VoxelBoundary vb = voxel_boundary(b);
    const SurfaceCertificate c = certify_surface(m.points, tris, img, vb, mesh_topology(vb));
    CHECK(c.failure() == "");
    if (!c.ok() || !sides) continue;
    std::vector<int> comp(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) comp[t] = c.topology.component_of[std::size_t(tris[t][0])];
    const VoxelSides s = voxel_sides(m.points, tris, comp, c.topology.components.size(), b);
    CHECK(s.wrong() == 0);
  }
}

} // namespace imgmesh::test
