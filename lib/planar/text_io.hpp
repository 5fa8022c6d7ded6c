// Fast text for the planar formats: fields split in place, numbers parsed by
// util/parse.hpp and written with std::to_chars into large chunks, with the
// results printf("%.17g") gave (10^6 quads: ~3 CPU-s of I/O with stdio).
#pragma once
#include "util/atomic_file.hpp"
#include "util/parse.hpp"

#include <charconv>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace imgmesh {

// The characters operator>> skips in the classic locale.
constexpr bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

// The fields of a line up to a '#' (a comment) into `fields`, as views of
// the line, split on blanks.
void split_fields(std::string_view line, std::vector<std::string_view>& fields);

// An AtomicOutput written in chunks of ~1 MiB: reals as printf("%.17g")
// (every bit kept; to_chars with precision 17 is specified to match it).
class TextOutput {
public:
  explicit TextOutput(const std::string& path) : out_(path), buf_(chunk + room) {}
  TextOutput& operator<<(double v) {
    reserve();
    const char* end = std::to_chars(&buf_[n_], &buf_[0] + buf_.size(), v, std::chars_format::general, 17).ptr;
    n_ = std::size_t(end - &buf_[0]);
    return *this;
  }
  template <class I, std::enable_if_t<std::is_integral_v<I> && !std::is_same_v<I, char>, int> = 0>
  TextOutput& operator<<(I v) {
    reserve();
    n_ = std::size_t(std::to_chars(&buf_[n_], &buf_[0] + buf_.size(), v).ptr - &buf_[0]);
    return *this;
  }
  TextOutput& operator<<(char c) {
    reserve();
    buf_[n_++] = c;
    return *this;
  }
  TextOutput& operator<<(std::string_view s);
  // Writes what is left and moves the file into place. Throws Error.
  void commit();

private:
  static constexpr std::size_t chunk = 1 << 20, room = 64;  // room: one number or char
  void reserve() {
    if (n_ > chunk) flush();
  }
  void flush();
  AtomicOutput out_;
  std::vector<char> buf_;
  std::size_t n_ = 0;
};

} // namespace imgmesh
