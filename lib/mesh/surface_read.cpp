// Reading the surface formats with per-face data that OpenMesh does not
// read: legacy VTK POLYDATA, and a .msh's triangles with their physical
// groups as labels or label pairs (mesh_read_detail.hpp).
#include "mesh/mesh_read_detail.hpp"

#include "util/atomic_file.hpp"
#include "util/binary_io.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace imgmesh {
namespace {

// A legacy VTK file: keyword lines, then values, ASCII tokens or BINARY
// big-endian numbers right after the line that announces them.
class LegacyVtk {
public:
  explicit LegacyVtk(const std::string& path) : x_(read_all(path)), path_(path) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("line " + std::to_string(line_) + ": " + what, path_);
  }
  bool at_end() const { return at_ >= x_.size(); }
  // The next line (a '\r' before its '\n' dropped), its words.
  std::string line() {
    if (at_ >= x_.size()) {
      at_ = x_.size();
      return {};
    }
    const std::size_t end = std::min(x_.find('\n', at_), x_.size());
    std::string l = x_.substr(at_, end - at_);
    if (!l.empty() && l.back() == '\r') l.pop_back();
    at_ = end + 1;
    ++line_;
    return l;
  }
  std::vector<std::string> words() {
    std::istringstream in(line());
    std::vector<std::string> w;
    for (std::string s; in >> s;) w.push_back(s);
    return w;
  }
  // The words of the next line that is not blank (none at the end).
  std::vector<std::string> next() {
    std::vector<std::string> w;
    while (w.empty() && !at_end()) w = words();
    return w;
  }
  // The same, left unread.
  std::vector<std::string> peek() {
    const std::size_t at = at_;
    const int line = line_;
    std::vector<std::string> w = next();
    at_ = at;
    line_ = line;
    return w;
  }
  void set_binary(bool binary) { binary_ = binary; }
  // n values of VTK type `type`, as doubles (exact for the integers the
  // format holds in a double's 53 bits).
  std::vector<double> values(const std::string& name, std::size_t n) {
    const std::string type = canonical_type(name);
    if (n > x_.size()) fail("a count beyond the size of the file");
    std::vector<double> v(n);
    if (!binary_) {
      for (double& d : v) d = token(type);
      return v;
    }
    const std::size_t size = type_size(type);
    if (at_ + n * size > x_.size()) fail("unexpected end of file in binary data");
    for (std::size_t i = 0; i < n; ++i) v[i] = binary_value(type, x_.data() + at_ + i * size);
    at_ += n * size;
    return v;
  }
  // n strings of a FIELD array: one a line with %XX escapes, or in binary
  // each behind its length (one byte 0xC0 | n, or two 0x8000 | n).
  std::vector<std::string> strings(std::size_t n) {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n; ++i) {
      if (!binary_) {
        out.push_back(unescape(line()));
        continue;
      }
      if (at_ >= x_.size()) fail("unexpected end of file in a string array");
      std::size_t len = static_cast<unsigned char>(x_[at_]);
      if ((len & 0xC0) == 0xC0) {
        len &= 0x3F;
        at_ += 1;
      } else {
        if (at_ + 2 > x_.size()) fail("unexpected end of file in a string array");
        len = get_bytes<std::uint16_t>(x_.data() + at_, ByteOrder::Big) & 0x3FFF;
        at_ += 2;
      }
      if (at_ + len > x_.size()) fail("unexpected end of file in a string array");
      out.push_back(x_.substr(at_, len));
      at_ += len;
    }
    return out;
  }

