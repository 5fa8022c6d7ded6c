// Reading tetrahedral meshes (.msh ASCII or binary, .mesh, .vtu ASCII or
// appended): one reader per format over values that are text or binary, the
// coordinates checked against util/coordinates.hpp's range either way.
#include "mesh/volume_io.hpp"

#include "mesh/mesh_read_detail.hpp"

#include "util/atomic_file.hpp"
#include "util/binary_io.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"
#include "util/path.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace imgmesh {
namespace {


// Reading: a whitespace token stream, counting lines, with the file's name
// and the line in its errors.
struct Tokens {
  std::istream& in;
  const std::string& path;
  int line = 1;  // of the last token read (or where reading stopped)

  [[noreturn]] void fail(const std::string& what) const {
    throw Error("line " + std::to_string(line) + ": " + what, path);
  }
  // Past the blanks; false at the end.
  bool more() {
    for (int c; (c = in.peek()) != EOF && std::isspace(c); in.get())
      if (c == '\n') ++line;
    return in.peek() != EOF;
  }
  bool read(std::string& s) {
    if (!more()) return false;
    s.clear();
    for (int c; (c = in.peek()) != EOF && !std::isspace(c); in.get()) s.push_back(char(c));
    return true;
  }
  std::string next() {
    std::string s;
    if (!read(s)) fail("unexpected end of file");
    return s;
  }
  void skip_line() {
    for (int c; (c = in.get()) != EOF && c != '\n';) {
    }
    ++line;
  }
  long long integer() {
    const std::string s = next();
    long long v;
    if (!parse_integer(s, v)) fail("expected an integer, found '" + s.substr(0, 40) + "'");
    return v;
  }
  double real() {
    const std::string s = next();
    double v;
    if (!parse_real(s, v) || !std::isfinite(v)) fail("expected a finite number, found '" + s.substr(0, 40) + "'");
    return v;
  }
  double coordinate() {
    const std::string s = next();
    double v;
    if (!parse_coordinate(s, v)) fail(coordinate_error(s));
    return v;
  }
  std::size_t count(const char* what) {
    const long long n = integer();
    if (n < 0 || n > 200000000) fail(std::string("bad ") + what + " count " + std::to_string(n));
    return std::size_t(n);
  }
  void skip_to(const std::string& end) {
    while (next() != end) {
    }
  }
};

// Node tags to 0-based indices.
struct NodeIds {
  std::unordered_map<long long, int> id;
  int operator()(long long tag, const std::string& path) const {
    const auto it = id.find(tag);
    if (it == id.end()) throw Error("element refers to unknown node " + std::to_string(tag), path);
    return it->second;
  }
};

void add_element(TetMesh& m, int type, const std::vector<int>& v, int region) {
  if (type == 4) {
    m.tets.push_back({v[0], v[1], v[2], v[3]});
    m.tet_region.push_back(region);
  } else if (type == 2) {
    m.triangles.push_back({v[0], v[1], v[2]});
    m.triangle_region.push_back(region);
  }
}

int gmsh_nodes(int type) {
  switch (type) {
    case 1: return 2;
    case 2: return 3;
    case 3: return 4;
    case 4: return 4;
    case 15: return 1;
    default: return -1;
  }
}

// Gmsh's values: ASCII tokens, or binary (little-endian int of 4 bytes,
// size_t and double of 8), as the file's $MeshFormat says. The line count
// goes on through binary data, so that an error in the text after it names
// the file's line.
struct MshValues {
  Tokens& t;
  bool binary;
  std::size_t size = 0;  // the file's bytes: no binary count beyond them
  template <class T> T raw() {
    char b[sizeof(T)];
    if (!t.in.read(b, sizeof b)) t.fail("unexpected end of file");
    t.line += int(std::count(b, b + sizeof b, '\n'));
    return get_bytes<T>(b);
  }
  long long i() { return binary ? raw<std::int32_t>() : t.integer(); }
  long long z() {
    if (!binary) return t.integer();
    const std::uint64_t v = raw<std::uint64_t>();
    return v > std::uint64_t(1) << 62 ? -1 : (long long)v;
  }
  double d() {
    if (!binary) return t.real();
    const double v = raw<double>();
    if (!std::isfinite(v)) t.fail("a number is not finite");
    return v;
  }
  // Node `tag`'s x, y, z, in the range util/coordinates.hpp sets (text
  // errors name the line, binary ones the node).
  std::array<double, 3> point(long long tag) {
    std::array<double, 3> p;
    for (double& c : p) {
      if (!binary) {
        c = t.coordinate();
        continue;
      }
      c = raw<double>();
      if (!valid_coordinate(c)) throw Error("node " + std::to_string(tag) + ": " + coordinate_error(c), t.path);
    }
    return p;
  }
  std::size_t count(long long n, const char* what) const {
    if (n < 0 || n > 200000000 || (binary && std::size_t(n) > size))
      t.fail(std::string("bad ") + what + " count " + std::to_string(n));
    return std::size_t(n);
  }
  std::size_t count_z(const char* what) { return count(z(), what); }
  std::size_t count_i(const char* what) { return count(i(), what); }
  // Binary data starts after the newline that ends a keyword or count line.
  void data_starts() {
    if (!binary) return;
    if (t.in.get() != '\n') t.fail("malformed binary .msh: no newline before the data");
    ++t.line;
  }
  // ... and ends with a newline right where the counts say (a byte lost or
  // added is an error, not other numbers).
  void data_ends(const std::string& section) {
    if (!binary) return;
    if (t.in.get() != '\n') t.fail("malformed binary .msh: " + section + " does not end where its counts say");
    ++t.line;
  }
};

// 4.1's $Entities: (dim, tag) -> the entity's first physical tag.
void read_msh_entities(MshValues& v, std::map<std::pair<int, int>, int>& physical) {
  std::size_t n[4];
  for (auto& k : n) k = v.count_z("entity");
  for (int dim = 0; dim < 4; ++dim)
    for (std::size_t e = 0; e < n[dim]; ++e) {
      const int tag = int(v.i());
      for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) v.d();
      const std::size_t np = v.count_z("physical tag");
      for (std::size_t k = 0; k < np; ++k) {
        const int p = int(v.i());
        if (k == 0) physical[{dim, tag}] = p;
      }
      if (dim > 0) {
        const std::size_t nb = v.count_z("bounding entity");
        for (std::size_t k = 0; k < nb; ++k) v.i();
      }
    }
}

