#include "util/binary_io.hpp"

#include "util/error.hpp"

#include <zlib.h>

#include <algorithm>

namespace imgmesh {
namespace {

constexpr std::size_t kBlock = VtkZlibEncoder::kBlock;

// base64's value of c, -1 for '=' (padding), -2 for any other byte.
int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return c == '=' ? -1 : -2;
}

// The runs of one array in the file: its bytes as they are, or runs of
// base64 text, each encoding whole bytes and padded with '=' at its end
// (vtkBase64OutputStream::EndWriting).
class ArrayRuns {
public:
  ArrayRuns(std::string_view data, const VtkBinaryLayout& layout, const std::string& what, const std::string& path)
      : data_(data), base64_(layout.base64), what_(what), path_(path) {}
  [[noreturn]] void fail(const std::string& why) const { throw Error(what_ + ": " + why, path_); }
  // The first n bytes of the run that starts at data[at].
  std::string bytes(std::size_t at, std::uint64_t n, const char* part) const {
    const std::uint64_t chars = size(n);
    if (at > data_.size() || chars > data_.size() - at) fail(std::string(part) + " runs past the end of the file");
    if (!base64_) return std::string(data_.substr(at, std::size_t(n)));
    std::string out;
    out.reserve(std::size_t(chars / 4 * 3));
    for (std::size_t q = at; q < at + chars; q += 4) {
      int v[4];
      for (int k = 0; k < 4; ++k) v[k] = base64_value(data_[q + std::size_t(k)]);
      // "xx==" holds one byte, "xxx=" two: padding only at the run's end.
      const int pad = v[3] != -1 ? 0 : v[2] != -1 ? 1 : 2;
      if (v[0] < 0 || v[1] < 0 || (pad < 2 && v[2] < 0) || (pad == 0 && v[3] < 0) || (pad && out.size() + 3 - pad < n))
        fail(std::string(part) + " is not base64 text");
      const std::uint32_t w = std::uint32_t(v[0]) << 18 | std::uint32_t(v[1]) << 12 |
                              std::uint32_t(std::max(v[2], 0)) << 6 | std::uint32_t(std::max(v[3], 0));
      for (int k = 0; k < 3 - pad; ++k) out.push_back(char(w >> (16 - 8 * k) & 0xFF));
    }
    out.resize(std::size_t(n));
    return out;
  }
  // The characters a run of n bytes takes.
  std::uint64_t size(std::uint64_t n) const { return base64_ ? (n + 2) / 3 * 4 : n; }

private:
  std::string_view data_;
  bool base64_;
  const std::string& what_;
  const std::string& path_;
};

// Header word i of `header`.
std::uint64_t header_word(const std::string& header, std::size_t i, const VtkBinaryLayout& layout) {
  return layout.uint64_header ? get_bytes<std::uint64_t>(header.data() + 8 * i, layout.order)
                              : get_bytes<std::uint32_t>(header.data() + 4 * i, layout.order);
}

// An uncompressed array: its byte count, then its bytes, one run.
std::string uncompressed_array(const ArrayRuns& runs, std::size_t offset, const VtkBinaryLayout& layout,
                               std::size_t file) {
  const std::size_t word = layout.uint64_header ? 8 : 4;
  const std::uint64_t n = header_word(runs.bytes(offset, word, "its header"), 0, layout);
  if (n > file) runs.fail("its byte count runs past the end of the file");
  return runs.bytes(offset, word + n, "its data").substr(word);
}

// A zlib-compressed array: its header (blocks, block size, the last
// block's, each block's compressed size), then its blocks, two runs.
std::string zlib_array(const ArrayRuns& runs, std::size_t offset, const VtkBinaryLayout& layout, std::size_t file) {
  const std::size_t word = layout.uint64_header ? 8 : 4;
  const std::string first = runs.bytes(offset, 3 * word, "its compression header");
  const std::uint64_t blocks = header_word(first, 0, layout), block = header_word(first, 1, layout),
                      last = header_word(first, 2, layout);
  if (blocks > file / word || (blocks > 0 && (block == 0 || block > (std::uint64_t(1) << 30) || last > block)))
    runs.fail("a malformed compression header (" + std::to_string(blocks) + " blocks of " + std::to_string(block) +
              " bytes, the last " + std::to_string(last) + ")");
  const std::string header = runs.bytes(offset, (3 + blocks) * word, "its compression header");
  std::vector<std::uint64_t> sizes(blocks);
  std::uint64_t total = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    sizes[b] = header_word(header, 3 + b, layout);
    if (sizes[b] > file) runs.fail("a compressed block runs past the end of the file");
    total += sizes[b];
  }
  const std::size_t body_at = offset + std::size_t(runs.size((3 + blocks) * word));
  const std::string body = runs.bytes(body_at, total, "its compressed blocks");
  std::string raw;
  std::size_t at = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t want = b + 1 == blocks && last ? last : block;
    std::string out(std::size_t(want), '\0');
    uLongf got = uLongf(want);
    if (uncompress(reinterpret_cast<Bytef*>(&out[0]), &got, reinterpret_cast<const Bytef*>(body.data() + at),
                   uLong(sizes[b])) != Z_OK ||
        got != want)
      runs.fail("compressed block " + std::to_string(b) + " does not decompress to its size");
    raw += out;
    at += std::size_t(sizes[b]);
  }
  return raw;
}

} // namespace

void VtkZlibEncoder::compress(const char* bytes, std::size_t n) {
  buf_.resize(compressBound(uLong(kBlock)));
  uLongf size = uLongf(buf_.size());
  if (compress2(buf_.data(), &size, reinterpret_cast<const Bytef*>(bytes), uLong(n), Z_DEFAULT_COMPRESSION) != Z_OK)
    throw Error("zlib cannot compress");
  blocks_.emplace_back(reinterpret_cast<const char*>(buf_.data()), size);  // its own size, not the bound's
  raw_size_ += n;
}

void VtkZlibEncoder::compress_full_blocks() {
  std::size_t at = 0;
  for (; block_.size() - at >= kBlock; at += kBlock) compress(block_.data() + at, kBlock);
  block_.erase(0, at);
}

void VtkZlibEncoder::add(const char* bytes, std::size_t n) {
  while (n > 0) {
    const std::size_t take = std::min(n, kBlock - block_.size());
    block_.append(bytes, take);
    bytes += take, n -= take;
    if (block_.size() == kBlock) compress_full_blocks();
  }
}

std::vector<std::string> VtkZlibEncoder::finish() {
  if (!block_.empty()) compress(block_.data(), block_.size());
  std::string header;
  append_bytes(header, std::uint64_t(blocks_.size()));
  append_bytes(header, std::uint64_t(kBlock));
  append_bytes(header, std::uint64_t(raw_size_ % kBlock));
  for (const std::string& b : blocks_) append_bytes(header, std::uint64_t(b.size()));
  std::vector<std::string> out{std::move(header)};
  for (std::string& b : blocks_) out.push_back(std::move(b));
  *this = VtkZlibEncoder();
  return out;
}

std::string vtk_zlib_encode(const std::string& raw) {
  VtkZlibEncoder e;
  e.add(raw.data(), raw.size());
  std::string out;
  for (const std::string& piece : e.finish()) out += piece;
  return out;
}

std::string vtk_array_decode(std::string_view data, std::size_t offset, const VtkBinaryLayout& layout,
                             const std::string& what, const std::string& path) {
  const ArrayRuns runs(data, layout, what, path);
  return layout.zlib ? zlib_array(runs, offset, layout, data.size()) : uncompressed_array(runs, offset, layout, data.size());
}

} // namespace imgmesh
