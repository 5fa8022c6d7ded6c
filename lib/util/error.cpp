#include "util/error.hpp"

namespace imgmesh {
std::string Error::message() const {
  return path_.empty() ? std::string(what()) : path_ + ": " + what();
}
} // namespace imgmesh
