// Benchmark peer of seg2mesh --conforming (issue 40; not installed, not a
// test): CGAL 5.5's Mesh_3 on a whole label map, its surface complex written
// with label pairs as seg2mesh writes interfaces, so that `meshinfo OUT
// --image LABELS` certifies it per label and per interface.
//   mesh3_labels_peer LABELS OUT.vtp [DISTANCE [SIZE]]
//   mesh3_labels_peer LABELS OUT.msh|.vtu|.mesh [DISTANCE [SIZE]]   (seg2tet's peer, issue 41)
// LABELS: any integer label image lib/image reads (labels 0..65535), padded
// by one background voxel (a label touching the side gets a closed surface).
// Labeled_mesh_domain_3::create_labeled_image_mesh_domain (labels
// interpolated trilinearly, CGAL's default), seeded from every connected
// component of every label (initialize_triangulation_from_labeled_image, as
// mesh3_image.hpp's "seeded"), then refine_mesh_3 with the surface criteria
// only: facet angle 30 degrees, facet distance DISTANCE (default 0.25) and
// facet size SIZE (default 0: unbounded) in voxels of the smallest spacing;
// no cell criteria, no manifold criterion (it would not end at curves where
// three labels meet), no perturb, no exude.
// OUT: every facet of the complex (between two different subdomains,
// 0 the background) once, as (behind, front) = (higher label, lower label),
// oriented from behind into front (its normal points into front), in world
// coordinates. Prints "seconds triangles smallest_angle_deg" on its last
// line (CGAL prints progress on stdout before it); the seconds are Mesh_3's
// (domain, seeding, refinement), not reading or writing.
// A tetrahedral OUT: the same with cell radius-edge ratio 2 and Mesh_3's
// default perturb and exude (issue 41's peer), every cell in the complex
// written with its subdomain as region and the complex's facets as
// triangles; prints "seconds tetrahedra smallest_dihedral_deg share_under_10
// largest_ratio".
#include "mesh3_image.hpp"
#include "mesh/surface_io.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/volume_io.hpp"
#include "mesh/triangle_quality.hpp"

#include <CGAL/Random.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace {

// The complex's facets, each between the subdomains of its two cells (a
// cell out of the complex is subdomain 0). A facet whose cells agree (its
// patch index says otherwise) is counted in `same` and skipped.
// The complex's vertices numbered by first use, in world coordinates.
struct VertexIndex {
  const mesh3::Tr& tr;
  const imgmesh::Geometry& g;
  std::vector<std::array<double, 3>>& points;
  std::map<mesh3::Tr::Vertex_handle, int> id;
  int operator()(mesh3::Tr::Vertex_handle v) {
    const auto [it, added] = id.emplace(v, int(points.size()));
    if (added) {
      const auto& q = tr.point(v).point();
      points.push_back(mesh3::world(g, {q.x(), q.y(), q.z()}));
    }
    return it->second;
  }
};

// The complex's facets as triangles numbered by `vertex`, with their pairs.
void complex_facets(const mesh3::C3t3& c3t3, const imgmesh::Geometry& g, VertexIndex& vertex,
                    std::vector<std::array<int, 3>>& triangles, std::vector<std::array<int, 2>>& pairs,
                    std::size_t& same) {
  using Tr = mesh3::Tr;
  const Tr& tr = c3t3.triangulation();
  const auto label = [&](Tr::Cell_handle c) { return c3t3.is_in_complex(c) ? int(c3t3.subdomain_index(c)) : 0; };
  // A reflecting direction flips the orientation.
  const auto& d = g.direction;
  const double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) +
                     d[2] * (d[3] * d[7] - d[4] * d[6]);
  same = 0;
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    Tr::Facet front = *f, behind = tr.mirror_facet(*f);
    if (label(front.first) > label(behind.first)) std::swap(front, behind);
    const int lo = label(front.first), hi = label(behind.first);
    if (lo == hi) {
      ++same;
      continue;
    }
    // The triangle turns counter-clockwise around a normal toward the
    // front cell's fourth vertex (away from the behind cell's when the
    // front cell is the infinite one).
    const bool finite = !tr.is_infinite(front.first);
    const auto [c, i] = finite ? front : behind;
    std::array<Tr::Vertex_handle, 3> v{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
    const auto side = CGAL::orientation(tr.point(v[0]).point(), tr.point(v[1]).point(), tr.point(v[2]).point(),
                                        tr.point(c->vertex(i)).point());
    if ((side == CGAL::POSITIVE) != finite) std::swap(v[1], v[2]);
    std::array<int, 3> t{vertex(v[0]), vertex(v[1]), vertex(v[2])};
    if (det < 0) std::swap(t[1], t[2]);
    triangles.push_back(t);
    pairs.push_back({hi, lo});
  }
}

imgmesh::SurfaceMesh surface_complex(const mesh3::C3t3& c3t3, const imgmesh::Geometry& g, std::size_t& same) {
  imgmesh::SurfaceMesh m;
  VertexIndex vertex{c3t3.triangulation(), g, m.points, {}};
  complex_facets(c3t3, g, vertex, m.triangles, m.interfaces, same);
  return m;
}

