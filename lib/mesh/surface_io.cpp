// Surface mesh I/O. OFF is read and written here directly (it is the format
// on pipes, and reading it ourselves keeps non-manifold input intact so that
// checks can report it); PLY, VTK and msh are written by surface_formats.cpp
// (they carry per-face data), ASCII STL here; reading PLY, OBJ, STL and
// writing OBJ and binary STL go through OpenMesh.
#include "mesh/surface_io.hpp"

#include "mesh/mesh_read_detail.hpp"
#include "mesh/surface_formats.hpp"

#include "util/atomic_file.hpp"
#include "util/binary_io.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"
#include "util/path.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <set>
#include <sstream>

namespace imgmesh {
namespace {

struct Traits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<Traits>;
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

// Tokens of an OFF text with comments removed, with line numbers for errors.
class OffTokens {
public:
  OffTokens(const std::string& text, const std::string& path) : in_(text), path_(path) {}
  bool next(std::string& tok) {
    while (!(line_ >> tok)) {
      std::string l;
      if (!std::getline(in_, l)) return false;
      ++lineno_;
      auto hash = l.find('#');
      if (hash != std::string::npos) l.resize(hash);
      line_.clear();
      line_.str(l);
    }
    return true;
  }
  template <class T> T get(const char* what) {
    std::string tok;
    if (!next(tok)) fail(std::string("truncated: expected ") + what);
    std::istringstream ss(tok);
    T v;
    if (!(ss >> v) || !ss.eof()) fail(std::string("expected ") + what + ", found '" + tok + "'");
    return v;
  }
  double coordinate() {
    std::string tok;
    if (!next(tok)) fail("truncated: expected a coordinate");
    double v;
    if (!parse_coordinate(tok, v)) fail(coordinate_error(tok));
    return v;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("line " + std::to_string(lineno_) + ": " + what, path_);
  }

private:
  std::istringstream in_;
  std::istringstream line_;
  std::string path_;
  int lineno_ = 0;
};

SurfaceMesh read_off(const std::string& path) {
  const std::string text = read_all(path);
  OffTokens t(text, path);
  std::string head;
  if (!t.next(head)) throw Error("empty file", path);
  if (head != "OFF") t.fail("not an OFF file (no OFF header; NOFF/COFF variants are not read)");
  const long nv = t.get<long>("the vertex count"), nf = t.get<long>("the face count");
  t.get<long>("the edge count");
  if (nv < 0 || nf < 0 || nv > 1L << 31 || nf > 1L << 31) t.fail("bad counts");
  // A vertex is 3 numbers and a face 4, each at least a character and a
  // blank: counts the text cannot hold are refused before allocating.
  if (3 * nv + 4 * nf > (long(text.size()) + 1) / 2)
    t.fail("truncated: the counts announce more vertices and faces than the file holds");
  SurfaceMesh m;
  m.points.resize(std::size_t(nv));
  for (auto& p : m.points)
    for (double& c : p) c = t.coordinate();
  check_extent(m.points, path);
  m.triangles.resize(std::size_t(nf));
  for (auto& f : m.triangles) {
    const long k = t.get<long>("a face size");
    if (k != 3) t.fail("face with " + std::to_string(k) + " vertices: triangles expected");
    for (int& v : f) {
      const long id = t.get<long>("a vertex id");
      if (id < 0 || id >= nv) t.fail("vertex id " + std::to_string(id) + " out of range");
      v = int(id);
    }
    // Colour values may follow a face; they are ignored by skipping to the
    // next line in OffTokens only if present on the same line, so we do not
    // try to be clever here: standard OFF from our tools has none.
  }
  return m;
}

// OpenMesh's PLY reader trusts its header: without "end_header" it never
// stops, a property before any element crashes it, and it reserves what the
// counts say, list lengths too. So the header is checked here first against
// the PLY grammar, every element count against the bytes of the file, and in
// an ASCII file every face's vertex count against the vertices there are and
// every vertex's x, y, z against the coordinates the tools take (OpenMesh
// reads them as floats: a number past that range fails its stream and the
// rest of the file with it).
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<std::string> properties, types;  // names and types, in order ("list uchar int" for a list)
  bool list = false;                           // a list property among them