private:
  double token(const std::string& type) {
    while (at_ < x_.size() && std::isspace(static_cast<unsigned char>(x_[at_]))) line_ += x_[at_++] == '\n';
    const std::size_t begin = at_;
    while (at_ < x_.size() && !std::isspace(static_cast<unsigned char>(x_[at_]))) ++at_;
    if (begin == at_) fail("unexpected end of file");
    const std::string s = x_.substr(begin, at_ - begin);
    double v;
    if (type == "float" || type == "double" ? !parse_coordinate(s, v) : !parse_real(s, v))
      fail(type == "float" || type == "double" ? coordinate_error(s) : "expected a number, found '" + s.substr(0, 40) + "'");
    return v;
  }
  // The type names vtkDataReader reads (case-insensitive), as one of
  // int8 ... uint64 (C names: char, short, int, long 8 bytes; vtkIdType is
  // written as 4-byte int), float, double.
  std::string canonical_type(std::string t) const {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (t.rfind("vtktype", 0) == 0) t = t.substr(7);
    static const std::map<std::string, std::string> names{
        {"char", "int8"},      {"signed_char", "int8"},     {"unsigned_char", "uint8"},  {"short", "int16"},
        {"unsigned_short", "uint16"}, {"int", "int32"},     {"vtkidtype", "int32"},      {"unsigned_int", "uint32"},
        {"long", "int64"},     {"unsigned_long", "uint64"}, {"float", "float"},         {"double", "double"}};
    if (const auto it = names.find(t); it != names.end()) return it->second;
    static const std::set<std::string> sized{"int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"};
    if (!sized.count(t)) fail("unsupported data type '" + t.substr(0, 40) + "'");
    return t;
  }
  std::size_t type_size(const std::string& t) const {
    if (t == "double" || t == "int64" || t == "uint64") return 8;
    if (t == "float" || t == "int32" || t == "uint32") return 4;
    return t == "int16" || t == "uint16" ? 2 : 1;
  }
  double binary_value(const std::string& t, const char* b) const {
    const auto get = [&](auto x) { return double(get_bytes<decltype(x)>(b, ByteOrder::Big)); };
    if (t == "double" || t == "float") {
      const double v = t == "double" ? get(double()) : get(float());
      if (!valid_coordinate(v)) fail(coordinate_error(v));
      return v;
    }
    if (t == "int64") return get(std::int64_t());
    if (t == "uint64") return get(std::uint64_t());
    if (t == "int32") return get(std::int32_t());
    if (t == "uint32") return get(std::uint32_t());
    if (t == "int16") return get(std::int16_t());
    if (t == "uint16") return get(std::uint16_t());
    if (t == "int8") return get(std::int8_t());
    return get(std::uint8_t());
  }
  static std::string unescape(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
          std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
        out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        out += s[i];
      }
    }
    return out;
  }
  std::string x_, path_;
  std::size_t at_ = 0;
  int line_ = 0;
  bool binary_ = false;
};

std::size_t count_of(LegacyVtk& f, const std::string& word) {
  long long n = -1;
  if (!parse_integer(word, n) || n < 0) f.fail("bad count '" + word.substr(0, 40) + "'");
  return std::size_t(n);
}

// The cells of a POLYGONS (VERTICES, LINES, TRIANGLE_STRIPS) section, its
// line `w`: 4.2's "n size" and size values (each cell its count, then its
// ids), or 5.1's "offsets size" and the OFFSETS and CONNECTIVITY arrays.
std::vector<std::vector<int>> read_cells(LegacyVtk& f, const std::vector<std::string>& w, std::size_t points) {
  if (w.size() != 3) f.fail("bad " + w[0] + " line");
  const std::size_t n = count_of(f, w[1]), size = count_of(f, w[2]);
  const auto id = [&](double v) {
    if (v < 0 || v >= double(points)) f.fail("a cell refers to unknown point " + std::to_string((long long)v));
    return int(v);
  };
  std::vector<std::vector<int>> cells;
  const auto offsets = f.peek();
  if (offsets.size() == 2 && offsets[0] == "OFFSETS") {
    f.next();
    const std::vector<double> off = f.values(offsets[1], n);
    const auto c = f.next();
    if (c.size() != 2 || c[0] != "CONNECTIVITY") f.fail("CONNECTIVITY expected after OFFSETS");
    const std::vector<double> con = f.values(c[1], size);
    for (std::size_t k = 0; k + 1 < off.size(); ++k) {
      if (off[k] < 0 || off[k] > off[k + 1] || off[k + 1] > double(con.size())) f.fail("bad offsets");
      cells.emplace_back();
      for (auto i = std::size_t(off[k]); i < std::size_t(off[k + 1]); ++i) cells.back().push_back(id(con[i]));
    }
    return cells;
  }
  const std::vector<double> v = f.values("int", size);
  for (std::size_t i = 0, c = 0; c < n; ++c) {
    const std::size_t k = i < v.size() ? std::size_t(v[i]) : 0;
    if (i + 1 + k > v.size()) f.fail("a cell beyond the section's size");
    cells.emplace_back();
    for (std::size_t j = 0; j < k; ++j) cells.back().push_back(id(v[i + 1 + j]));
    i += 1 + k;
  }
  return cells;
}

// What a legacy file's data sections hold that a SurfaceMesh or a TetMesh keeps.
struct VtkArrays {
  std::vector<double> label, labels, region, label_values, normals;
  std::vector<std::string> label_names;
};

