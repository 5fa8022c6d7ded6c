// Benchmark peer (not installed, not a test): CGAL 5.5's Surface_mesher on
// the same implicit function f as implicit2mesh, as the issue asks:
// make_surface_mesh with Surface_mesh_default_criteria_3 (30-degree angle
// bound) and Manifold_tag.
//   surface_mesher_peer IN.nrrd OUT.off [RADIUS DISTANCE]
// RADIUS, DISTANCE: the criteria's size and distance bounds in voxels of the
// smallest spacing (default 2 and 0.1). Prints "seconds triangles
// max|f|-at-centroids".
#include "implicit/implicit_file.hpp"

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/IO/Complex_2_in_triangulation_3_file_writer.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Surface_mesh_default_criteria_3.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>

using Tr = CGAL::Surface_mesh_default_triangulation_3;
using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
using GT = Tr::Geom_traits;
using Sphere = GT::Sphere_3;
using Point = GT::Point_3;
using FT = GT::FT;

int main(int argc, char** argv) {
  if (argc != 3 && argc != 5) {
    std::cerr << "usage: surface_mesher_peer IN.nrrd OUT.off [RADIUS DISTANCE]\n";
    return 2;
  }
  try {
    const imgmesh::PartitionOfUnity pu = imgmesh::read_implicit(argv[1]);
    const imgmesh::SampleGrid& g = pu.samples();
    const double h = std::min({g.spacing[0], g.spacing[1], g.spacing[2]});
    const double radius = argc == 5 ? std::atof(argv[3]) : 2.0, distance = argc == 5 ? std::atof(argv[4]) : 0.1;
    // The bounding sphere's centre must be inside: the deepest voxel centre.
    std::size_t bx = 0, by = 0, bz = 0;
    for (std::size_t z = 0; z < g.size[2]; ++z)
      for (std::size_t y = 0; y < g.size[1]; ++y)
        for (std::size_t x = 0; x < g.size[0]; ++x)
          if (g(x, y, z) < g(bx, by, bz)) bx = x, by = y, bz = z;
    const imgmesh::Vec3 c = g.world(double(bx), double(by), double(bz));
    double r2 = 0;  // to the farthest corner of the grid
    for (int k = 0; k < 8; ++k) {
      const imgmesh::Vec3 q = g.world((k & 1) ? double(g.size[0] - 1) : 0, (k & 2) ? double(g.size[1] - 1) : 0,
                                      (k & 4) ? double(g.size[2] - 1) : 0);
      r2 = std::max(r2, (q[0] - c[0]) * (q[0] - c[0]) + (q[1] - c[1]) * (q[1] - c[1]) + (q[2] - c[2]) * (q[2] - c[2]));
    }
    auto f = [&pu](const Point& p) -> FT { return pu.value({p.x(), p.y(), p.z()}); };
    using Function = decltype(f);
    CGAL::Implicit_surface_3<GT, Function> surface(f, Sphere(Point(c[0], c[1], c[2]), r2 * 1.01), 1e-6 * h);
    CGAL::Surface_mesh_default_criteria_3<Tr> criteria(30.0, radius * h, distance * h);
    Tr tr;
    C2t3 c2t3(tr);
    const auto t0 = std::chrono::steady_clock::now();
    CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag());
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ofstream out(argv[2]);
    CGAL::output_surface_facets_to_off(out, c2t3);
    // |f| at the triangles' centroids, as implicit2mesh's --stats reports it.
    double max_centroid = 0;
    for (auto it = c2t3.facets_begin(); it != c2t3.facets_end(); ++it) {
      imgmesh::Vec3 m{0, 0, 0};
      for (int k = 1; k < 4; ++k) {
        const Point& p = it->first->vertex((it->second + k) & 3)->point();
        m[0] += p.x() / 3; m[1] += p.y() / 3; m[2] += p.z() / 3;
      }
      max_centroid = std::max(max_centroid, std::abs(pu.value(m)));
    }
    std::cout << secs << ' ' << c2t3.number_of_facets() << ' ' << max_centroid << '\n';
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "surface_mesher_peer: " << e.what() << '\n';
    return 1;
  }
}
