// Private to lib/mesh: the two layouts that the surface and the
// tetrahedral writers share in ASCII and binary, so that one code writes
// both encodings. VtkXmlArrays: VTK XML DataArrays inline in ASCII (the
// bytes the ASCII files have always had) or as vtkXMLWriter writes them by
// default: appended raw data, each array zlib-compressed behind a UInt64
// header. MshWriter: Gmsh's values in ASCII (one line each record, spaces
// between) or in its binary form (little-endian int, size_t, double; the
// section keywords and names stay text).
#pragma once
#include "util/binary_io.hpp"

#include <cstdint>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

namespace imgmesh::mesh_detail {

// A Gmsh physical name: one line (control characters as spaces), no double
// quote, at most 127 bytes (the format's limit), not cut inside a UTF-8
// character. Surfaces and tetrahedra name their groups alike.
inline std::string msh_name(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    if (c == '"') c = '\'';
  }
  if (s.size() > 127) {
    std::size_t end = 127;
    while (end > 0 && (static_cast<unsigned char>(s[end]) & 0xc0) == 0x80) --end;
    s.resize(end);
  }
  return s;
}

class VtkXmlArrays {
public:
  // tag_indent before each <DataArray>, value_indent before each ASCII line.
  VtkXmlArrays(std::ostream& out, bool binary, std::string tag_indent, std::string value_indent)
      : out_(out), binary_(binary), tag_indent_(std::move(tag_indent)), value_indent_(std::move(value_indent)) {}
  // The <VTKFile> attributes after its type: version, byte order and, in
  // binary, the header type and compressor (VTK 1.0 files).
  std::string file_attributes() const {
    return binary_ ? "version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\""
                   : "version=\"0.1\" byte_order=\"LittleEndian\"";
  }
  // A DataArray of VTK type `type` (the C++ type T's) of `count` values,
  // value(i) the i-th; in ASCII in `lines` lines, line l of line_size(l)
  // values. In binary each value goes to the compressor as it comes: no
  // copy of the array is made, only its compressed blocks are held.
  template <class T, class Value, class LineSize>
  void array(const char* type, const char* name, int components, std::size_t count, const Value& value,
             std::size_t lines, const LineSize& line_size) {
    out_ << tag_indent_ << "<DataArray type=\"" << type << "\"";
    if (name) out_ << " Name=\"" << name << "\"";
    if (components > 1) out_ << " NumberOfComponents=\"" << components << "\"";
    if (binary_) {
      out_ << " format=\"appended\" offset=\"" << appended_size_ << "\"/>\n";
      VtkZlibEncoder encoder;
      for (std::size_t i = 0; i < count; ++i) encoder.add_value(T(value(i)));
      for (std::string& piece : encoder.finish()) {
        appended_size_ += piece.size();
        appended_.push_back(std::move(piece));
      }
      return;
    }
    out_ << " format=\"ascii\">\n";
    std::size_t i = 0;
    for (std::size_t l = 0; l < lines; ++l) {
      out_ << value_indent_;
      for (std::size_t k = 0, n = line_size(l); k < n; ++k) out_ << (k ? " " : "") << +T(value(i++));
      out_ << '\n';
    }
    out_ << tag_indent_ << "</DataArray>\n";
  }
  // `components` values a line.
  template <class T, class Value>
  void array(const char* type, const char* name, int components, std::size_t count, const Value& value) {
    const std::size_t per_line = std::size_t(components);
    array<T>(type, name, components, count, value, count / per_line, [per_line](std::size_t) { return per_line; });
  }
  // The values of a vector, in ASCII in lines of line_sizes values.
  template <class T>
  void array(const char* type, const char* name, int components, const std::vector<T>& values,
             const std::vector<std::size_t>& line_sizes) {
    array<T>(type, name, components, values.size(), [&](std::size_t i) { return values[i]; }, line_sizes.size(),
             [&](std::size_t l) { return line_sizes[l]; });
  }
  template <class T> void array(const char* type, const char* name, int components, const std::vector<T>& values) {
    array<T>(type, name, components, values.size(), [&](std::size_t i) { return values[i]; });
  }
  // The <AppendedData> element in binary (nothing in ASCII), before </VTKFile>.
  void appended_data() {
    if (!binary_) return;
    out_ << "  <AppendedData encoding=\"raw\">\n   _";
    for (const std::string& piece : appended_) out_.write(piece.data(), std::streamsize(piece.size()));
    out_ << "\n  </AppendedData>\n";
  }

private:
  std::ostream& out_;
  bool binary_;
  std::string tag_indent_, value_indent_;
  std::vector<std::string> appended_;  // the arrays' encodings, piece by piece
  std::size_t appended_size_ = 0;
};

class MshWriter {
public:
  MshWriter(std::ostream& out, bool binary) : out_(out), binary_(binary) {}
  bool binary() const { return binary_; }
  // $MeshFormat: version, file type, size_t's size; in binary the int 1
  // that tells readers the byte order.
  void format(const std::string& version) {
    out_ << "$MeshFormat\n" << version << (binary_ ? " 1 8\n" : " 0 8\n");
    if (binary_) {
      put_bytes(out_, std::int32_t(1));
      out_ << '\n';
    }
    out_ << "$EndMeshFormat\n";
  }
  MshWriter& i(long long v) { return value(std::int32_t(v), v); }          // an int
  MshWriter& z(std::size_t v) { return value(std::uint64_t(v), v); }      // a size_t
  MshWriter& d(double v) { return value(v, v); }                          // a double
  MshWriter& d(double v, const std::string& ascii) { return value(v, ascii); }  // printed as `ascii` in ASCII
  void eol() {  // the end of an ASCII line
    if (!binary_) out_ << '\n';
    first_ = true;
  }
  // The end of a section whose body was values: binary data ends with a newline.
  void end(const char* section) { out_ << (binary_ ? "\n$End" : "$End") << section << '\n'; }
  // Gmsh 2.2's elements: in binary grouped in blocks of one type and tag
  // count, each behind a header (type, count, number of tags).
  void block22(int type, std::size_t count, int tags) {
    if (binary_ && count > 0) {
      put_bytes(out_, std::int32_t(type));
      put_bytes(out_, std::int32_t(count));
      put_bytes(out_, std::int32_t(tags));
    }
  }
  template <class Nodes> void element22(std::size_t id, int type, const std::vector<int>& tags, const Nodes& nodes) {
    i((long long)id);
    if (!binary_) i(type).i((long long)tags.size());
    for (int t : tags) i(t);
    for (auto v : nodes) i(v);
    eol();
  }

private:
  template <class B, class A> MshWriter& value(B bytes, const A& ascii) {
    if (binary_) {
      put_bytes(out_, bytes);
    } else {
      if (!first_) out_ << ' ';
      out_ << ascii;
    }
    first_ = false;
    return *this;
  }
  std::ostream& out_;
  bool binary_;
  bool first_ = true;
};

} // namespace imgmesh::mesh_detail