void read_msh_nodes(MshValues& v, bool v4, TetMesh& m, NodeIds& ids) {
  if (!v4) {
    const std::size_t k = v.count(v.t.integer(), "node");
    v.data_starts();
    for (std::size_t i = 0; i < k; ++i) {
      const long long g = v.i();
      ids.id[g] = int(m.points.size());
      m.points.push_back(v.point(g));
    }
    return;
  }
  const std::size_t blocks = v.count_z("block");
  v.count_z("node");
  v.z();
  v.z();
  for (std::size_t b = 0; b < blocks; ++b) {
    v.i();
    v.i();
    if (v.i() != 0) throw Error("parametric nodes are not supported", v.t.path);
    const std::size_t k = v.count_z("node");
    std::vector<long long> tags(k);
    for (auto& g : tags) g = v.z();
    for (long long g : tags) {
      ids.id[g] = int(m.points.size());
      m.points.push_back(v.point(g));
    }
  }
}

// One element after its tag: `tags` tags (the first is its region, else
// `region`) and its nodes.
void read_msh_element(MshValues& v, TetMesh& m, const NodeIds& ids, int type, std::size_t tags, int region, bool v4) {
  const int nn = gmsh_nodes(type);
  if (nn < 0) throw Error("unsupported element type " + std::to_string(type), v.t.path);
  for (std::size_t j = 0; j < tags; ++j) {
    const int g = int(v.i());
    if (j == 0) region = g;
  }
  std::vector<int> nodes;
  for (int j = 0; j < nn; ++j) nodes.push_back(ids(v4 ? v.z() : v.i(), v.t.path));
  add_element(m, type, nodes, region);
}

void read_msh_elements(MshValues& v, bool v4, TetMesh& m, const NodeIds& ids,
                       const std::map<std::pair<int, int>, int>& physical) {
  if (v4) {
    const std::size_t blocks = v.count_z("block");
    v.count_z("element");
    v.z();
    v.z();
    for (std::size_t b = 0; b < blocks; ++b) {
      const int dim = int(v.i()), entity = int(v.i()), type = int(v.i());
      const std::size_t k = v.count_z("element");
      const auto p = physical.find({dim, entity});
      for (std::size_t e = 0; e < k; ++e) {
        v.z();
        read_msh_element(v, m, ids, type, 0, p != physical.end() ? p->second : entity, true);
      }
    }
    return;
  }
  const std::size_t k = v.count(v.t.integer(), "element");
  v.data_starts();
  // 2.2: in ASCII each element says its type and tag count after its tag; in
  // binary a header (type, count, tag count) comes before each run.
  for (std::size_t read = 0; read < k;) {
    if (!v.binary) {
      v.i();
      const int type = int(v.i());
      read_msh_element(v, m, ids, type, v.count_i("tag"), 1, false);
      ++read;
      continue;
    }
    const int type = int(v.i());
    const std::size_t run = v.count_i("element"), tags = v.count_i("tag");
    if (run == 0 || run > k - read) throw Error("malformed binary $Elements", v.t.path);
    for (std::size_t e = 0; e < run; ++e) {
      v.i();
      read_msh_element(v, m, ids, type, tags, 1, false);
    }
    read += run;
  }
}

