// implicit2mesh's and implicit2tet's input: the implicit function file read
// with the surface mesher's options resolved from its grid.
#pragma once
#include "cli/cli.hpp"
#include "implicit/partition_of_unity.hpp"
#include "surface/restricted_delaunay.hpp"
#include "surface_options.hpp"

#include <string>

namespace imgmesh {

struct MesherInput {
  PartitionOfUnity f;                 // on g's samples clamped far from S
  RestrictedDelaunayOptions options;  // the bounds resolved; seed, threads... at their defaults
};

// The options checked first (a bad option is said before the file is read),
// then IN read (- for stdin), the options resolved from its voxel spacing,
// and f built on g clamped far from S for them: the same S and signs, a
// fraction of the memory (PartitionOfUnity::clamp_for). A crop (img2wc
// --label) is placed back in its scan's grid, so that the mesh is the whole
// grid's; when its margin does not cover the clamp (a larger
// --max-distance), the crop is meshed alone, said on stderr.
MesherInput read_mesher_input(const cli::Tool& tool, const std::string& in, const SurfaceOptions& surface_options);

} // namespace imgmesh
