#include "util/path.hpp"

#include <algorithm>
#include <cctype>

namespace imgmesh {

std::string extension_of(const std::string& path) {
  auto slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  std::transform(base.begin(), base.end(), base.begin(), [](unsigned char c) { return std::tolower(c); });
  auto dot = base.rfind('.');
  if (dot == std::string::npos || dot == 0) return "";
  std::string ext = base.substr(dot);
  if (ext == ".gz") {
    auto dot2 = base.rfind('.', dot - 1);
    if (dot2 != std::string::npos && dot2 != 0) ext = base.substr(dot2);
  }
  return ext;
}

std::string replace_extension(const std::string& path, const std::string& ext) {
  std::string old = extension_of(path);
  return path.substr(0, path.size() - old.size()) + ext;
}

} // namespace imgmesh
