// meshinfo's library: read any mesh of the suite and describe it (topology
// and element quality) as one ordered JSON object, or as text.
#pragma once
#include "mesh/surface_certificate.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/topology.hpp"
#include "surfacenets/interface_certificate.hpp"
#include "util/json.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace imgmesh {

// A polygon mesh of any origin: surfaces (OFF/PLY/OBJ/STL) or planar meshes
// (.ele/.node, OFF with z = 0).
struct PolyMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<int>> faces;
  bool planar = false;  // every z is 0: planar quality (quad convexity, Joe's mu) applies
  std::string format;   // "ele", "off", "ply", ...
  // .ele with element attributes: each face's region label (its first
  // attribute, an integer); empty otherwise.
  std::vector<std::int32_t> region;
  // Per face, the label pair (behind, front) it separates, the face
  // oriented out of behind, when the file gives one (seg2mesh --fast's
  // .vtp, .vtk, .ply); empty otherwise.
  std::vector<std::array<std::int32_t, 2>> interfaces;
};

// By extension: .ele (+ .node), .off (any polygons), .ply/.obj/.stl/.vtp/.vtk
// (triangles). "-" reads OFF from stdin. Throws Error.
PolyMesh read_poly_mesh(const std::string& path);
// A surface read by read_surface (a .msh of triangles among them), its
// label pairs kept; format names it in the report ("msh").
PolyMesh poly_mesh(const SurfaceMesh& surface, const std::string& format);

// Everything meshinfo reports: counts, topology (MeshTopology::to_json, with
// "components" and "euler" first), triangle and quad quality.
Json mesh_report(const PolyMesh& m);

// The "image" section for --image (3D): bdCA(X)'s components, whether the
// mesh is certified against it ("matches"), the correspondence and the
// certificate's checks.
Json image_comparison(const MeshTopology& image, const SurfaceCertificate& certificate);

// Human-readable lines for a report made by mesh_report.
std::string format_report(const Json& report);

// meshinfo's result: the report, and with an image whether the mesh is
// certified against it (the guarantee it checks).
struct MeshInfo {
  Json report;  // mesh_report(), with "image" (image_comparison) when compared
  bool compared = false, matches = true;
  bool conforming = true;  // tetrahedral meshes: positive, conforming tetrahedra
  std::string image_name;
  SurfaceCertificate certificate;    // 3D: the surface's against bdCA(X)
  ComponentCorrespondence by_place;  // 2D: the certificate by correspondence of regions (planar)
  bool by_interfaces = false;        // 3D label pairs: the interface certificate decides
  InterfaceCertificate interfaces;
  bool by_tet_labels = false;        // tetrahedra against a label map: label_tet_mesh_info's certificate decides
  std::string tet_labels_failure;    // its first failed check, "CHECK: why"
  Json to_json() const;  // vertices, faces, components, euler; matches_image when compared
  std::string failed_guarantee() const;
};

// mesh_report of `mesh` and, when `image` is given, its certificate against
// bdCA(X) of the image's foreground (certify_surface, the mesh's points in
// the image's world coordinates, polygons split into triangles by a fan from
// their first corner). A 2D image goes to planar_mesh_info as a 0/1 label
// image. Throws Error naming mesh_name (no face, bad ids) or image_name (no
// foreground, not well-composed).
MeshInfo mesh_info(const PolyMesh& mesh, const std::string& mesh_name, const BinaryImage* image = nullptr,
                   const std::string& image_name = "", const CertificateOptions& options = {});

// A planar mesh against a well-composed 2D label image (well_composed_labels
// of what img2poly read): the certificate by correspondence of regions
// (match_regions). With region labels the mesh's foreground is its faces of
// nonzero label, each region matched within its label; without, every face is
// foreground and the image's nonzero pixels are one label. reach: pixels, see
// match_regions (img2poly's tolerance + 1). Throws Error as mesh_info, and on
// a mesh that is not planar.
MeshInfo planar_mesh_info(const PolyMesh& mesh, const std::string& mesh_name, const LabelImage& labels,
                          const std::string& image_name, double reach = 2);

// A mesh with a label pair per face (PolyMesh::interfaces) against a 3D
// label image: the interface certificate (surfacenets/interface_certificate.hpp:
// every pair's patches against K(X)'s, no two triangles crossing, each
// label's surface, voxel sides) against the image's partition made
// well-composed as seg2mesh --fast and img2wc --labels all make it (a map
// already well-composed is unchanged), in "interface_image". Throws Error as
// mesh_info, and on faces that are not triangles.
MeshInfo interface_mesh_info(const PolyMesh& mesh, const std::string& mesh_name, LabelImage labels,
                             const std::string& image_name, const InterfaceCertificateOptions& options = {});

// A tetrahedral mesh (.msh, .mesh, .vtu): mesh_info of the boundary of all
// its tetrahedra (region 1's when there are others; certified against
// bdCA(X) when `image` is given), with a
// "tetrahedra" section: conformity and orientation, radius-edge ratios,
// dihedral angles (smallest, histogram), volume per region, and with an
// image the foreground's voxel volume. Without an image, a mesh of several
// regions gets a line per region (tetrahedra, volume, largest radius-edge
// ratio, smallest dihedral angle).
MeshInfo tet_mesh_info(const TetMesh& mesh, const std::string& mesh_name, const BinaryImage* image = nullptr,
                       const std::string& image_name = "", const CertificateOptions& options = {});

// A tetrahedral mesh with a region per label against a 3D label map
// (several labels), the map repaired as seg2tet and seg2mesh repair it
// (make_well_composed_partition): certify_tet_labels (meshinfo/tet_labels.hpp)
// in "certificate", the interface certificate of the regions' interfaces in
// "interface_image"; the report's surface is those interfaces, and the
// "tetrahedra" section has a line per region with its label's voxel volume.
// Throws Error as interface_mesh_info, and on a mesh without tetrahedra.
MeshInfo label_tet_mesh_info(const TetMesh& mesh, const std::string& mesh_name, LabelImage labels,
                             const std::string& image_name, const InterfaceCertificateOptions& options = {});

} // namespace imgmesh