// A FIELD's arrays ("name components tuples type", then the values; 5.1
// may put METADATA after one, up to a blank line).
void read_field(LegacyVtk& f, const std::vector<std::string>& w, bool cells, VtkArrays& out) {
  if (w.size() != 3) f.fail("bad FIELD line");
  const std::size_t arrays = count_of(f, w[2]);
  for (std::size_t a = 0; a < arrays; ++a) {
    const auto h = f.next();
    if (h.size() != 4) f.fail("bad FIELD array line");
    const std::size_t n = count_of(f, h[1]) * count_of(f, h[2]);
    if (h[3] == "string") {
      auto s = f.strings(n);
      if (!cells && h[0] == "label_names") out.label_names = std::move(s);
    } else {
      auto v = f.values(h[3], n);
      if (cells && h[0] == "label" && h[1] == "1") out.label = std::move(v);
      if (cells && h[0] == "labels" && h[1] == "2") out.labels = std::move(v);
      if (cells && h[0] == "region" && h[1] == "1") out.region = std::move(v);
      if (!cells && h[0] == "label_values") out.label_values = std::move(v);
    }
    if (auto m = f.peek(); !m.empty() && m[0] == "METADATA")
      while (!f.at_end() && !f.line().empty()) {
      }
  }
}

// A legacy file's dataset: POLYDATA (its triangles) or UNSTRUCTURED_GRID
// (its cells and their types), the points and the arrays kept.
struct LegacyDataset {
  bool grid = false;
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<int>> cells;
  std::vector<double> types;
  VtkArrays arrays;
};

// One section of a legacy file, its keyword line `w`, into d; `tuples`,
// `cells` and `data` say which data section we are in.
void read_section(LegacyVtk& f, const std::vector<std::string>& w, LegacyDataset& d, std::size_t& tuples, bool& cells,
                  bool& data) {
  const std::string& k = w[0];
  VtkArrays& arrays = d.arrays;
  if (k == "POINTS" && w.size() == 3) {
    const std::vector<double> p = f.values(w[2], 3 * count_of(f, w[1]));
    for (std::size_t i = 0; i < p.size(); i += 3) d.points.push_back({p[i], p[i + 1], p[i + 2]});
  } else if (!d.grid && (k == "POLYGONS" || k == "VERTICES" || k == "LINES" || k == "TRIANGLE_STRIPS")) {
    for (auto& c : read_cells(f, w, d.points.size())) {
      if (k != "POLYGONS" || c.size() != 3) f.fail("a cell that is not a triangle: only triangles are read");
      d.cells.push_back(std::move(c));
    }
  } else if (d.grid && k == "CELLS") {
    d.cells = read_cells(f, w, d.points.size());
  } else if (d.grid && k == "CELL_TYPES" && w.size() == 2) {
    d.types = f.values("int", count_of(f, w[1]));
  } else if ((k == "CELL_DATA" || k == "POINT_DATA") && w.size() == 2) {
    cells = k == "CELL_DATA";
    data = true;
    tuples = count_of(f, w[1]);
  } else if (k == "FIELD") {
    read_field(f, w, data && cells, arrays);
  } else if (k == "SCALARS" && data && w.size() >= 3) {
    const std::size_t components = w.size() > 3 ? count_of(f, w[3]) : 1;
    const auto lut = f.peek();
    if (lut.size() == 2 && lut[0] == "LOOKUP_TABLE") f.next();
    auto v = f.values(w[2], tuples * components);
    if (cells && w[1] == "label" && components == 1) arrays.label = std::move(v);
    if (cells && w[1] == "labels" && components == 2) arrays.labels = std::move(v);
    if (cells && w[1] == "region" && components == 1) arrays.region = std::move(v);
  } else if ((k == "NORMALS" || k == "VECTORS" || k == "TENSORS") && data && w.size() == 3) {
    auto v = f.values(w[2], tuples * (k == "TENSORS" ? 9 : 3));
    if (!cells && k == "NORMALS") arrays.normals = std::move(v);
  } else if (k == "METADATA") {
    while (!f.at_end() && !f.line().empty()) {
    }
  } else {
    f.fail("unsupported legacy VTK keyword '" + k.substr(0, 40) + "'");
  }
}

LegacyDataset read_dataset(LegacyVtk& f) {
  if (f.line().rfind("# vtk DataFile Version", 0) != 0) f.fail("not a legacy VTK file");
  f.line();  // the title
  const auto encoding = f.words();
  if (encoding.size() != 1 || (encoding[0] != "ASCII" && encoding[0] != "BINARY")) f.fail("ASCII or BINARY expected");
  f.set_binary(encoding[0] == "BINARY");
  LegacyDataset d;
  const auto dataset = f.next();
  d.grid = dataset == std::vector<std::string>{"DATASET", "UNSTRUCTURED_GRID"};
  if (!d.grid && dataset != std::vector<std::string>{"DATASET", "POLYDATA"})
    f.fail("only DATASET POLYDATA (a surface) or UNSTRUCTURED_GRID (tetrahedra) is read");
  std::size_t tuples = 0;  // of the CELL_DATA or POINT_DATA section we are in
  bool cells = false, data = false;
  for (auto w = f.next(); !w.empty(); w = f.next()) read_section(f, w, d, tuples, cells, data);
  const std::size_t n = d.cells.size();
  if (d.grid && d.types.size() != n) f.fail("not one CELL_TYPES value a cell");
  if (!d.arrays.label.empty() && d.arrays.label.size() != n) f.fail("not one label a cell");
  if (!d.arrays.labels.empty() && d.arrays.labels.size() != 2 * n) f.fail("not two labels a cell");
  if (!d.arrays.region.empty() && d.arrays.region.size() != n) f.fail("not one region a cell");
  return d;
}

