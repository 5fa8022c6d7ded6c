// Benchmark peer (not installed, not a test): CGAL 5.5's Mesh_3 on a
// labeled image, as issue 14 asks: Labeled_mesh_domain_3 with facet angle
// 30, facet distance a quarter of the smallest voxel spacing, cell
// radius-edge ratio 2, and Mesh_3's default perturb and exude.
//   mesh3_tet_peer IN-image OUT.mesh seeded|plain
// IN: any image lib/image reads (nonzero = label 1), padded by one
// background voxel. seeded / plain: mesh3_image.hpp's mesh3::mesh (plain
// make_mesh_3 may miss components). OUT in world coordinates, tetrahedra
// positively oriented, label 1. Prints "seconds tetrahedra" on its last
// line (CGAL prints progress on stdout before it).
#include "mesh3_image.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: mesh3_tet_peer IN-image OUT.mesh seeded|plain\n";
    return 2;
  }
  try {
    const imgmesh::BinaryImage x = mesh3::padded_foreground(argv[1]);
    const double h = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
    const auto t0 = std::chrono::steady_clock::now();
    const CGAL::Image_3 image = mesh3::cgal_image(x);
    const mesh3::Domain domain = mesh3::Domain::create_labeled_image_mesh_domain(image);
    namespace p = CGAL::parameters;
    const mesh3::Criteria criteria(p::facet_angle = 30, p::facet_distance = h / 4, p::cell_radius_edge_ratio = 2);
    const mesh3::C3t3 c3t3 = mesh3::mesh(argv[3], domain, image, criteria);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // A reflecting direction flips the orientation.
    const auto& d = x.direction;
    const double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) + d[2] * (d[3] * d[7] - d[4] * d[6]);
    std::map<mesh3::Tr::Vertex_handle, int> id;
    std::vector<std::array<int, 4>> tets;
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
      std::array<int, 4> t;
      for (int i = 0; i < 4; ++i) t[std::size_t(i)] = id.emplace(c->vertex(i), int(id.size()) + 1).first->second;
      if (det < 0) std::swap(t[2], t[3]);
      tets.push_back(t);
    }
    std::vector<std::array<double, 3>> pts(id.size());
    for (const auto& [v, k] : id) {
      const auto& q = v->point().point();
      pts[std::size_t(k - 1)] = mesh3::world(x, {q.x(), q.y(), q.z()});
    }
    std::ofstream out(argv[2]);
    out.precision(17);
    out << "MeshVersionFormatted 2\nDimension 3\nVertices\n" << pts.size() << '\n';
    for (const auto& q : pts) out << q[0] << ' ' << q[1] << ' ' << q[2] << " 0\n";
    out << "Tetrahedra\n" << tets.size() << '\n';
    for (const auto& t : tets) out << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << " 1\n";
    out << "End\n";
    std::cout << '\n' << secs << ' ' << c3t3.number_of_cells_in_complex() << '\n';
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "mesh3_tet_peer: " << e.what() << '\n';
    return 1;
  }
}
