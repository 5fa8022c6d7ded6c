// Benchmark peer (not installed, not a test): CGAL 5.5's Mesh_3 on the
// labeled image (the well-composed image, labels 0 / 1), surface criteria
// only: facet angle 30 degrees, facet distance DISTANCE voxels of the
// smallest spacing, manifold; no cell criteria, no optimisation.
//   mesh3_peer IN.nrrd OUT.off seeded|plain [DISTANCE]
// seeded / plain: mesh3_image.hpp's mesh3::mesh. Prints "seconds triangles" on
// its last line (CGAL prints progress on stdout before it).
#include "mesh3_image.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::cerr << "usage: mesh3_peer IN.nrrd OUT.off seeded|plain [DISTANCE]\n";
    return 2;
  }
  try {
    const std::string mode = argv[3];
    const double distance = argc == 5 ? std::atof(argv[4]) : 0.25;
    const imgmesh::BinaryImage x = mesh3::padded_foreground(argv[1]);
    const double h = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
    const auto t0 = std::chrono::steady_clock::now();
    const CGAL::Image_3 image = mesh3::cgal_image(x);
    const mesh3::Domain domain = mesh3::Domain::create_labeled_image_mesh_domain(image);
    namespace p = CGAL::parameters;
    const mesh3::Criteria criteria(p::facet_angle = 30, p::facet_distance = distance * h,
                                   p::facet_topology = CGAL::MANIFOLD);
    const mesh3::C3t3 c3t3 = mesh3::mesh(mode, domain, image, criteria, p::manifold(), p::no_perturb(), p::no_exude());
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::stringstream off;
    c3t3.output_boundary_to_off(off);
    std::ofstream out(argv[2]);
    out.precision(17);
    std::string magic;
    std::size_t nv, nf, ne;
    off >> magic >> nv >> nf >> ne;
    out << "OFF\n" << nv << ' ' << nf << " 0\n";
    for (std::size_t k = 0; k < nv; ++k) {
      std::array<double, 3> q;
      off >> q[0] >> q[1] >> q[2];
      const auto w = mesh3::world(x, q);
      out << w[0] << ' ' << w[1] << ' ' << w[2] << '\n';
    }
    out << off.rdbuf();
    std::cout << '\n' << secs << ' ' << c3t3.number_of_facets_in_complex() << '\n';
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "mesh3_peer: " << e.what() << '\n';
    return 1;
  }
}
