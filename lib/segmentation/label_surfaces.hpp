// Every label of a segmentation meshed in one call (seg2mesh): per label,
// the foreground {v = L} made well-composed (ch. 5), its implicit function
// (ch. 6) and its certified restricted Delaunay surface (ch. 7-8), exactly
// what img2wc | wc2implicit | implicit2mesh do for --label L; labels run in
// parallel, one thread a label. The surfaces are then joined into one mesh
// whose faces carry their label (and its name, from a 3D Slicer
// segmentation): neighbouring labels give separate closed surfaces (a shared
// interface mesh is later work).
#pragma once
#include "image/grid.hpp"
#include "image/slicer_segmentation.hpp"
#include "implicit/crop.hpp"
#include "mesh/surface_io.hpp"
#include "surface/restricted_delaunay.hpp"
#include "util/json.hpp"
#include "wellcomposed/well_composed.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace imgmesh {

struct LabelSurfacesOptions {
  std::vector<long long> labels;       // empty: every nonzero value present
  LabelNames names;                    // the labels' names where the image gives them (read_labels)
  RepairMode mode = RepairMode::Add;   // img2wc --mode
  RestrictedDelaunayOptions mesher;    // seed, bounds (threads: set by jobs)
  bool normals = false;                // per-vertex normals from grad f
  int jobs = 1;                        // labels meshed at once (>= 1)
  int threads = 1;                     // threads in all; left over ones go to the labels' meshers
  std::function<void(const std::string&)> progress;  // called from the workers, serialised
};

struct LabelSurface {
  long long label = 0;
  std::string name;                    // from LabelSurfacesOptions::names, or empty
  std::size_t voxels = 0;              // of the label in the input
  std::array<std::size_t, 3> crop{0, 0, 0};  // the grid it was meshed on: its box plus the margin
  std::size_t changed = 0;             // voxels the well-composed repair changed
  std::string well_composed_failure;   // make_well_composed's failed guarantee, or empty
  RestrictedDelaunayResult mesh;       // the certified surface of this label
  std::size_t first_face = 0;          // its faces in the joined mesh: [first_face, first_face + triangles)
  double seconds = 0;
};

struct LabelSurfacesResult {
  std::vector<LabelSurface> labels;    // ascending label
  SurfaceMesh mesh;                    // all surfaces, mesh.labels (and label_names) set
  int jobs = 1;
  Json to_json() const;
  // Each label whose surface is not certified, named: "label 3: ...".
  std::string failed_guarantee() const;
};

// The label images these take: held at 1, 2 or 4 bytes a voxel
// (read_labels_narrow), T one of std::uint8_t, std::uint16_t, std::int32_t.

// The nonzero values of an image, ascending.
template <class T> std::vector<long long> labels_present(const Image<T>& image);
// The labels to mesh: `asked` (every nonzero value when empty), ascending,
// once each. Throws Error on a 2D image, an image without labels, or an
// asked label absent from the image (naming those present).
template <class T> std::vector<long long> chosen_labels(const Image<T>& image, const std::vector<long long>& asked);

// Throws Error on a label absent from the image (naming those present), an
// image without labels, or a 2D image; an Error while meshing a label is
// thrown again as "label L: ...". Takes the image (move it in): its voxels
// are let go once every label's crop is made.
template <class T> LabelSurfacesResult mesh_label_surfaces(Image<T> image, const LabelSurfacesOptions& options);

} // namespace imgmesh