  // Where x, y, z are among the properties (those present, as (axis,
  // field)), and none when a list makes a vertex's fields other than one per
  // property.
  std::vector<std::pair<std::size_t, std::size_t>> coordinates() const {
    std::vector<std::pair<std::size_t, std::size_t>> xyz;
    if (list) return xyz;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const auto at = std::find(properties.begin(), properties.end(), std::string(1, char('x' + axis)));
      if (at != properties.end()) xyz.push_back({axis, std::size_t(at - properties.begin())});
    }
    return xyz;
  }
};

// Bytes of a PLY scalar type (the header check admits no other name).
std::size_t ply_size(const std::string& type) {
  if (type == "double" || type == "float64") return 8;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32")
    return 4;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  return 1;
}

// A binary PLY scalar of `type` at b, in the file's byte order, as a double.
double ply_value(const unsigned char* b, const std::string& type, bool big_endian) {
  const auto get = [&](auto x) {
    return double(get_bytes<decltype(x)>(reinterpret_cast<const char*>(b), big_endian ? ByteOrder::Big : ByteOrder::Little));
  };
  if (type == "double" || type == "float64") return get(double());
  if (type == "float" || type == "float32") return get(float());
  if (type == "int" || type == "int32") return get(std::int32_t());
  if (type == "uint" || type == "uint32") return get(std::uint32_t());
  if (type == "short" || type == "int16") return get(std::int16_t());
  if (type == "ushort" || type == "uint16") return get(std::uint16_t());
  if (type == "char" || type == "int8") return get(std::int8_t());
  return get(std::uint8_t());
}

// The vertices of a binary PLY, where the elements before them have no
// lists (so that their place is known): every x, y, z as the file holds it
// (OpenMesh reads them as floats: 1e-300 would come out 0, 1e300 infinite).
void check_binary_ply_vertices(std::istream& in, const std::vector<PlyElement>& elements, bool big_endian,
                               const std::string& path) {
  std::streamoff at = in.tellg();
  for (const PlyElement& e : elements) {
    if (e.list) return;
    std::size_t record = 0;
    std::vector<std::size_t> offset;
    for (const auto& t : e.types) {
      offset.push_back(record);
      record += ply_size(t);
    }
    if (e.name != "vertex") {
      at += std::streamoff(record) * e.count;
      continue;
    }
    in.seekg(at);
    Extent extent;
    std::vector<unsigned char> b(record);
    for (long long i = 0; i < e.count; ++i) {
      if (!in.read(reinterpret_cast<char*>(b.data()), std::streamsize(record))) return;  // short: OpenMesh reports it
      for (const auto& [axis, k] : e.coordinates()) {
        const double v = ply_value(&b[offset[k]], e.types[k], big_endian);
        const bool single = e.types[k] == "float" || e.types[k] == "float32";
        if (single ? !valid_coordinate(float(v)) : !valid_coordinate(v))
          throw Error("cannot read the mesh: PLY vertex " + std::to_string(i) + ": " + coordinate_error(v), path);
        extent.add(axis, v);
      }
    }
    check_extent(extent.value(), path);
    return;
  }
}

