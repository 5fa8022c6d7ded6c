// Numbers in text, fast: std::from_chars for the common forms, with exactly
// the results strtod / strtoll give (the readers of every text format).
#pragma once
#include <string_view>

namespace imgmesh {

// All of s as a number, accepting exactly what strtod / strtoll (base 10,
// C locale) accept; false if s is not entirely one number or (integers) out
// of range. Reals may come out infinite or NaN ("inf", "nan", "1e400").
bool parse_real(std::string_view s, double& v);
bool parse_integer(std::string_view s, long long& v);

} // namespace imgmesh
