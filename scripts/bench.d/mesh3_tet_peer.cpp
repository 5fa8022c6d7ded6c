// Benchmark peer (not installed, not a test): CGAL 5.5's Mesh_3 on a
// labeled image, as issue 14 asks: make_mesh_3 on Labeled_mesh_domain_3
// with facet angle 30, facet distance a quarter of the smallest voxel
// spacing, cell radius-edge ratio 2, and make_mesh_3's default perturb and
// exude.   mesh3_tet_peer IN-image OUT.mesh
// IN: any image lib/image reads (nonzero = label 1). OUT in world
// coordinates (Image_3 has no direction: it is applied here), tetrahedra
// positively oriented, label 1. Prints "seconds tetrahedra".
#include "image/io.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <vector>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: mesh3_tet_peer IN-image OUT.mesh\n";
    return 2;
  }
  try {
    const imgmesh::BinaryImage img = imgmesh::read_foreground(argv[1], {});
    _image* im = ::_createImage(img.size[0], img.size[1], img.size[2], 1, img.spacing[0], img.spacing[1],
                                img.spacing[2], 1, WK_FIXED, SGN_UNSIGNED);
    auto* data = static_cast<unsigned char*>(im->data);
    for (std::size_t k = 0; k < img.data.size(); ++k) data[k] = img.data[k] ? 1 : 0;
    im->tx = float(img.origin[0]);
    im->ty = float(img.origin[1]);
    im->tz = float(img.origin[2]);
    CGAL::Image_3 image(im);
    const double h = std::min({img.spacing[0], img.spacing[1], img.spacing[2]});
    const auto t0 = std::chrono::steady_clock::now();
    Domain domain = Domain::create_labeled_image_mesh_domain(image);
    Criteria criteria(CGAL::parameters::facet_angle = 30, CGAL::parameters::facet_distance = h / 4,
                      CGAL::parameters::cell_radius_edge_ratio = 2);
    C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // World = origin + D (p - origin); a reflecting D flips orientation.
    const auto& d = img.direction;
    const double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) + d[2] * (d[3] * d[7] - d[4] * d[6]);
    std::map<Tr::Vertex_handle, int> id;
    std::vector<std::array<int, 4>> tets;
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
      std::array<int, 4> t;
      for (int i = 0; i < 4; ++i) t[std::size_t(i)] = id.emplace(c->vertex(i), int(id.size()) + 1).first->second;
      if (det < 0) std::swap(t[2], t[3]);
      tets.push_back(t);
    }
    std::vector<std::array<double, 3>> pts(id.size());
    for (const auto& [v, k] : id) {
      const auto& p = v->point().point();
      const double q[3] = {p.x() - img.origin[0], p.y() - img.origin[1], p.z() - img.origin[2]};
      for (int r = 0; r < 3; ++r)
        pts[std::size_t(k - 1)][std::size_t(r)] = img.origin[std::size_t(r)] + d[std::size_t(3 * r)] * q[0] + d[std::size_t(3 * r + 1)] * q[1] + d[std::size_t(3 * r + 2)] * q[2];
    }
    std::ofstream out(argv[2]);
    out.precision(17);
    out << "MeshVersionFormatted 2\nDimension 3\nVertices\n" << pts.size() << '\n';
    for (const auto& p : pts) out << p[0] << ' ' << p[1] << ' ' << p[2] << " 0\n";
    out << "Tetrahedra\n" << tets.size() << '\n';
    for (const auto& t : tets) out << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << " 1\n";
    out << "End\n";
    std::cout << secs << ' ' << c3t3.number_of_cells_in_complex() << '\n';
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "mesh3_peer: " << e.what() << '\n';
    return 1;
  }
}
