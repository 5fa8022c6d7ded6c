// What the multi-label certificate's files share (interface_certificate.cpp:
// the driver, labels, intersections, sides; interface_patches.cpp: the
// interfaces). Internal to lib/surfacenets.
#pragma once
#include "surfacenets/interface_certificate.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace imgmesh::surfacenets_detail {

// The interfaces check: every pair of K(X) and of the mesh, each with its
// patches matched to K(X)'s and `why` set when it fails. tolerance > 0,
// world units.
std::vector<InterfaceCertificate::Interface> certify_interfaces(const std::vector<Vec3>& points,
                                                                const std::vector<std::array<int, 3>>& triangles,
                                                                const std::vector<std::array<std::int32_t, 2>>& pairs,
                                                                const Geometry& grid, const InterfaceComplex& k,
                                                                double tolerance);

} // namespace imgmesh::surfacenets_detail
