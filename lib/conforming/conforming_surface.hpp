// The conforming surface complex of a well-composed label image (issue 40,
// route 1): the restricted Delaunay triangulation of the partition that the
// labelling function lambda (label_function.hpp) makes of space, refined
// as DELMESH refines one surface (thesis 7.6), every interface meshed once.
//
//   cells      each Delaunay cell carries lambda at its circumcentre; a facet
//              is restricted when its two cells' labels differ (its dual
//              Voronoi edge crosses the interface between them); its surface
//              centre is where lambda changes along that edge.
//   seeds      points of every patch of K(X): where lambda changes between
//              the two voxel centres of a face, faces a few voxels apart and
//              at least four per patch (thesis 8.1's role: every patch and
//              every label's component sampled from the start).
//   REFINE     in passes over the cells made since the last one, each
//              candidate re-checked before it goes in, by priority:
//     VorEdge    a Voronoi edge along which lambda changes twice or more:
//                its change farthest from the facet's first vertex;
//     TopoDisk   per label, at every vertex, the label's restricted facets
//                around it form one disk (one cycle in the vertex's link):
//                where not, the surface centre of its largest facet there.
//                (Each label's surface is then a 2-manifold; at a curve the
//                labels' disks make the "book" of half-disks.)
//     QUALITY    a restricted facet's radius-edge ratio above rho_0;
//     distance   a surface centre farther than E from its facet's plane;
//     VoxelSides every voxel centre next to an interface in a cell of its
//                own label, else the first change of lambda from the centre
//                towards that cell's circumcentre.
//   certificate  the caller's; where it fails, every restricted facet near
//              the K(X) patches it names gets its surface centre, and REFINE
//              again (a patch sampled too coarsely shows as split, merged or
//              pinched).
//   cells      (tets.on, seg2tet) rounds until one inserts nothing, worst
//              first (ties by sorted vertex ids; a round's bad cells the
//              last round's still there and those made since): every
//              cell of a label but 0 whose radius-edge ratio exceeds R (or
//              circumradius S, or, after those, a dihedral angle under the
//              sliver bound) gets its circumcentre, unless that lies in the
//              surface Delaunay ball of a restricted facet (the facets of
//              its conflict zone): then that facet's surface centre
//              (Oudot-Rineau-Yvinec's rule, implicit2tet's), for a sliver
//              a point of the interface an eighth of the ball's radius off
//              it (a flat patch's cocircular points made no finer lattice
//              of cocircular points); REFINE after
//              each round, where a restricted facet with a vertex off the
//              interfaces (a cell's circumcentre) gets its surface centre;
//              with tets.on the certificate runs after the cells (their
//              encroached facets' points refine the surface where it would;
//              before them its rounds put in 3x the points on the brain),
//              the cells again if its rounds inserted (three times at most);
//              then every voxel centre located (its cell's label).
//   output     every restricted facet once, with (behind, front) = (higher,
//              lower label), oriented out of behind (K(X)'s convention);
//              tets.on: the cells of every label but 0, region = label,
//              and every restricted facet once as a triangle of the
//              higher label (region = behind), oriented out of it;
//              tets.outside: the background's cells too, region 0, B's
//              faces triangles of region 0 (pair {0, 0}).
// The Delaunay triangulation embeds the complex: no two triangles cross.
// What the mesh is, against K(X), is the interface certificate's to say
// (surfacenets/interface_certificate.hpp); this file certifies nothing.
#pragma once
#include "conforming/label_function.hpp"
#include "mesh/tet_mesh.hpp"
#include "util/json.hpp"
#include "wellcomposed/interface_complex.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

