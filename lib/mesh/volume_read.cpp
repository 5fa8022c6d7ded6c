// Reading tetrahedral meshes (.msh ASCII or binary, .mesh; .vtu in
// vtk_xml_read.cpp, legacy .vtk in surface_read.cpp, .inp in inp_read.cpp): one reader per format
// over values that are text or binary, the coordinates checked against
// util/coordinates.hpp's range either way.
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

using mesh_detail::add_element;
using mesh_detail::Tokens;

// Node tags to 0-based indices.
struct NodeIds {
  std::unordered_map<long long, int> id;
  int operator()(long long tag, const std::string& path) const {
    const auto it = id.find(tag);
    if (it == id.end()) throw Error("element refers to unknown node " + std::to_string(tag), path);
    return it->second;
  }
};

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
void read_msh_physical_names(Tokens& t, std::map<int, std::string>& names, int& background) {
  const std::size_t n = t.count("physical name");
  for (std::size_t k = 0; k < n; ++k) {
    const long long dim = t.integer(), tag = t.integer();
    std::string rest;
    std::getline(t.in, rest);
    ++t.line;
    const std::size_t a = rest.find('"'), b = rest.rfind('"');
    if (a == std::string::npos || b == a) t.fail("a physical name without its double quotes");
    if (dim == 2) names[int(tag)] = rest.substr(a + 1, b - a - 1);
    if (dim == 3 && rest.substr(a + 1, b - a - 1) == kBackgroundName) background = int(tag);
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
    } else if (s == "$PhysicalNames" || s == "$LabelPairs" || s == "$BackgroundRegion") {
      if (s == "$PhysicalNames") read_msh_physical_names(t, file.physical_names, file.background);
      else if (s == "$LabelPairs") read_msh_label_pairs(t, file.label_pairs);
      else if ((file.background = int(t.integer())) < 0) t.fail("a negative background tag");
      if (t.next() != "$End" + s.substr(1)) throw Error("malformed " + s, path);
    } else if (!s.empty() && s[0] == '$' && s.rfind("$End", 0) != 0) {
      t.skip_to("$End" + s.substr(1));
    } else {
      throw Error("unexpected '" + s + "'", path);
    }
  }
  // The background's tag back to region 0 (write_tet_mesh's).
  const int bg = file.background;
  if (bg != 0) {
    for (int& r : m.tet_region) r = r == bg ? 0 : r;
    for (int& r : m.triangle_region) r = r == bg ? 0 : r;
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

} // namespace

namespace mesh_detail {

MshFile read_msh_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open", path);
  MshFile f = read_msh(in, path);
  check_extent(f.mesh.points, path);
  return f;
}

} // namespace mesh_detail

TetMesh read_tet_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  TetMesh m;
  if (ext == ".vtu") m = mesh_detail::read_vtu(path);
  else if (ext == ".inp") m = mesh_detail::read_inp(path);
  else {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open", path);
    if (ext == ".msh") m = read_msh(in, path).mesh;
    else if (ext == ".mesh") m = read_medit(in, path);
    else if (ext == ".vtk") {
      TetsOrSurface v = mesh_detail::read_vtk_legacy_mesh(path);
      if (!v.tets) throw Error("a DATASET POLYDATA: tetrahedra (DATASET UNSTRUCTURED_GRID) expected", path);
      m = std::move(*v.tets);
    }
    else throw Error("reading tetrahedral meshes: .msh, .mesh, .vtu, .inp or .vtk", path);
  }
  if (m.tets.empty()) throw Error("no tetrahedron", path);
  check_extent(m.points, path);
  return m;
}

TetsOrSurface read_tets_or_surface(const std::string& path) {
  if (extension_of(path) == ".vtk") return mesh_detail::read_vtk_legacy_mesh(path);
  mesh_detail::MshFile f = mesh_detail::read_msh_file(path);
  TetsOrSurface m;
  if (!f.mesh.tets.empty()) m.tets = std::move(f.mesh);
  else m.surface = mesh_detail::msh_surface(std::move(f), path);
  return m;
}

} // namespace imgmesh
