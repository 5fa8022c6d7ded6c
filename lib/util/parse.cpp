#include "util/parse.hpp"

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <string>

namespace imgmesh {

// from_chars takes the common forms; whatever it refuses or leaves unread
// ('+1', '0x1p3', out of range) goes to the C function, which has the last word.
bool parse_real(std::string_view s, double& v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec == std::errc() && r.ptr == s.data() + s.size()) return true;
  const std::string c(s);
  char* e = nullptr;
  v = std::strtod(c.c_str(), &e);
  return e != c.c_str() && *e == '\0';
}

bool parse_integer(std::string_view s, long long& v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec == std::errc() && r.ptr == s.data() + s.size()) return true;
  const std::string c(s);
  char* e = nullptr;
  errno = 0;
  v = std::strtoll(c.c_str(), &e, 10);
  return e != c.c_str() && *e == '\0' && errno != ERANGE;
}

} // namespace imgmesh