// $PhysicalNames: "dim tag \"name\"" a line; the surface groups' names kept.
void read_msh_physical_names(Tokens& t, std::map<int, std::string>& names) {
  const std::size_t n = t.count("physical name");
  for (std::size_t k = 0; k < n; ++k) {
    const long long dim = t.integer(), tag = t.integer();
    std::string rest;
    std::getline(t.in, rest);
    ++t.line;
    const std::size_t a = rest.find('"'), b = rest.rfind('"');
    if (a == std::string::npos || b == a) t.fail("a physical name without its double quotes");
    if (dim == 2) names[int(tag)] = rest.substr(a + 1, b - a - 1);
  }
}

// $LabelPairs (written by write_msh): "tag behind front" a line.
void read_msh_label_pairs(Tokens& t, std::map<int, std::array<int, 2>>& pairs) {
  const std::size_t n = t.count("label pair");
  for (std::size_t k = 0; k < n; ++k) {
    const long long tag = t.integer(), a = t.integer(), b = t.integer();
    pairs[int(tag)] = {int(a), int(b)};
  }
}

mesh_detail::MshFile read_msh(std::istream& in, const std::string& path) {
  Tokens t{in, path};
  if (t.next() != "$MeshFormat") throw Error("not a Gmsh .msh file", path);
  const std::string version = t.next();
  const long long type = t.integer();
  if (type != 0 && type != 1) throw Error("bad .msh file type " + std::to_string(type) + " (0 ASCII, 1 binary)", path);
  MshValues v{t, type == 1};
  const std::string size = t.next();
  if (v.binary) {
    if (size != "8") throw Error("binary .msh with a size_t of " + size + " bytes (8 expected)", path);
    v.data_starts();
    if (v.raw<std::int32_t>() != 1) throw Error("big-endian binary .msh is not supported", path);
    const auto here = in.tellg();
    in.seekg(0, std::ios::end);
    v.size = std::size_t(in.tellg());
    in.seekg(here);
  }
  if (t.next() != "$EndMeshFormat") throw Error("malformed $MeshFormat", path);
  if (version != "2.2" && version != "4.1") throw Error("unsupported .msh version " + version + " (2.2 or 4.1)", path);
  const bool v4 = version == "4.1";
  mesh_detail::MshFile file;
  TetMesh& m = file.mesh;
  NodeIds ids;
  std::map<std::pair<int, int>, int> physical;  // 4.1: (dim, entity) -> its first physical tag
  std::string s;
  while (t.read(s)) {
    const bool known = (s == "$Entities" && v4) || s == "$Nodes" || s == "$Elements";
    if (known && v4) v.data_starts();
    if (s == "$Entities" && v4) {
      read_msh_entities(v, physical);
      v.data_ends(s);
      t.skip_to("$EndEntities");
    } else if (s == "$Nodes") {
      read_msh_nodes(v, v4, m, ids);
      v.data_ends(s);
      if (t.next() != "$EndNodes") throw Error("malformed $Nodes", path);
    } else if (s == "$Elements") {
      read_msh_elements(v, v4, m, ids, physical);
      v.data_ends(s);
      if (t.next() != "$EndElements") throw Error("malformed $Elements", path);
    } else if (s == "$PhysicalNames" || s == "$LabelPairs") {
      if (s == "$PhysicalNames") read_msh_physical_names(t, file.physical_names);
      else read_msh_label_pairs(t, file.label_pairs);
      if (t.next() != "$End" + s.substr(1)) throw Error("malformed " + s, path);
    } else if (!s.empty() && s[0] == '$' && s.rfind("$End", 0) != 0) {
      t.skip_to("$End" + s.substr(1));
    } else {
      throw Error("unexpected '" + s + "'", path);
    }
  }
  return file;
}

