// Deterministic hashing for seeded sampling and tie-breaks: splitmix64's
// finaliser (Steele, Lea and Flood 2014), and a hash's top 53 bits as a
// double in [0, 1).
#pragma once
#include <cstdint>

namespace imgmesh {

inline std::uint64_t mix64(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// The splitmix64 generator's output for state x.
inline std::uint64_t splitmix64(std::uint64_t x) { return mix64(x + 0x9E3779B97F4A7C15ull); }

inline double unit01(std::uint64_t h) { return double(h >> 11) * 0x1.0p-53; }

} // namespace imgmesh
