// Benchmark peer (not installed, not a test): CGAL 5.5's Mesh_3 on the
// labeled image (the well-composed image, labels 0 / 1), surface criteria
// only: facet angle 30 degrees, facet distance DISTANCE voxels of the
// smallest spacing, manifold; no cell criteria, no optimisation.
//   mesh3_peer IN.nrrd OUT.off seeded|plain [DISTANCE]
// seeded: initialize_triangulation_from_labeled_image (CGAL's
// mesh_3D_image_with_custom_initialization: points shot from every
// connected component) then refine_mesh_3; plain: make_mesh_3, which seeds
// from random rays and may miss components. Prints "seconds triangles" on
// its last line (CGAL prints progress on stdout before it).
#include "image/io.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/refine_mesh_3.h>
#include <CGAL/Mesh_3/initialize_triangulation_from_labeled_image.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::cerr << "usage: mesh3_peer IN.nrrd OUT.off seeded|plain [DISTANCE]\n";
    return 2;
  }
  try {
    const std::string mode = argv[3];
    const double distance = argc == 5 ? std::atof(argv[4]) : 0.25;
    // One background voxel around: a label touching the image's border
    // still gets a closed surface (implicit2mesh's f is closed there too).
    const imgmesh::BinaryImage x = imgmesh::pad(imgmesh::read_foreground(argv[1], {}), {1, 1, 1}, {1, 1, 1});
    const double h = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
    const auto t0 = std::chrono::steady_clock::now();
    _image* im = _createImage(x.size[0], x.size[1], x.size[2], 1, x.spacing[0], x.spacing[1], x.spacing[2], 1,
                              WK_FIXED, SGN_UNSIGNED);
    std::memcpy(im->data, x.data.data(), x.data.size());
    im->tx = float(x.origin[0]);
    im->ty = float(x.origin[1]);
    im->tz = float(x.origin[2]);
    CGAL::Image_3 image(im);
    const Domain domain = Domain::create_labeled_image_mesh_domain(image);
    namespace p = CGAL::parameters;
    const Criteria criteria(p::facet_angle = 30, p::facet_distance = distance * h, p::facet_topology = CGAL::MANIFOLD);
    C3t3 c3t3;
    if (mode == "seeded") {
      initialize_triangulation_from_labeled_image(c3t3, domain, image, criteria, static_cast<unsigned char>(0));
      CGAL::refine_mesh_3(c3t3, domain, criteria, p::manifold(), p::no_perturb(), p::no_exude());
    } else {
      c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, p::manifold(), p::no_perturb(), p::no_exude());
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // CGAL's image has no direction: world = origin + direction * (p - origin).
    std::stringstream off;
    c3t3.output_boundary_to_off(off);
    std::ofstream out(argv[2]);
    out.precision(17);
    std::string magic;
    std::size_t nv, nf, ne;
    off >> magic >> nv >> nf >> ne;
    out << "OFF\n" << nv << ' ' << nf << " 0\n";
    for (std::size_t k = 0; k < nv; ++k) {
      double p[3];
      off >> p[0] >> p[1] >> p[2];
      for (int i = 0; i < 3; ++i) p[i] -= x.origin[std::size_t(i)];
      for (int i = 0; i < 3; ++i)
        out << x.origin[std::size_t(i)] + x.direction[std::size_t(3 * i)] * p[0] +
                   x.direction[std::size_t(3 * i + 1)] * p[1] + x.direction[std::size_t(3 * i + 2)] * p[2]
            << (i < 2 ? ' ' : '\n');
    }
    out << off.rdbuf();
    std::cout << '\n' << secs << ' ' << c3t3.number_of_facets_in_complex() << '\n';
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "mesh3_peer: " << e.what() << '\n';
    return 1;
  }
}
