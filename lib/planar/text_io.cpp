#include "planar/text_io.hpp"

#include <array>
#include <cstring>

namespace imgmesh {

namespace {
// What a character is to split_fields: 0 part of a field, 1 blank, 2 comment
// (one look-up a character instead of seven comparisons).
constexpr auto kinds = [] {
  std::array<unsigned char, 256> k{};
  for (int c = 0; c < 256; ++c) k[std::size_t(c)] = blank(char(c)) ? 1 : c == '#' ? 2 : 0;
  return k;
}();
} // namespace

void split_fields(std::string_view line, std::vector<std::string_view>& fields) {
  const auto kind = [](char c) { return kinds[static_cast<unsigned char>(c)]; };
  fields.clear();
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && kind(line[i]) == 1) ++i;
    if (i == line.size() || kind(line[i]) == 2) break;
    const std::size_t b = i;
    while (i < line.size() && kind(line[i]) == 0) ++i;
    fields.push_back(line.substr(b, i - b));
  }
}

TextOutput& TextOutput::operator<<(std::string_view s) {
  if (n_ + s.size() > buf_.size()) flush();
  if (s.size() > buf_.size()) {
    out_.stream().write(s.data(), std::streamsize(s.size()));
  } else {
    std::memcpy(&buf_[n_], s.data(), s.size());
    n_ += s.size();
  }
  return *this;
}

void TextOutput::flush() {
  out_.stream().write(buf_.data(), std::streamsize(n_));
  n_ = 0;
}

void TextOutput::commit() {
  flush();
  out_.commit();
}

} // namespace imgmesh
