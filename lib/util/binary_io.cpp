#include "util/binary_io.hpp"

#include "util/error.hpp"

#include <zlib.h>

#include <algorithm>

namespace imgmesh {
namespace {

constexpr std::size_t kBlock = 32768;  // vtkZLibDataCompressor's block size

std::uint64_t header_word(const std::string& data, std::size_t& at, bool uint64_header, const std::string& path) {
  const std::size_t n = uint64_header ? 8 : 4;
  if (at > data.size() || data.size() - at < n) throw Error("appended data: an array's header runs past the end", path);
  const std::uint64_t v = uint64_header ? get_bytes<std::uint64_t>(data.data() + at) : get_bytes<std::uint32_t>(data.data() + at);
  at += n;
  return v;
}

} // namespace

std::string vtk_zlib_encode(const std::string& raw) {
  const std::size_t blocks = (raw.size() + kBlock - 1) / kBlock;
  std::string body, header;
  std::vector<unsigned char> buf(compressBound(uLong(kBlock)));
  append_bytes(header, std::uint64_t(blocks));
  append_bytes(header, std::uint64_t(kBlock));
  append_bytes(header, std::uint64_t(raw.size() % kBlock));
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t size = std::min(kBlock, raw.size() - b * kBlock);
    uLongf out = uLongf(buf.size());
    if (compress2(buf.data(), &out, reinterpret_cast<const Bytef*>(raw.data() + b * kBlock), uLong(size),
                  Z_DEFAULT_COMPRESSION) != Z_OK)
      throw Error("zlib cannot compress");
    append_bytes(header, std::uint64_t(out));
    body.append(reinterpret_cast<const char*>(buf.data()), out);
  }
  return header + body;
}

std::string vtk_zlib_decode(const std::string& data, std::size_t offset, bool uint64_header, const std::string& path) {
  std::size_t at = offset;
  const std::uint64_t blocks = header_word(data, at, uint64_header, path);
  const std::uint64_t block = header_word(data, at, uint64_header, path);
  const std::uint64_t last = header_word(data, at, uint64_header, path);
  if (blocks > data.size() || (blocks > 0 && (block == 0 || block > (std::uint64_t(1) << 30) || last > block)))
    throw Error("appended data: a malformed compressed array header", path);
  std::vector<std::uint64_t> sizes(blocks);
  for (auto& s : sizes) s = header_word(data, at, uint64_header, path);
  std::string raw;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t want = b + 1 == blocks && last ? last : block;
    if (sizes[b] > data.size() - at) throw Error("appended data: a compressed block runs past the end", path);
    std::string out(want, '\0');
    uLongf got = uLongf(want);
    if (uncompress(reinterpret_cast<Bytef*>(&out[0]), &got, reinterpret_cast<const Bytef*>(data.data() + at),
                   uLong(sizes[b])) != Z_OK ||
        got != want)
      throw Error("appended data: a compressed block does not decompress to its size", path);
    raw += out;
    at += sizes[b];
  }
  return raw;
}

std::string vtk_raw_decode(const std::string& data, std::size_t offset, bool uint64_header, const std::string& path) {
  std::size_t at = offset;
  const std::uint64_t n = header_word(data, at, uint64_header, path);
  if (n > data.size() - at) throw Error("appended data: an array runs past the end", path);
  return data.substr(at, n);
}

} // namespace imgmesh
