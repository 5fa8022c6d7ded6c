// File names by their extension: the formats are chosen by it.
#pragma once
#include <string>

namespace imgmesh {

// The extension of a path in lower case, with a leading dot, counting ".gz"
// compound extensions (".nii.gz"); "" if none.
std::string extension_of(const std::string& path);
// Replace the extension (as extension_of sees it) by ext ("." included).
std::string replace_extension(const std::string& path, const std::string& ext);

} // namespace imgmesh
