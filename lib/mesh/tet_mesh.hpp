// Tetrahedral meshes as plain data (implicit2tet's output, meshinfo's
// input), their element quality (radius-edge ratio, dihedral angles,
// volume per region) and their combinatorial checks (orientation,
// conformity, the boundary of a region). No CGAL; world coordinates.
#pragma once
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace imgmesh {

struct TetMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 4>> tets;        // 0-based, det(b-a, c-a, d-a) > 0
  std::vector<int> tet_region;                 // per tetrahedron, >= 1 (seg2tet --outside: 0 the background)
  std::vector<std::array<int, 3>> triangles;   // the boundary, counter-clockwise seen from outside
  std::vector<int> triangle_region;            // per triangle: the region it bounds
  // Regions' names where they have one (seg2tet: the labels' names of a
  // 3D Slicer segmentation): Gmsh physical names, Abaqus sets.
  std::map<int, std::string> region_names;
  // Optional, per triangle: the two regions it separates (its region
  // first, 0 for none), seg2tet's label pairs. Gmsh 4.1 then gets a surface
  // entity per pair, in its region's boundary group and in a group of its
  // own ("a|b", by the regions' names where they have them); Gmsh 2.2 an
  // elementary tag per pair; Abaqus a surface INTERFACE_a_b per pair.
  std::vector<std::array<int, 2>> triangle_pair;
};

// Six times the signed volume: positive for a positively oriented tetrahedron.
double tet_orient(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                  const std::array<double, 3>& d);
// Circumradius over shortest edge (infinity when degenerate).
double tet_radius_edge_ratio(const std::array<double, 3>& a, const std::array<double, 3>& b,
                             const std::array<double, 3>& c, const std::array<double, 3>& d);
double tet_circumradius(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                        const std::array<double, 3>& d);
// The six interior dihedral angles, in degrees (0 when degenerate).
std::array<double, 6> tet_dihedral_angles(const std::array<double, 3>& a, const std::array<double, 3>& b,
                                          const std::array<double, 3>& c, const std::array<double, 3>& d);
// Their cosines (1 when degenerate), in the same order: acos is monotone,
// so the smallest angle is dihedral_degrees of the largest cosine, and a
// test against a bound needs no acos for most tetrahedra.
std::array<double, 6> tet_dihedral_cosines(const std::array<double, 3>& a, const std::array<double, 3>& b,
                                           const std::array<double, 3>& c, const std::array<double, 3>& d);
double dihedral_degrees(double cosine);

// The smallest dihedral angle (degrees) when it is below `bound`, else
// some angle >= bound: acos only near or under the bound (the cosine test
// has room for acos's rounding), not for every cell of every scan.
double smallest_dihedral_below(const std::array<double, 3>& a, const std::array<double, 3>& b,
                               const std::array<double, 3>& c, const std::array<double, 3>& d, double bound);

// How far a tetrahedron is beyond Delaunay refinement's bounds, 0 when
// within them (implicit2tet's and seg2tet's cell refinement): above the
// radius-edge bound R, 1 + ratio / R; above the circumradius bound S (> 0),
// 1 + circumradius / S; the larger. Else, for a sliver (a dihedral angle
// under sliver_angle > 0, circumradius at least `floor`: smaller ones have
// no insertion floor), 1 - angle / sliver_angle in (0, 1], below every
// other bad one. r2: its squared circumradius (from the caller's centre).
double refinement_badness(const std::array<std::array<double, 3>, 4>& p, double r2, double ratio_bound,
                          double size_bound, double sliver_angle, double floor, bool& sliver);

struct TetQualityReport {
  std::size_t tetrahedra = 0;
  double max_radius_edge_ratio = 0, mean_radius_edge_ratio = 0;
  double max_circumradius = 0;
  double min_dihedral = 0, max_dihedral = 0;  // degrees
  std::size_t under_10_degrees = 0;           // tetrahedra with a dihedral angle under 10 degrees
  std::array<std::size_t, 9> min_dihedral_histogram{};  // smallest dihedral per tetrahedron, 10-degree bins to 90
  std::array<std::size_t, 6> ratio_histogram{};         // radius-edge ratio in [0.6,1), [1,1.5), [1.5,2), [2,3), [3,5), >= 5
  std::map<int, double> volume_by_region;
  double total_volume = 0;
  // Per region, for meshinfo's report of several regions (not in to_json:
  // a one-region mesh's report stays as it was).
  struct Region {
    std::size_t tetrahedra = 0;
    double max_radius_edge_ratio = 0, min_dihedral = 180;  // degrees
  };
  std::map<int, Region> by_region;
  double share_under_10() const { return tetrahedra ? double(under_10_degrees) / double(tetrahedra) : 0; }
  Json to_json() const;
};
TetQualityReport tet_quality(const TetMesh& mesh);

// Conformity of a tetrahedral mesh: every triangle a face of one or two
// tetrahedra, traversed oppositely by the two, no two tetrahedra on the same
// four vertices, every tetrahedron of positive volume.
struct TetConformity {
  std::size_t nonpositive = 0, duplicates = 0, overfull_faces = 0, inconsistent_faces = 0, bad_ids = 0;
  std::size_t interior_faces = 0, boundary_faces = 0;
  bool ok() const { return !nonpositive && !duplicates && !overfull_faces && !inconsistent_faces && !bad_ids; }
  Json to_json() const;
};
TetConformity tet_conformity(const TetMesh& mesh);

// The faces with a tetrahedron of `region` on one side only (region 0: of
// any region), oriented outward from it, in a deterministic order.
std::vector<std::array<int, 3>> tet_boundary(const TetMesh& mesh, int region = 0);

// The faces between its regions, each once, as a surface with a label
// pair per triangle (the interface certificate's input,
// surfacenets/interface_certificate.hpp): a face of tetrahedra of two
// regions, or of one region (not 0) and nothing, oriented out of the higher
// region, pair (higher, lower), nothing being region 0. Faces in three
// tetrahedra or more are left out (tet_conformity counts them). In the
// order of their sorted vertex ids.
void region_interfaces(const TetMesh& mesh, std::vector<std::array<int, 3>>& triangles,
                       std::vector<std::array<std::int32_t, 2>>& pairs);

// The boundary the mesh states (its triangles, each with the region it
// bounds) against its tetrahedra's: every face on a region's boundary (a
// face of one of its tetrahedra with none of it across) stated exactly
// once, as a triangle of a region it bounds, oriented out of that region
// (an interface between two regions once, on either side). "" when so,
// else what differs first.
std::string boundary_mismatch(const TetMesh& mesh);

} // namespace imgmesh