SurfaceMesh surface_of(LegacyDataset d, const std::string& path) {
  if (d.grid) throw Error("a DATASET UNSTRUCTURED_GRID: a surface (DATASET POLYDATA) expected", path);
  SurfaceMesh m;
  m.points = std::move(d.points);
  for (const auto& c : d.cells) m.triangles.push_back({c[0], c[1], c[2]});
  const VtkArrays& arrays = d.arrays;
  for (double l : arrays.label) m.labels.push_back(int(l));
  for (std::size_t i = 0; i < arrays.labels.size(); i += 2)
    m.interfaces.push_back({int(arrays.labels[i]), int(arrays.labels[i + 1])});
  if (arrays.normals.size() == 3 * m.points.size())
    for (std::size_t i = 0; i < arrays.normals.size(); i += 3)
      m.normals.push_back({arrays.normals[i], arrays.normals[i + 1], arrays.normals[i + 2]});
  for (std::size_t i = 0; i < arrays.label_values.size() && i < arrays.label_names.size(); ++i)
    m.label_names[int(arrays.label_values[i])] = arrays.label_names[i];
  check_extent(m.points, path);
  return m;
}

// The grid's tetrahedra (VTK_TETRA, 10) and triangles (VTK_TRIANGLE, 5)
// with their cell data "region" (1 without), the other cells left out, as
// the .vtu reader does.
TetMesh tets_of(LegacyDataset d, const std::string& path) {
  TetMesh m;
  m.points = std::move(d.points);
  for (std::size_t c = 0; c < d.cells.size(); ++c) {
    const int region = d.arrays.region.empty() ? 1 : int(d.arrays.region[c]);
    const int type = d.types[c] == 10 && d.cells[c].size() == 4 ? 4 : d.types[c] == 5 && d.cells[c].size() == 3 ? 2 : 0;
    mesh_detail::add_element(m, type, d.cells[c], region);
  }
  if (m.tets.empty()) throw Error("no tetrahedron", path);
  check_extent(m.points, path);
  return m;
}

} // namespace

namespace mesh_detail {

SurfaceMesh read_vtk_legacy(const std::string& path) {
  LegacyVtk f(path);
  return surface_of(read_dataset(f), path);
}

TetsOrSurface read_vtk_legacy_mesh(const std::string& path) {
  LegacyVtk f(path);
  LegacyDataset d = read_dataset(f);
  TetsOrSurface m;
  if (d.grid) m.tets = tets_of(std::move(d), path);
  else m.surface = surface_of(std::move(d), path);
  return m;
}

// A .msh's triangles; their groups as label pairs (its $LabelPairs, else
// names "a|b" of two integers), else as labels (tag = label, as write_msh
// writes them) unless the groups are components.
SurfaceMesh read_msh_surface(const std::string& path) { return msh_surface(read_msh_file(path), path); }

SurfaceMesh msh_surface(MshFile f, const std::string& path) {
  SurfaceMesh m;
  m.points = std::move(f.mesh.points);
  m.triangles = std::move(f.mesh.triangles);
  if (m.triangles.empty()) throw Error("no triangle", path);
  const std::vector<int>& tag = f.mesh.triangle_region;
  const std::set<int> used(tag.begin(), tag.end());
  std::map<int, std::array<int, 2>> pairs = f.label_pairs;
  bool components = false;
  for (int t : used) {
    const auto named = f.physical_names.find(t);
    const std::string name = named == f.physical_names.end() ? "" : named->second;
    components |= name.rfind("component ", 0) == 0;
    long long a, b;
    const std::size_t bar = name.find('|');
    if (f.label_pairs.empty() && bar != std::string::npos && parse_integer(name.substr(0, bar), a) &&
        parse_integer(name.substr(bar + 1), b))
      pairs[t] = {int(a), int(b)};
  }
  if (!pairs.empty()) {
    for (int t : tag) {
      const auto p = pairs.find(t);
      if (p == pairs.end()) throw Error("a triangle of physical group " + std::to_string(t) + " has no label pair", path);
      m.interfaces.push_back(p->second);
    }
  } else if (!components && !f.physical_names.empty()) {
    m.labels = tag;
    for (int t : used)
      if (f.physical_names.count(t) && f.physical_names.at(t) != "label " + std::to_string(t))
        m.label_names[t] = f.physical_names.at(t);
  }
  return m;
}

} // namespace mesh_detail
} // namespace imgmesh
