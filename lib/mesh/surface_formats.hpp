// Surface formats that carry per-face data for the programs users open the
// meshes in: VTK XML PolyData (.vtp) and legacy VTK (.vtk) for ParaView and
// 3D Slicer, Gmsh .msh (4.1 or 2.2) with a physical group per label or
// component, and binary PLY with face properties (MeshLab, Slicer). Every
// face carries its component id (0 = the largest component) and, when the
// mesh has labels, its label, and when it has label pairs (interfaces),
// its (behind, front) pair: VTK cell data "labels" of 2 components, PLY
// properties "int label_behind" and "int label_front", a .msh physical
// group per pair; the labels' names (label_names) go in the
// VTK files' field data (label_values, label_names), the .msh physical
// names and PLY header comments ("comment label_name L NAME"); vertex
// normals go where the format holds them.
// Coordinates are world coordinates as ITK's (LPS); the VTK and PLY headers
// say "SPACE=LPS", which 3D Slicer reads. Plain writers on a stream: no
// OpenMesh, no files (surface_io.cpp opens the atomic output).
#pragma once
#include "mesh/surface_io.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace imgmesh {

// Per face, the id of its connected component (faces sharing a vertex are
// connected), numbered by decreasing face count, ties by first face.
std::vector<int> face_components(const SurfaceMesh& mesh);

// binary: .vtp with appended raw data, zlib-compressed (as vtkXMLWriter
// writes by default), Float64 points; legacy .vtk BINARY (big-endian, as
// the legacy format requires), double points. Else ASCII, 17 digits.
void write_vtp(std::ostream& out, const SurfaceMesh& mesh, const std::vector<int>& component, bool binary);
void write_vtk_legacy(std::ostream& out, const SurfaceMesh& mesh, const std::vector<int>& component, bool binary);
// version "4.1" or "2.2". One surface entity per component; its physical
// group is its label (named as label_names says, else "label L") when the
// mesh has labels, else the component ("component C", tag C + 1). With
// label pairs, one entity per pair instead, its physical group of tag r
// (the pair's rank, from 1, pairs in increasing order) named "a|b" (each
// label by its name where label_names has one), and a section
// $LabelPairs ("r a b" per group) that Gmsh and meshio skip. Normals
// as a node data view. binary: Gmsh's binary form (little-endian, doubles).
void write_msh(std::ostream& out, const SurfaceMesh& mesh, const std::vector<int>& component,
               const std::string& version, bool binary);
// Binary little-endian or ASCII (9 digits: the same floats), float
// coordinates (and normals), face properties "int component" and, with
// labels, "int label", with label pairs "int label_behind", "int label_front".
void write_ply(std::ostream& out, const SurfaceMesh& mesh, const std::vector<int>& component, bool binary);

} // namespace imgmesh