// Every cell in the complex, region = its subdomain, positively oriented in
// world coordinates; the complex's facets as the boundary (each once, of
// the higher subdomain).
imgmesh::TetMesh tetrahedra(const mesh3::C3t3& c3t3, const imgmesh::Geometry& g) {
  imgmesh::TetMesh m;
  VertexIndex vertex{c3t3.triangulation(), g, m.points, {}};
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    std::array<int, 4> t{vertex(c->vertex(0)), vertex(c->vertex(1)), vertex(c->vertex(2)), vertex(c->vertex(3))};
    if (imgmesh::tet_orient(m.points[std::size_t(t[0])], m.points[std::size_t(t[1])], m.points[std::size_t(t[2])],
                            m.points[std::size_t(t[3])]) < 0)
      std::swap(t[2], t[3]);  // a reflecting direction
    m.tets.push_back(t);
    m.tet_region.push_back(int(c3t3.subdomain_index(c)));
  }
  // The facets, each out of its higher subdomain (its normal points into
  // the lower), as the boundary of that region.
  std::size_t same = 0;
  complex_facets(c3t3, g, vertex, m.triangles, m.triangle_pair, same);
  for (const auto& p : m.triangle_pair) m.triangle_region.push_back(p[0]);
  return m;
}

template <class Word>
int run_tets(const imgmesh::LabelImage& x, const std::string& out, double distance, double size) {
  const double h = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
  const auto t0 = std::chrono::steady_clock::now();
  const CGAL::Image_3 image = mesh3::cgal_image<Word>(x);
  const mesh3::Domain domain = mesh3::Domain::create_labeled_image_mesh_domain(image);
  namespace p = CGAL::parameters;
  const mesh3::Criteria criteria =
      size > 0 ? mesh3::Criteria(p::facet_angle = 30, p::facet_distance = distance * h, p::facet_size = size * h,
                                 p::cell_radius_edge_ratio = 2)
               : mesh3::Criteria(p::facet_angle = 30, p::facet_distance = distance * h, p::cell_radius_edge_ratio = 2);
  mesh3::C3t3 c3t3;
  initialize_triangulation_from_labeled_image(c3t3, domain, image, criteria, Word(0));
  CGAL::refine_mesh_3(c3t3, domain, criteria);  // perturb and exude: Mesh_3's defaults
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const imgmesh::TetMesh m = tetrahedra(c3t3, x);
  imgmesh::write_tet_mesh(out, m);
  const imgmesh::TetQualityReport q = imgmesh::tet_quality(m);
  std::cout << '\n'
            << secs << ' ' << m.tets.size() << ' ' << q.min_dihedral << ' ' << q.share_under_10() << ' '
            << q.max_radius_edge_ratio << '\n';
  return 0;
}

template <class Word>
int run(const imgmesh::LabelImage& x, const std::string& out, double distance, double size) {
  if (imgmesh::is_tet_mesh_path(out)) return run_tets<Word>(x, out, distance, size);
  const double h = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
  const auto t0 = std::chrono::steady_clock::now();
  const CGAL::Image_3 image = mesh3::cgal_image<Word>(x);
  const mesh3::Domain domain = mesh3::Domain::create_labeled_image_mesh_domain(image);
  namespace p = CGAL::parameters;
  const mesh3::Criteria criteria = size > 0 ? mesh3::Criteria(p::facet_angle = 30, p::facet_distance = distance * h,
                                                              p::facet_size = size * h)
                                            : mesh3::Criteria(p::facet_angle = 30, p::facet_distance = distance * h);
  mesh3::C3t3 c3t3;
  initialize_triangulation_from_labeled_image(c3t3, domain, image, criteria, Word(0));
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_perturb(), p::no_exude());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t same = 0;
  const imgmesh::SurfaceMesh m = surface_complex(c3t3, x, same);
  if (same) std::cerr << "mesh3_labels_peer: " << same << " facets of the complex between cells of one subdomain, left out\n";
  imgmesh::write_surface(out, m);
  const double angle = imgmesh::triangle_quality_report(m).smallest_angle();
  std::cout << '\n' << secs << ' ' << m.triangles.size() << ' ' << angle << '\n';
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 5) {
    std::cerr << "usage: mesh3_labels_peer LABELS OUT.vtp [DISTANCE [SIZE]]\n";
    return 2;
  }
  try {
    // CGAL's default random is seeded from the clock; the seeds' directions
    // come from it: the same mesh every run.
    CGAL::get_default_random() = CGAL::Random(0);
    if (!imgmesh::is_surface_output(argv[2]) && !imgmesh::is_tet_mesh_path(argv[2]))
      throw std::runtime_error(std::string(argv[2]) + ": not " + imgmesh::kSurfaceExtensions);
    const double distance = argc >= 4 ? std::atof(argv[3]) : 0.25;
    const double size = argc >= 5 ? std::atof(argv[4]) : 0;
    const imgmesh::LabelImage x = imgmesh::pad(imgmesh::read_labels(argv[1]), {1, 1, 1}, {1, 1, 1});
    const auto [lo, hi] = std::minmax_element(x.data.begin(), x.data.end());
    if (*lo < 0 || *hi > 65535) throw std::runtime_error("labels must lie in 0..65535");
    if (*hi <= 255) return run<unsigned char>(x, argv[2], distance, size);
    return run<unsigned short>(x, argv[2], distance, size);
  } catch (const std::exception& e) {
    std::cerr << "mesh3_labels_peer: " << e.what() << '\n';
    return 1;
  }
}
