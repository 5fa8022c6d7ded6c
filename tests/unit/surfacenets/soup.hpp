// A mesh as any mesher hands it to the interface certificate: points,
// triangles, a label pair each (test_interface_certificate.cpp,
// test_interface_cells.cpp).
#pragma once
#include "surfacenets/surface_nets.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace imgmesh::test {

struct Soup {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::int32_t, 2>> pairs;
};
inline Soup soup_of(const InterfaceMesh& m) {
  Soup s{m.points, m.triangles, {}};
  for (std::size_t t = 0; t < m.triangles.size(); ++t) s.pairs.push_back(m.triangle_labels(t));
  return s;
}

} // namespace imgmesh::test