// Tetrahedra of every label (seg2tet), implicit2tet's bounds.
struct ConformingTetOptions {
  bool on = false;
  double cell_ratio = 2;      // R: radius-edge ratio bound of every labelled tetrahedron
  double cell_size = 0;       // S: circumradius bound (world); 0: none
  std::vector<std::pair<std::int32_t, double>> cell_size_by_label;  // S of these labels instead
  double size_of(std::int32_t label) const {
    for (const auto& e : cell_size_by_label)
      if (e.first == label) return e.second;
    return cell_size;
  }
  double sliver_angle = 10;   // degrees: smaller dihedral angles refined after R and S (best effort); 0: off
  long long max_cell_points = 1000000;
  int max_rounds = 100;
  // seg2tet --outside: the background's cells too (label 0) up to the
  // image box B (conforming_cells.cpp), B's faces their boundary.
  bool outside = false;
};

struct ConformingOptions {
  double ratio = 1.2;         // rho_0: angles >= asin(1 / (2 rho_0)) = 24.6 degrees
  double max_distance = 0;    // E (world); 0: 0.3 of the smallest spacing
  double seed_spacing = 4;    // voxels between the seeds of a patch
  // lambda's samples along a segment (voxels of the smallest spacing):
  // every run of one label longer than this holds a sample and is found
  // (test_label_function); a shorter one (a corner cut) may be missed, the
  // certificate decides. 0.5 (half the samples, head 128^3 -12% CPU) left
  // the bundled brain map uncertified after one round (a handle on patch
  // 2|1 where 0.25 certifies it in two).
  double step = 0.25;
  std::size_t max_points = 2000000;
  bool voxel_sides = true;
  // The certificate (surfacenets/interface_certificate.hpp, the caller's):
  // the places where it fails (InterfaceCertificate::failing_places: world
  // points on the wrong pieces), empty when it holds. Each round the
  // surface centres of the restricted facets within a voxel of those places
  // go in and REFINE runs again, at most `certificate_rounds` times, while
  // each round leaves fewer places, and not after a round that more than
  // doubled the points and left more than half of them. Unset: no rounds.
  std::function<std::vector<Vec3>(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                  const std::vector<std::array<std::int32_t, 2>>& pairs)>
      certificate;
  int certificate_rounds = 8;
  ConformingTetOptions tets;
  std::function<void(const std::string&)> progress;
  unsigned threads = 1;  // lambda's walks along a pass's Voronoi edges (the same mesh whatever the number; 0: all cores)
};

struct ConformingSurface {
  std::vector<Vec3> points;                         // world
  std::vector<std::array<int, 3>> triangles;        // oriented out of pairs[t][0]
  std::vector<std::array<std::int32_t, 2>> pairs;   // (behind, front), behind > front
  // Points inserted per step: seed, vor_edge, topo_disk, patch_fan,
  // quality, distance, voxel_side, certificate, cell, cell_facet (an
  // encroached facet's surface centre), off_surface.
  std::array<long long, 11> inserted{};
  long long refused = 0;       // candidates within 1e-6 voxel of a vertex
  long long passes = 0;
  int certificate_rounds = 0;  // rounds that refined where the certificate failed
  // This very mesh was the certificate callback's last input (the caller
  // may keep that certificate rather than run it again).
  bool certified_as_is = false;
  bool max_points_hit = false;
  // tets.on: the tetrahedra (TetMesh: region = label; the interfaces, each
  // once, with the higher label), the rounds, and every voxel centre
  // located in the triangulation: those in a cell of another label.
  TetMesh tets;
  int cell_rounds = 0;
  bool cell_rounds_exhausted = false, cell_points_exhausted = false;
  long long sliver_points = 0;
  std::size_t centres_checked = 0, centres_wrong = 0;
  // tets.outside: B's volume, the box points (splits of B's edges and
  // faces; refused: within the insertion floor), and whether the box
  // triangles lie on B's faces and add up to its area.
  double box_volume = 0;
  long long box_points = 0, box_refused = 0;
  bool box_covered = false;
  Json to_json() const;
};

// Throws Error when K(X) is not that of `x` (X held in the narrowest type
// its labels fit: image/narrow_labels.hpp).
ConformingSurface conforming_surface(const LabelFunction& lambda, const NarrowLabelImage& x, const InterfaceComplex& k,
                                     const ConformingOptions& options = {});

} // namespace imgmesh