// The body of an ASCII PLY, one element a line: each face line starts with
// a vertex count from 3 to the number of vertices.
void check_ascii_ply_body(std::istream& in, const std::vector<PlyElement>& elements, int number,
                          const std::string& path) {
  long long vertices = 0;
  std::string line;
  auto fail = [&](const std::string& what) {
    throw Error("cannot read the mesh: PLY line " + std::to_string(number) + ": " + what, path);
  };
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertices = e.count;
    // The coordinates' fields in a vertex line.
    const auto xyz = e.name == "vertex" ? e.coordinates() : std::vector<std::pair<std::size_t, std::size_t>>{};
    Extent extent;
    for (long long i = 0; i < e.count; ++i) {
      if (!std::getline(in, line)) return;  // short: OpenMesh reports it
      ++number;
      std::istringstream words(line);
      if (!xyz.empty()) {
        std::vector<std::string> w;
        for (std::string x; words >> x;) w.push_back(x);
        double v;
        for (const auto& [axis, k] : xyz) {
          if (k < w.size() && !parse_coordinate(w[k], v)) fail(coordinate_error(w[k]));
          if (k < w.size()) extent.add(axis, v);
        }
        if (i + 1 == e.count) check_extent(extent.value(), path);
      }
      if (e.name != "face") continue;
      std::string first;
      long long n = 0;
      if (!(words >> first) || !(std::istringstream(first) >> n) || n < 3 || n > vertices)
        fail(first.empty() ? std::string("a face without its vertex count")
                           : "a face of " + first.substr(0, 20) + " vertices (" + std::to_string(vertices) +
                                 " in the file)");
    }
  }
}

struct PlyHeader {
  std::vector<PlyElement> elements;  // in file order
  bool ascii = false, big_endian = false;
  std::streamoff body = 0;  // where the data starts
  bool has(const std::string& element, const std::string& property) const {
    for (const PlyElement& e : elements)
      if (e.name == element && std::count(e.properties.begin(), e.properties.end(), property)) return true;
    return false;
  }
};

PlyHeader check_ply_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const long long file_size = in.tellg();
  in.seekg(0);
  static const std::set<std::string> types{"char",  "uchar",  "short",  "ushort", "int",     "uint",
                                           "float", "double", "int8",   "uint8",  "int16",   "uint16",
                                           "int32", "uint32", "float32", "float64"};
  std::string line;
  int number = 0;
  bool element = false, ascii = false, big_endian = false;
  std::vector<PlyElement> elements;  // in file order
  auto fail = [&](const std::string& what) {
    throw Error("cannot read the mesh: PLY header line " + std::to_string(number) + ": " + what, path);
  };
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    if (number == 1) {
      if (w.size() != 1 || w[0] != "ply") fail("not a PLY file (no 'ply' line)");
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      const PlyHeader header{elements, ascii, big_endian, in.tellg()};
      if (ascii) check_ascii_ply_body(in, elements, number, path);
      else check_binary_ply_vertices(in, elements, big_endian, path);
      return header;
    }
    if (w[0] == "format") {
      // OpenMesh loops for ever on a version it cannot parse.
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") ||
          (w[2] != "1.0" && w[2] != "1"))
        fail("bad format line (ascii, binary_little_endian or binary_big_endian, version 1.0)");
      ascii = w[1] == "ascii";
      big_endian = w[1] == "binary_big_endian";
    } else if (w[0] == "element") {
      long long n = -1;
      if (w.size() != 3 || !(std::istringstream(w[2]) >> n) || n < 0) fail("bad element line");
      if (n > file_size) fail("element count " + w[2] + " beyond the " + std::to_string(file_size) + " bytes of the file");
      elements.push_back({w[1], n, {}, {}, false});
      element = true;
    } else if (w[0] == "property") {
      if (!element) fail("a property before any element");
      const bool list = w.size() == 5 && w[1] == "list" && types.count(w[2]) && types.count(w[3]);
      if (!list && (w.size() != 3 || !types.count(w[1]))) fail("bad property line");
      elements.back().properties.push_back(w.back());
      elements.back().types.push_back(list ? "list " + w[2] + " " + w[3] : w[1]);
      elements.back().list |= list;
    } else {
      fail("unknown keyword '" + w[0] + "'");
    }
  }
  throw Error("cannot read the mesh: PLY header line " + std::to_string(number) + ": no end_header", path);
}

