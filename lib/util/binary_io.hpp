// Numbers as bytes in a fixed byte order whatever the machine's (PLY, STL,
// Gmsh and VTK XML binary are little-endian, legacy VTK big-endian), legacy
// VTK's value lines in either encoding, and VTK XML's binary arrays: the
// zlib framing we write (appended raw data), and every layout
// vtkXMLWriter writes read back (raw or base64, zlib or none, either byte
// order and header size).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace imgmesh {

enum class ByteOrder { Little, Big };

inline bool machine_order_is(ByteOrder order) {
  const std::uint32_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return (first == 1) == (order == ByteOrder::Little);
}

// The bytes of v in `order` appended to out / written to out.
template <class T> void append_bytes(std::string& out, T v, ByteOrder order = ByteOrder::Little) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (!machine_order_is(order))
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(b, sizeof(T));
}
template <class T> void put_bytes(std::ostream& out, T v, ByteOrder order = ByteOrder::Little) {
  std::string b;
  append_bytes(b, v, order);
  out.write(b.data(), std::streamsize(b.size()));
}
// The T whose bytes in `order` start at p.
template <class T> T get_bytes(const char* p, ByteOrder order = ByteOrder::Little) {
  char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (!machine_order_is(order))
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// Legacy VTK's values of one array on `out` (an std::ostream, or any
// stream with << for numbers, chars and string_views): ASCII, the lines of
// `line_sizes` values, separated by a space; binary, big-endian T's then a
// newline, as vtkDataWriter lays them out.
template <class Out, class T>
void vtk_legacy_values(Out& out, const std::vector<T>& v, bool binary, const std::vector<std::size_t>& line_sizes) {
  if (binary) {
    std::string b;
    b.reserve(v.size() * sizeof(T) + 1);
    for (T x : v) append_bytes(b, x, ByteOrder::Big);
    b += '\n';
    out << std::string_view(b);
    return;
  }
  std::size_t i = 0;
  for (std::size_t n : line_sizes) {
    for (std::size_t k = 0; k < n; ++k) {
      if (k) out << ' ';
      out << v[i++];
    }
    out << '\n';
  }
}
// The same with `per_line` values on every line.
template <class Out, class T> void vtk_legacy_values(Out& out, const std::vector<T>& v, bool binary, std::size_t per_line) {
  vtk_legacy_values(out, v, binary, std::vector<std::size_t>(per_line ? v.size() / per_line : 0, per_line));
}

// One array as vtkXMLWriter writes it compressed: a UInt64 header (number
// of blocks, block size 32768, the last block's size when partial else 0,
// each block's compressed size), then the blocks, each zlib-compressed.
std::string vtk_zlib_encode(const std::string& raw);
// The same bytes made as the raw bytes come, a block at a time: only the
// compressed blocks are held, never the raw array (a writer streams an
// array from the mesh's own vectors instead of copying it twice).
class VtkZlibEncoder {
public:
  static constexpr std::size_t kBlock = 32768;  // vtkZLibDataCompressor's block size
  void add(const char* bytes, std::size_t n);
  template <class T> void add_value(T v) {  // its bytes, little-endian
    append_bytes(block_, v);
    if (block_.size() >= kBlock) compress_full_blocks();
  }
  // The encoding of every byte given: the header, then the compressed
  // blocks, in order (pieces to write one after the other); the encoder is
  // then empty.
  std::vector<std::string> finish();

private:
  void compress_full_blocks();
  void compress(const char* bytes, std::size_t n);
  std::string block_;                // raw bytes not compressed yet, fewer than kBlock after each call
  std::vector<std::string> blocks_;  // compressed
  std::uint64_t raw_size_ = 0;       // of the blocks compressed
  std::vector<unsigned char> buf_;   // a block's compression
};

// How a VTK XML file holds its binary arrays (vtkXMLWriter's choices):
// base64 text (inline format="binary" always, appended data unless
// encoding="raw") or the bytes themselves, zlib-compressed or not, header
// words UInt32 or UInt64, header and values in `order`.
struct VtkBinaryLayout {
  bool base64 = false;
  bool zlib = false;
  bool uint64_header = false;
  ByteOrder order = ByteOrder::Little;
};
// The bytes of the array that starts at data[offset], its values still in
// layout.order. Uncompressed: one header word (the byte count), then the
// bytes; compressed: the header words (blocks, block size, the last block's
// size when partial else 0, each block's compressed size), then the blocks.
// In base64 (vtkXMLWriter::WriteBinaryData) an uncompressed array is one
// run of text, a compressed one two: its header, then its blocks together.
// Throws Error("`what`: ...", path) on a malformed, cut or non-base64 array.
std::string vtk_array_decode(std::string_view data, std::size_t offset, const VtkBinaryLayout& layout,
                             const std::string& what, const std::string& path);

} // namespace imgmesh