TetMesh read_medit(std::istream& in, const std::string& path) {
  Tokens t{in, path};
  TetMesh m;
  std::string s;
  bool seen_version = false;
  while (t.read(s)) {
    if (s == "MeshVersionFormatted") {
      t.integer();
      seen_version = true;
    } else if (s == "Dimension") {
      if (t.integer() != 3) throw Error("only 3D MEDIT meshes are supported", path);
    } else if (s == "Vertices") {
      const std::size_t n = t.count("vertex");
      for (std::size_t i = 0; i < n; ++i) {
        m.points.push_back({t.coordinate(), t.coordinate(), t.coordinate()});
        t.integer();
      }
    } else if (s == "Triangles" || s == "Tetrahedra" || s == "Edges" || s == "Quadrilaterals") {
      const int nn = s == "Triangles" ? 3 : s == "Edges" ? 2 : 4;
      const std::size_t n = t.count("element");
      std::vector<int> v(static_cast<std::size_t>(nn));
      for (std::size_t i = 0; i < n; ++i) {
        for (int j = 0; j < nn; ++j) {
          const long long k = t.integer();
          if (k < 1 || k > (long long)m.points.size()) throw Error("element refers to unknown vertex " + std::to_string(k), path);
          v[std::size_t(j)] = int(k - 1);
        }
        const int ref = int(t.integer());
        if (s == "Triangles") add_element(m, 2, v, ref);
        if (s == "Tetrahedra") add_element(m, 4, v, ref);
      }
    } else if (s == "Corners" || s == "RequiredVertices" || s == "Ridges" || s == "RequiredEdges") {
      const std::size_t n = t.count("entry");
      for (std::size_t i = 0; i < n; ++i) t.integer();
    } else if (s == "End") {
      break;
    } else if (s[0] == '#') {
      t.skip_line();
    } else {
      throw Error("unsupported MEDIT keyword '" + s + "'", path);
    }
  }
  if (!seen_version) throw Error("not a MEDIT .mesh file (no MeshVersionFormatted)", path);
  return m;
}

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
    if (format != "ascii") throw Error("DataArray " + a.label + ": format \"" + format.substr(0, 40) + "\" (ascii, binary or appended expected)", path_);
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
        if (required) throw Error("no <" + section + "> in the .vtu file", path_);
        return {};
      }
    }
    for (;;) {
      at = x_.find("<DataArray", at);
      if (at == std::string::npos) {
        if (required) throw Error("no DataArray " + name + " in the .vtu file", path_);
        return {};
      }
      close = x_.find('>', at);
      if (close == std::string::npos) throw Error("a DataArray tag is not closed", path_);
      const std::string tag = x_.substr(at, close - at);
      if (name.empty() || tag.find("Name=\"" + name + "\"") != std::string::npos) return tag;
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
  static std::string attribute(const std::string& tag, const std::string& key) {
    const std::size_t at = tag.find(" " + key + "=\"");
    if (at == std::string::npos) return {};
    const std::size_t begin = at + key.size() + 3;
    return tag.substr(begin, tag.find('"', begin) - begin);
  }
  // A binary array: inline base64 from `inline_at`, or appended.
  template <class T> void decode(const std::string& tag, bool appended, std::size_t inline_at, VtuArray<T>& a) const {
    a.what = (appended ? "appended DataArray " : "binary DataArray ") + a.label;
    if (!compressor_.empty() && !layout_.zlib)
      throw Error(a.what + ": compressed by " + compressor_.substr(0, 40) + " (only zlib or no compression is read)", path_);
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

TetMesh read_vtu(const std::string& path) {
  const VtuArrays f(read_all(path), path);
  TetMesh m;
  const VtuArray<double> xyz = f.values<double>("Points", "");
  const VtuArray<long long> con = f.values<long long>("", "connectivity"), off = f.values<long long>("", "offsets"),
                            types = f.values<long long>("", "types"), reg = f.values<long long>("CellData", "region", false);
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

} // namespace

namespace mesh_detail {

MshFile read_msh_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open", path);
  MshFile f = read_msh(in, path);
  check_extent(f.mesh.points, path);
  return f;
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

TetMesh read_tet_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  TetMesh m;
  if (ext == ".vtu") m = read_vtu(path);
  else {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open", path);
    if (ext == ".msh") m = read_msh(in, path).mesh;
    else if (ext == ".mesh") m = read_medit(in, path);
    else throw Error("reading tetrahedral meshes: .msh, .mesh or .vtu", path);
  }
  if (m.tets.empty()) throw Error("no tetrahedron", path);
  check_extent(m.points, path);
  return m;
}

MshMesh read_msh_mesh(const std::string& path) {
  mesh_detail::MshFile f = mesh_detail::read_msh_file(path);
  MshMesh m;
  if (!f.mesh.tets.empty()) m.tets = std::move(f.mesh);
  else m.surface = mesh_detail::msh_surface(std::move(f), path);
  return m;
}

} // namespace imgmesh