// A PLY read as it is, every face kept in its place (OpenMesh cuts a
// triangle set that is no manifold, as an interface mesh is at its
// curves): vertices' x, y, z; faces' vertex_indices (triangles) and int
// properties label, label_behind, label_front.
SurfaceMesh read_ply_as_is(const std::string& path, const PlyHeader& h) {
  const std::string x = read_all(path);
  std::size_t at = std::size_t(h.body);
  std::istringstream text(h.ascii ? x.substr(at) : std::string());
  long long item = 0;  // the element being read, for errors
  const auto fail = [&](const std::string& what) {
    throw Error("cannot read the mesh: PLY element " + std::to_string(item) + ": " + what, path);
  };
  const auto scalar = [&](const std::string& type) {
    double v;
    if (h.ascii) {
      std::string s;
      if (!(text >> s) || !parse_real(s, v)) fail(s.empty() ? "unexpected end of file" : "not a number: " + s.substr(0, 40));
      return type == "float" || type == "float32" ? double(float(v)) : v;  // as binary holds it
    }
    if (at + ply_size(type) > x.size()) fail("unexpected end of file");
    v = ply_value(reinterpret_cast<const unsigned char*>(x.data() + at), type, h.big_endian);
    at += ply_size(type);
    return v;
  };
  SurfaceMesh m;
  std::vector<int> label;
  for (const PlyElement& e : h.elements)
    for (item = 0; item < e.count; ++item) {
      std::array<double, 3> p{0, 0, 0};
      std::array<int, 3> t{-1, -1, -1};
      std::array<int, 3> labels{0, 0, 0};  // label, label_behind, label_front
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const std::string& name = e.properties[k];
        std::istringstream type(e.types[k]);
        std::string list, count_type, value_type;
        type >> list >> count_type >> value_type;
        if (list != "list") {
          const double v = scalar(e.types[k]);
          if (e.name == "vertex" && name.size() == 1 && name[0] >= 'x' && name[0] <= 'z') {
            if (!valid_coordinate(v)) fail(coordinate_error(v));
            p[std::size_t(name[0] - 'x')] = v;
          }
          if (name == "label" || name == "label_behind" || name == "label_front")
            labels[name == "label" ? 0 : name == "label_behind" ? 1 : 2] = int(v);
          continue;
        }
        const double n = scalar(count_type);
        const bool ids = e.name == "face" && (name == "vertex_indices" || name == "vertex_index");
        if (ids && n != 3) fail("a face of " + std::to_string((long long)n) + " vertices: triangles expected");
        for (long long i = 0; i < (long long)n; ++i) {
          const double v = scalar(value_type);
          if (ids) t[std::size_t(i)] = int(v);
        }
      }
      if (e.name == "vertex") m.points.push_back(p);
      if (e.name != "face") continue;
      for (int v : t)
        if (v < 0 || std::size_t(v) >= m.points.size()) fail("vertex id " + std::to_string(v) + " out of range");
      m.triangles.push_back(t);
      label.push_back(labels[0]);
      m.interfaces.push_back({labels[1], labels[2]});
    }
  if (h.has("face", "label")) m.labels = label;
  check_extent(m.points, path);
  return m;
}

// Three coordinates from `words` (the rest of a vertex line of an ASCII
// file OpenMesh reads): OpenMesh reads them as floats and, where one fails,
// drops the vertex (OBJ) or the rest of the file (STL) without a word.
void check_coordinates(std::istream& words, int number, const std::string& path, Extent& extent) {
  std::string word;
  for (std::size_t k = 0; k < 3; ++k) {
    double v;
    if (!(words >> word))
      throw Error("cannot read the mesh: line " + std::to_string(number) + ": a vertex needs x y z", path);
    if (!parse_coordinate(word, v))
      throw Error("cannot read the mesh: line " + std::to_string(number) + ": " + coordinate_error(word), path);
    extent.add(k, v);
  }
}

