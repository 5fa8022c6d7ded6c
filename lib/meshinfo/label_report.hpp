// meshinfo on a surface with a label pair per face (seg2mesh --fast and
// --conforming, seg2tet's interfaces): each label's closed surface and each
// interface on its own (issue 40), without an image. The whole complex is
// not a manifold where three labels meet; each label's surface should be.
#pragma once
#include "util/json.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace imgmesh {

// "labels": per label (ascending; 0 the background, whose surface is the
// labels' union's), its triangles oriented out of it (out of the union for
// 0), their components, Euler characteristics, closed/manifold/oriented,
// area, enclosed volume and smallest angle. "interfaces": per pair a|b
// (a > b, as the certificate names them), its triangles, patches (edge-
// connected pieces), area and smallest angle. Faces are triangles; pairs
// (behind, front), the face oriented out of behind.
Json label_report(const std::vector<std::array<double, 3>>& points, const std::vector<std::array<int, 3>>& triangles,
                  const std::vector<std::array<std::int32_t, 2>>& pairs);

} // namespace imgmesh
