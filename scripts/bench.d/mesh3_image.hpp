// The benchmark peers' one way into CGAL 5.5's Mesh_3 on a labeled image
// (mesh3_peer: the surface; mesh3_tet_peer: the tetrahedra): the image,
// how Mesh_3 is seeded, and the way back to world coordinates.
#pragma once

#include "image/io.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_3/initialize_triangulation_from_labeled_image.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <array>
#include <stdexcept>
#include <string>

namespace mesh3 {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

// The image's foreground (labels 0 / 1) with one background voxel around:
// a label touching the image's border still gets a closed surface
// (implicit2mesh's f is closed there too).
inline imgmesh::BinaryImage padded_foreground(const std::string& path) {
  imgmesh::BinaryImage x = imgmesh::pad(imgmesh::read_foreground(path, {}), {1, 1, 1}, {1, 1, 1});
  for (auto& v : x.data) v = v ? 1 : 0;
  return x;
}

// CGAL's copy of X, as unsigned words of type Word (it has spacing and
// origin, no direction).
template <class Word = unsigned char, class T>
CGAL::Image_3 cgal_image(const imgmesh::Image<T>& x) {
  _image* im = _createImage(x.size[0], x.size[1], x.size[2], 1, x.spacing[0], x.spacing[1], x.spacing[2],
                            sizeof(Word), WK_FIXED, SGN_UNSIGNED);
  Word* data = static_cast<Word*>(im->data);
  for (std::size_t i = 0; i < x.data.size(); ++i) data[i] = static_cast<Word>(x.data[i]);
  im->tx = float(x.origin[0]);
  im->ty = float(x.origin[1]);
  im->tz = float(x.origin[2]);
  return CGAL::Image_3(im);
}

// seeded: initialize_triangulation_from_labeled_image (CGAL's
// mesh_3D_image_with_custom_initialization: points shot from every
// connected component) then refine_mesh_3; plain: make_mesh_3, which seeds
// from random rays and may miss components. `options` go to both
// (manifold(), no_perturb(), ...); none: Mesh_3's defaults.
template <class... Options>
C3t3 mesh(const std::string& mode, const Domain& domain, const CGAL::Image_3& image, const Criteria& criteria,
          Options... options) {
  C3t3 c3t3;
  if (mode == "seeded") {
    initialize_triangulation_from_labeled_image(c3t3, domain, image, criteria, static_cast<unsigned char>(0));
    CGAL::refine_mesh_3(c3t3, domain, criteria, options...);
  } else if (mode == "plain") {
    c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, options...);
  } else {
    throw std::runtime_error("mode '" + mode + "': seeded or plain");
  }
  return c3t3;
}

// World = origin + direction * (p - origin), p in CGAL's image frame.
inline std::array<double, 3> world(const imgmesh::Geometry& x, const std::array<double, 3>& p) {
  const double q[3] = {p[0] - x.origin[0], p[1] - x.origin[1], p[2] - x.origin[2]};
  std::array<double, 3> w{};
  for (std::size_t r = 0; r < 3; ++r)
    w[r] = x.origin[r] + x.direction[3 * r] * q[0] + x.direction[3 * r + 1] * q[1] + x.direction[3 * r + 2] * q[2];
  return w;
}

}  // namespace mesh3