// OpenMesh's OBJ reader asserts (aborts) on a face without a vertex it can
// use: every face is checked here first to be at least 3 references
// "v[/vt][/vn]" to vertices defined before it (1-based, or negative from
// the last one); every vertex to be 3 coordinates.
void check_obj_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, word;
  long long vertices = 0;
  int number = 0;
  Extent extent;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    if (!(words >> word)) continue;
    if (word == "v") {
      ++vertices;
      check_coordinates(words, number, path, extent);
    }
    if (word != "f") continue;
    int refs = 0;
    while (words >> word) {
      const std::string v = word.substr(0, word.find('/'));
      long long id = 0;
      std::size_t used = 0;
      try {
        id = std::stoll(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != v.size() || id == 0 || id > vertices || -id > vertices)
        throw Error("cannot read the mesh: line " + std::to_string(number) + ": bad vertex reference '" + word + "'",
                    path);
      ++refs;
    }
    if (refs < 3)
      throw Error("cannot read the mesh: line " + std::to_string(number) + ": a face needs 3 vertices", path);
  }
  check_extent(extent.value(), path);
}

// An STL's coordinates as the file holds them: a binary one (84 + 50 n
// bytes, as OpenMesh tells them apart) as floats, an ASCII one as the text
// of its "vertex" lines.
void check_stl_coordinates(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char head[84] = {};
  in.read(reinterpret_cast<char*>(head), 84);
  in.clear();
  in.seekg(0, std::ios::end);
  const long long size = in.tellg();
  long long triangles = 0;  // little-endian
  for (int i = 3; i >= 0; --i) triangles = triangles * 256 + head[80 + i];
  Extent extent;
  if (size >= 84 && size == 84 + 50LL * triangles) {
    in.seekg(84);
    unsigned char t[50];
    for (long long i = 0; i < triangles && in.read(reinterpret_cast<char*>(t), 50); ++i)
      for (int k = 3; k < 12; ++k) {  // after the normal, 3 corners
        const double v = ply_value(t + 4 * k, "float", false);
        if (!valid_coordinate(float(v)))
          throw Error("cannot read the mesh: STL triangle " + std::to_string(i) + ": " + coordinate_error(v), path);
        extent.add(std::size_t(k % 3), v);
      }
  } else {
    in.seekg(0);
    std::string line, word;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      std::istringstream words(line);
      if (words >> word && word == "vertex") check_coordinates(words, number, path, extent);
    }
  }
  check_extent(extent.value(), path);
}

// A line of numbers by std::to_chars, the same text as the stream's at
// precision 17 (printf's %.17g, which to_chars' general format is defined
// by) in a fraction of the time (the bunny's output was 1.4% of its run).
void write_off(std::ostream& out, const SurfaceMesh& m) {
  out << "OFF\n" << m.points.size() << ' ' << m.triangles.size() << " 0\n";
  char line[128];
  for (const auto& p : m.points) {
    char* e = line;
    for (int k = 0; k < 3; ++k) {
      e = std::to_chars(e, line + sizeof line, p[std::size_t(k)], std::chars_format::general, 17).ptr;
      *e++ = k < 2 ? ' ' : '\n';
    }
    out.write(line, e - line);
  }
  for (const auto& f : m.triangles) {
    char* e = line;
    *e++ = '3';
    for (int v : f) {
      *e++ = ' ';
      e = std::to_chars(e, line + sizeof line, v).ptr;
    }
    *e++ = '\n';
    out.write(line, e - line);
  }
}

