// Reading VTK XML files (.vtp, .vtu) as vtkXMLWriter writes them: ASCII,
// inline base64 or appended (raw or base64) arrays, zlib-compressed or not,
// either header size and byte order (util/binary_io.hpp decodes them).
#include "mesh/mesh_read_detail.hpp"

#include "util/atomic_file.hpp"
#include "util/binary_io.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <sstream>
#include <type_traits>
#include <vector>

namespace imgmesh {
namespace {

using mesh_detail::add_element;
using mesh_detail::Tokens;

// One DataArray's values and where they are, for errors.
template <class T> struct VtuArray {
  std::vector<T> values;
  std::string label;                     // its Name, or its section's
  std::size_t text = std::string::npos;  // ASCII: where its values start in the file
  std::string what;                      // binary: "appended DataArray NAME" or "binary DataArray NAME"
};

// A VTK XML file's DataArrays (.vtu, .vtp), ASCII or binary, inline or
// appended, every layout vtkXMLWriter writes (util/binary_io.hpp's
// VtkBinaryLayout) but LZ4 and LZMA compression, which are refused naming
// the compressor. The real arrays read are coordinates (Points), in the
// range of util/coordinates.hpp whichever the encoding.
class VtuArrays {
public:
  VtuArrays(std::string text, std::string path) : x_(std::move(text)), path_(std::move(path)) {
    const std::size_t file = x_.find("<VTKFile");
    const std::string head = file == std::string::npos ? "" : x_.substr(file, x_.find('>', file) - file);
    layout_.uint64_header = attribute(head, "header_type") == "UInt64";
    compressor_ = attribute(head, "compressor");
    layout_.zlib = compressor_ == "vtkZLibDataCompressor";
    const std::string order = attribute(head, "byte_order");
    if (order != "" && order != "LittleEndian" && order != "BigEndian")
      throw Error("VTK XML byte_order \"" + order.substr(0, 40) + "\" (LittleEndian or BigEndian expected)", path_);
    layout_.order = order == "BigEndian" ? ByteOrder::Big : ByteOrder::Little;
    // The appended data start after its tag, blanks and a '_'; base64 unless
    // encoding="raw", as vtkXMLDataParser reads them.
    const std::size_t a = x_.find("<AppendedData");
    if (a == std::string::npos || x_.find('>', a) == std::string::npos) return;
    appended_base64_ = attribute(x_.substr(a, x_.find('>', a) - a), "encoding") != "raw";
    appended_ = data_start(x_.find('>', a) + 1);
    if (appended_ < x_.size() && x_[appended_] == '_') ++appended_;
  }
  // The values of the DataArray named `name` (or the first in `section`),
  // as T (double or long long); empty when absent and not required.
  template <class T> VtuArray<T> values(const std::string& section, const std::string& name, bool required = true) const {
    std::size_t close = 0;
    const std::string tag = find(section, name, required, close);
    VtuArray<T> a{{}, name.empty() ? section : name};
    if (tag.empty()) return a;
    const std::string format = attribute(tag, "format");
    if (format == "appended" || format == "binary") {
      decode(tag, format == "appended", close + 1, a);
      return a;
    }
    if (format != "ascii")
      throw Error("DataArray " + a.label + ": format \"" + format.substr(0, 40) +
                      "\" (ascii, binary or appended expected)", path_);
    a.text = close + 1;
    std::istringstream text(ascii(a.text));
    Tokens t{text, path_, line_at(a.text)};
    while (t.more()) {
      if constexpr (std::is_same_v<T, double>) a.values.push_back(t.coordinate());
      else a.values.push_back(t.integer());
    }
    return a;
  }
  // Throws Error for value i of `a` (i = its size: where it ends): in ASCII
  // naming the line it is on, in binary data the array and the index.
  template <class T> [[noreturn]] void fail(const VtuArray<T>& a, std::size_t i, const std::string& what) const {
    if (a.text == std::string::npos)
      throw Error(a.what + ", value " + std::to_string(i) + ": " + what, path_);
    std::istringstream text(ascii(a.text));
    Tokens t{text, path_, line_at(a.text)};
    std::string s;
    for (std::size_t k = 0; k <= i && t.read(s); ++k) {
    }
    t.fail(what);
  }

private:
  // The tag (up to its '>', at `close`) of the array.
  std::string find(const std::string& section, const std::string& name, bool required, std::size_t& close) const {
    std::size_t at = 0;
    if (!section.empty()) {
      at = x_.find("<" + section);
      if (at == std::string::npos) {
        if (required) throw Error("no <" + section + "> in the VTK XML file", path_);
        return {};
      }
    }
    for (;;) {
      at = x_.find("<DataArray", at);
      if (at == std::string::npos) {
        if (required) throw Error("no DataArray " + name + " in the VTK XML file", path_);
        return {};
      }
      close = x_.find('>', at);
      if (close == std::string::npos) throw Error("a DataArray tag is not closed", path_);
      const std::string tag = x_.substr(at, close - at);
      if (name.empty() || attribute(tag, "Name") == name) return tag;
      at = close;
    }
  }
  // An ASCII array's text from `begin` up to the next tag (the end of the
  // array, or the InformationKey elements VTK writes after the values).
  std::string ascii(std::size_t begin) const {
    const std::size_t end = x_.find('<', begin);
    return x_.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  }
  int line_at(std::size_t begin) const {
    return 1 + int(std::count(x_.begin(), x_.begin() + std::ptrdiff_t(begin), '\n'));
  }
  // Past the blanks from `at`.
  std::size_t data_start(std::size_t at) const {
    while (at < x_.size() && std::isspace(static_cast<unsigned char>(x_[at]))) ++at;
    return at;
  }
  // The value of attribute `key` of `tag` (after a blank, quoted with " or
  // '), empty when absent.
  static std::string attribute(const std::string& tag, const std::string& key) {
    for (std::size_t at = tag.find(key + "="); at != std::string::npos; at = tag.find(key + "=", at + 1)) {
      const std::size_t q = at + key.size() + 1;
      if (at == 0 || !std::isspace(static_cast<unsigned char>(tag[at - 1])) || q >= tag.size() ||
          (tag[q] != '"' && tag[q] != '\''))
        continue;
      const std::size_t end = tag.find(tag[q], q + 1);
      return end == std::string::npos ? std::string() : tag.substr(q + 1, end - q - 1);
    }
    return {};
  }
  // A binary array: inline base64 from `inline_at`, or appended.
  template <class T> void decode(const std::string& tag, bool appended, std::size_t inline_at, VtuArray<T>& a) const {
    a.what = (appended ? "appended DataArray " : "binary DataArray ") + a.label;
    if (!compressor_.empty() && !layout_.zlib)
      throw Error(a.what + ": compressed by " + compressor_.substr(0, 40) + " (only zlib or no compression is read)",
                  path_);
    VtkBinaryLayout layout = layout_;
    std::size_t at = data_start(inline_at);
    if (appended) {
      if (appended_ == std::string::npos) throw Error("an appended DataArray without <AppendedData>", path_);
      std::size_t offset = 0;
      try {
        offset = std::stoull(attribute(tag, "offset"));
      } catch (const std::exception&) {
        throw Error("an appended DataArray without a valid offset", path_);
      }
      if (offset > x_.size() - appended_) throw Error("an appended DataArray's offset beyond the file", path_);
      at = appended_ + offset;
      layout.base64 = appended_base64_;
    } else {
      layout.base64 = true;
    }
    const std::string raw = vtk_array_decode(x_, at, layout, a.what, path_);
    const std::string type = attribute(tag, "type");
    if (type == "Float64") return convert<T, double>(raw, a);
    if (type == "Float32") return convert<T, float>(raw, a);
    if (type == "Int64") return convert<T, std::int64_t>(raw, a);
    if (type == "UInt64") return convert<T, std::uint64_t>(raw, a);
    if (type == "Int32") return convert<T, std::int32_t>(raw, a);
    if (type == "UInt32") return convert<T, std::uint32_t>(raw, a);
    if (type == "UInt8") return convert<T, std::uint8_t>(raw, a);
    if (type == "Int16") return convert<T, std::int16_t>(raw, a);
    if (type == "UInt16") return convert<T, std::uint16_t>(raw, a);
    if (type == "Int8") return convert<T, std::int8_t>(raw, a);
    throw Error(a.what + ": unsupported type '" + type.substr(0, 40) + "'", path_);
  }
  template <class T, class S> void convert(const std::string& raw, VtuArray<T>& a) const {
    if (raw.size() % sizeof(S)) throw Error(a.what + ": its size is not a multiple of its type's", path_);
    a.values.resize(raw.size() / sizeof(S));
    for (std::size_t i = 0; i < a.values.size(); ++i) {
      const S v = get_bytes<S>(raw.data() + i * sizeof(S), layout_.order);
      if constexpr (std::is_floating_point_v<S>) {
        if constexpr (!std::is_floating_point_v<T>) throw Error("real numbers where integers are expected", path_);
        if (!valid_coordinate(v)) fail(a, i, coordinate_error(double(v)));
      }
      if constexpr (std::is_same_v<S, std::uint64_t>)
        if (v > std::uint64_t(1) << 62) fail(a, i, "an integer out of range");
      a.values[i] = T(v);
    }
  }
  std::string x_, path_;
  std::size_t appended_ = std::string::npos;  // where the appended data start
  bool appended_base64_ = true;
  VtkBinaryLayout layout_;
  std::string compressor_;
};

} // namespace

namespace mesh_detail {

TetMesh read_vtu(const std::string& path) {
  const VtuArrays f(read_all(path), path);
  TetMesh m;
  const VtuArray<double> xyz = f.values<double>("Points", "");
  const VtuArray<long long> con = f.values<long long>("", "connectivity"), off = f.values<long long>("", "offsets"),
                            types = f.values<long long>("", "types"), reg_region = f.values<long long>("CellData", "region", false);
  // seg2tet's is "label".
  const VtuArray<long long> reg = reg_region.values.empty() ? f.values<long long>("CellData", "label", false) : reg_region;
  const auto& p = xyz.values;
  if (p.size() % 3) throw Error("the point count is not a multiple of 3", path);
  for (std::size_t i = 0; i < p.size(); i += 3) m.points.push_back({p[i], p[i + 1], p[i + 2]});
  const std::size_t cells = types.values.size();
  if (off.values.size() < cells) f.fail(off, off.values.size(), "unexpected end of file");
  if (!reg.values.empty() && reg.values.size() < cells) f.fail(reg, reg.values.size(), "unexpected end of file");
  long long last = 0;
  std::vector<int> v;
  for (std::size_t c = 0; c < cells; ++c) {
    const long long end = off.values[c];
    if (end < last) f.fail(off, c, "decreasing offsets");
    if (end > (long long)con.values.size()) f.fail(con, con.values.size(), "unexpected end of file");
    v.clear();
    for (long long k = last; k < end; ++k) {
      const long long id = con.values[std::size_t(k)];
      if (id < 0 || id >= (long long)m.points.size()) f.fail(con, std::size_t(k), "cell refers to unknown point " + std::to_string(id));
      v.push_back(int(id));
    }
    last = end;
    const int region = reg.values.empty() ? 1 : int(reg.values[c]);
    const long long type = types.values[c];
    if (type == 10 && v.size() == 4) add_element(m, 4, v, region);
    else if (type == 5 && v.size() == 3) add_element(m, 2, v, region);
  }
  return m;
}


SurfaceMesh read_vtp(const std::string& path) {
  const VtuArrays f(read_all(path), path);
  const VtuArray<double> xyz = f.values<double>("Points", "");
  const VtuArray<long long> con = f.values<long long>("Polys", "connectivity"),
                            off = f.values<long long>("Polys", "offsets"),
                            label = f.values<long long>("CellData", "label", false),
                            labels = f.values<long long>("CellData", "labels", false);
  SurfaceMesh m;
  const auto& p = xyz.values;
  if (p.size() % 3) throw Error("the point count is not a multiple of 3", path);
  for (std::size_t i = 0; i < p.size(); i += 3) m.points.push_back({p[i], p[i + 1], p[i + 2]});
  const std::size_t cells = off.values.size();
  long long last = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    const long long end = off.values[c];
    if (end != last + 3) f.fail(off, c, "a polygon that is not a triangle (or decreasing offsets)");
    if (end > (long long)con.values.size()) f.fail(con, con.values.size(), "unexpected end of file");
    std::array<int, 3> t{};
    for (long long k = last; k < end; ++k) {
      const long long id = con.values[std::size_t(k)];
      if (id < 0 || id >= (long long)m.points.size()) f.fail(con, std::size_t(k), "cell refers to unknown point " + std::to_string(id));
      t[std::size_t(k - last)] = int(id);
    }
    m.triangles.push_back(t);
    last = end;
  }
  if (!label.values.empty() && label.values.size() != cells) f.fail(label, label.values.size(), "not one label a triangle");
  if (!labels.values.empty() && labels.values.size() != 2 * cells)
    f.fail(labels, labels.values.size(), "not two labels a triangle");
  for (long long l : label.values) m.labels.push_back(int(l));
  for (std::size_t c = 0; c < labels.values.size(); c += 2)
    m.interfaces.push_back({int(labels.values[c]), int(labels.values[c + 1])});
  check_extent(m.points, path);
  return m;
}

} // namespace mesh_detail
} // namespace imgmesh