// The unit normal of triangle f as STL stores it (0 when degenerate).
std::array<float, 3> facet_normal(const SurfaceMesh& m, const std::array<int, 3>& f) {
  const auto &a = m.points[std::size_t(f[0])], &b = m.points[std::size_t(f[1])], &c = m.points[std::size_t(f[2])];
  std::array<double, 3> n{(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                          (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                          (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return {float(len > 0 ? n[0] / len : 0), float(len > 0 ? n[1] / len : 0), float(len > 0 ? n[2] / len : 0)};
}

// ASCII STL: the floats binary STL holds, 9 digits each (the same floats back).
void write_stl_ascii(std::ostream& out, const SurfaceMesh& m) {
  out.precision(9);
  out << "solid imgmesh\n";
  for (const auto& f : m.triangles) {
    const auto n = facet_normal(m, f);
    out << "  facet normal " << n[0] << ' ' << n[1] << ' ' << n[2] << "\n    outer loop\n";
    for (int v : f) {
      const auto& p = m.points[std::size_t(v)];
      out << "      vertex " << float(p[0]) << ' ' << float(p[1]) << ' ' << float(p[2]) << '\n';
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid imgmesh\n";
}

// A triangle set OpenMesh's halfedge mesh cannot hold (not a manifold: e.g.
// a refinement stopped by --max-points), in the layout OpenMesh writes for
// a manifold one (OBJ, binary STL), so that the run still leaves its output
// (exit 3) in the format asked for.
void write_triangle_set(std::ostream& out, const std::string& ext, const SurfaceMesh& m, bool normals) {
  if (ext == ".obj") {
    out << "# " << m.points.size() << " vertices, " << m.triangles.size() << " faces\n";
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      out << "v " << m.points[i][0] << ' ' << m.points[i][1] << ' ' << m.points[i][2] << '\n';
      if (normals) out << "vn " << m.normals[i][0] << ' ' << m.normals[i][1] << ' ' << m.normals[i][2] << '\n';
    }
    for (const auto& f : m.triangles) {
      out << 'f';
      for (int v : f) out << ' ' << v + 1 << (normals ? "//" + std::to_string(v + 1) : "");
      out << '\n';
    }
  } else {  // .stl
    out << std::string(80, ' ');
    put_bytes(out, std::uint32_t(m.triangles.size()));
    for (const auto& f : m.triangles) {
      for (float x : facet_normal(m, f)) put_bytes(out, x);
      for (int v : f)
        for (double x : m.points[std::size_t(v)]) put_bytes(out, float(x));
      put_bytes(out, std::uint16_t(0));
    }
  }
}

} // namespace

SurfaceMesh read_surface(const std::string& path) {
  const std::string ext = path == "-" ? ".off" : extension_of(path);
  if (ext == ".off") return read_off(path);
  if (!is_surface_output(path))
    throw Error("unknown mesh extension '" + ext + "' (OFF, PLY, OBJ, STL, VTP, VTK or MSH expected)", path);
  {
    std::ifstream probe(path);
    if (!probe) throw Error("cannot open", path);
  }
  if (ext == ".vtp") return mesh_detail::read_vtp(path);
  if (ext == ".vtk") return mesh_detail::read_vtk_legacy(path);
  if (ext == ".msh") return mesh_detail::read_msh_surface(path);
  if (ext == ".ply") {
    const PlyHeader header = check_ply_header(path);
    if (header.has("face", "label_behind") && header.has("face", "label_front")) return read_ply_as_is(path, header);
  }
  if (ext == ".obj") check_obj_text(path);
  if (ext == ".stl") check_stl_coordinates(path);
  PolyMesh pm;
  OpenMesh::IO::Options opt;
  omerr().disable();
  omlog().disable();
  const bool ok = OpenMesh::IO::read_mesh(pm, path, opt);
  if (!ok) throw Error("cannot read the mesh (corrupt or unsupported file)", path);
  SurfaceMesh m;
  m.points.reserve(pm.n_vertices());
  for (auto v : pm.vertices()) {
    const auto& p = pm.point(v);
    // Checked in the file above, but for a PLY whose vertices follow a list.
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(p[i])) throw Error("coordinate is not finite", path);
    m.points.push_back({p[0], p[1], p[2]});
  }
  for (auto f : pm.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (auto v : pm.fv_range(f)) {
      if (k == 3) throw Error("a face with more than 3 vertices: triangles expected", path);
      tri[std::size_t(k++)] = v.idx();
    }
    if (k != 3) throw Error("a face with fewer than 3 vertices", path);
    m.triangles.push_back(tri);
  }
  check_extent(m.points, path);
  return m;
}

const char* const kSurfaceExtensions = ".off, .ply, .obj, .stl, .vtp, .vtk or .msh";

bool is_surface_output(const std::string& path) {
  static const std::set<std::string> exts{".off", ".ply", ".obj", ".stl", ".vtp", ".vtk", ".msh"};
  return path == "-" || exts.count(extension_of(path)) > 0;
}

bool surface_output_holds_normals(const std::string& path) {
  const std::string ext = extension_of(path);
  return path != "-" && ext != ".off" && ext != ".stl";
}

bool surface_output_holds_labels(const std::string& path) {
  const std::string ext = extension_of(path);
  return ext == ".ply" || ext == ".vtp" || ext == ".vtk" || ext == ".msh";
}

void write_surface(const std::string& path, const SurfaceMesh& m, const SurfaceWriteOptions& options) {
  const std::string ext = path == "-" ? ".off" : extension_of(path);
  if (!is_surface_output(path))
    throw UsageError("unknown mesh extension '" + ext + "' (use " + kSurfaceExtensions + ")", path);
  if (options.msh_version != "4.1" && options.msh_version != "2.2")
    throw UsageError("msh version '" + options.msh_version + "': 4.1 or 2.2 expected");
  for (const auto& f : m.triangles)
    for (int v : f)
      if (v < 0 || std::size_t(v) >= m.points.size()) throw Error("internal: triangle refers to a missing vertex", path);
  const bool binary = !options.ascii && (ext == ".ply" || ext == ".stl" || ext == ".vtp" || ext == ".vtk");
  AtomicOutput out(path, binary || (ext == ".msh" && options.msh_binary));
  if (ext == ".off" || (ext == ".stl" && !binary)) {
    (ext == ".off" ? write_off : write_stl_ascii)(out.stream(), m);
    out.commit();
    return;
  }
  // The formats with per-face data are written here whatever the mesh is
  // (a triangle set that is not a manifold too).
  if (ext == ".ply" || ext == ".vtp" || ext == ".vtk" || ext == ".msh") {
    const std::vector<int> component = face_components(m);
    if (ext == ".ply") write_ply(out.stream(), m, component, binary);
    if (ext == ".vtp") write_vtp(out.stream(), m, component, binary);
    if (ext == ".vtk") write_vtk_legacy(out.stream(), m, component, binary);
    if (ext == ".msh") write_msh(out.stream(), m, component, options.msh_version, options.msh_binary);
    out.commit();
    return;
  }
  TriMesh tm;
  const bool normals = !m.normals.empty() && m.normals.size() == m.points.size() && ext != ".stl";
  if (normals) tm.request_vertex_normals();
  std::vector<TriMesh::VertexHandle> vh;
  vh.reserve(m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const auto& p = m.points[i];
    vh.push_back(tm.add_vertex(TriMesh::Point(p[0], p[1], p[2])));
    if (normals) tm.set_normal(vh.back(), TriMesh::Normal(m.normals[i][0], m.normals[i][1], m.normals[i][2]));
  }
  // OpenMesh logs on the terminal ("[STLWriter] : write binary file"); the
  // library never prints.
  omerr().disable();
  omlog().disable();
  omout().disable();
  for (const auto& f : m.triangles) {
    auto fh = tm.add_face(vh[std::size_t(f[0])], vh[std::size_t(f[1])], vh[std::size_t(f[2])]);
    if (!fh.is_valid()) {
      write_triangle_set(out.stream(), ext, m, normals);
      out.commit();
      return;
    }
  }
  OpenMesh::IO::Options opt;
  if (ext == ".stl") opt += OpenMesh::IO::Options::Binary;
  if (normals) opt += OpenMesh::IO::Options::VertexNormal;
  if (!OpenMesh::IO::write_mesh(tm, out.path(), opt, 17)) throw Error("cannot write the mesh", path);
  out.commit();
}

} // namespace imgmesh
