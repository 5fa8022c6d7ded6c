#include "mesh/volume_io.hpp"

#include "util/atomic_file.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"
#include "util/path.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace imgmesh {

const char* const kTetMeshExtensions = ".msh, .mesh, .vtu or .inp";

bool is_tet_mesh_path(const std::string& path) {
  const std::string e = extension_of(path);
  return e == ".msh" || e == ".mesh" || e == ".vtu" || e == ".inp";
}

namespace {

int region_of(const std::vector<int>& regions, std::size_t k) { return k < regions.size() ? regions[k] : 1; }

std::set<int> regions_of(const TetMesh& m) {
  std::set<int> r;
  for (std::size_t t = 0; t < m.tets.size(); ++t) r.insert(region_of(m.tet_region, t));
  for (std::size_t t = 0; t < m.triangles.size(); ++t) r.insert(region_of(m.triangle_region, t));
  return r;
}

void write_msh22(std::ostream& o, const TetMesh& m) {
  const std::set<int> regions = regions_of(m);
  o << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n" << 2 * regions.size() << '\n';
  for (int r : regions) o << "2 " << r << " \"boundary_" << r << "\"\n3 " << r << " \"region_" << r << "\"\n";
  o << "$EndPhysicalNames\n$Nodes\n" << m.points.size() << '\n';
  for (std::size_t i = 0; i < m.points.size(); ++i)
    o << i + 1 << ' ' << m.points[i][0] << ' ' << m.points[i][1] << ' ' << m.points[i][2] << '\n';
  o << "$EndNodes\n$Elements\n" << m.triangles.size() + m.tets.size() << '\n';
  std::size_t id = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const int r = region_of(m.triangle_region, t);
    o << ++id << " 2 2 " << r << ' ' << r;
    for (int v : m.triangles[t]) o << ' ' << v + 1;
    o << '\n';
  }
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const int r = region_of(m.tet_region, t);
    o << ++id << " 4 2 " << r << ' ' << r;
    for (int v : m.tets[t]) o << ' ' << v + 1;
    o << '\n';
  }
  o << "$EndElements\n";
}

// Gmsh 4.1: one surface entity (tag R) and one volume entity (tag R) per
// region, each in the physical group R of its dimension.
void write_msh41(std::ostream& o, const TetMesh& m) {
  const std::set<int> regions = regions_of(m);
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int i = 0; i < 3 && !m.points.empty(); ++i) {
    lo[std::size_t(i)] = hi[std::size_t(i)] = m.points[0][std::size_t(i)];
    for (const auto& p : m.points) {
      lo[std::size_t(i)] = std::min(lo[std::size_t(i)], p[std::size_t(i)]);
      hi[std::size_t(i)] = std::max(hi[std::size_t(i)], p[std::size_t(i)]);
    }
  }
  auto box = [&] { return std::to_string(lo[0]) + ' ' + std::to_string(lo[1]) + ' ' + std::to_string(lo[2]) + ' ' +
                          std::to_string(hi[0]) + ' ' + std::to_string(hi[1]) + ' ' + std::to_string(hi[2]); };
  o << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n" << 2 * regions.size() << '\n';
  for (int r : regions) o << "2 " << r << " \"boundary_" << r << "\"\n3 " << r << " \"region_" << r << "\"\n";
  o << "$EndPhysicalNames\n$Entities\n0 0 " << regions.size() << ' ' << regions.size() << '\n';
  for (int r : regions) o << r << ' ' << box() << " 1 " << r << " 0\n";
  for (int r : regions) o << r << ' ' << box() << " 1 " << r << " 1 " << r << '\n';
  o << "$EndEntities\n";
  const std::size_t n = m.points.size();
  o << "$Nodes\n1 " << n << " 1 " << n << "\n3 " << *regions.begin() << " 0 " << n << '\n';
  for (std::size_t i = 0; i < n; ++i) o << i + 1 << '\n';
  for (const auto& p : m.points) o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  o << "$EndNodes\n";
  std::map<std::pair<int, int>, std::vector<std::size_t>> blocks;  // (dim, region) -> elements
  for (std::size_t t = 0; t < m.triangles.size(); ++t) blocks[{2, region_of(m.triangle_region, t)}].push_back(t);
  for (std::size_t t = 0; t < m.tets.size(); ++t) blocks[{3, region_of(m.tet_region, t)}].push_back(t);
  const std::size_t total = m.triangles.size() + m.tets.size();
  o << "$Elements\n" << blocks.size() << ' ' << total << " 1 " << total << '\n';
  std::size_t id = 0;
  for (const auto& [key, elems] : blocks) {
    o << key.first << ' ' << key.second << ' ' << (key.first == 2 ? 2 : 4) << ' ' << elems.size() << '\n';
    for (std::size_t e : elems) {
      o << ++id;
      if (key.first == 2)
        for (int v : m.triangles[e]) o << ' ' << v + 1;
      else
        for (int v : m.tets[e]) o << ' ' << v + 1;
      o << '\n';
    }
  }
  o << "$EndElements\n";
}

void write_medit(std::ostream& o, const TetMesh& m) {
  o << "MeshVersionFormatted 2\nDimension 3\nVertices\n" << m.points.size() << '\n';
  for (const auto& p : m.points) o << p[0] << ' ' << p[1] << ' ' << p[2] << " 0\n";
  o << "Triangles\n" << m.triangles.size() << '\n';
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    o << m.triangles[t][0] + 1 << ' ' << m.triangles[t][1] + 1 << ' ' << m.triangles[t][2] + 1 << ' '
      << region_of(m.triangle_region, t) << '\n';
  o << "Tetrahedra\n" << m.tets.size() << '\n';
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    for (int v : m.tets[t]) o << v + 1 << ' ';
    o << region_of(m.tet_region, t) << '\n';
  }
  o << "End\n";
}

void write_vtu(std::ostream& o, const TetMesh& m) {
  const std::size_t cells = m.tets.size() + m.triangles.size();
  o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << m.points.size() << "\" NumberOfCells=\"" << cells << "\">\n"
       "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : m.points) o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  o << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : m.tets) o << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  for (const auto& t : m.triangles) o << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  o << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t off = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) o << (off += 4) << '\n';
  for (std::size_t t = 0; t < m.triangles.size(); ++t) o << (off += 3) << '\n';
  o << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < m.tets.size(); ++t) o << "10\n";
  for (std::size_t t = 0; t < m.triangles.size(); ++t) o << "5\n";
  o << "</DataArray>\n</Cells>\n<CellData Scalars=\"region\">\n<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < m.tets.size(); ++t) o << region_of(m.tet_region, t) << '\n';
  for (std::size_t t = 0; t < m.triangles.size(); ++t) o << region_of(m.triangle_region, t) << '\n';
  o << "</DataArray>\n<DataArray type=\"Int32\" Name=\"boundary\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < m.tets.size(); ++t) o << "0\n";
  for (std::size_t t = 0; t < m.triangles.size(); ++t) o << "1\n";
  o << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

// Abaqus: C3D4 elements in element sets REGION_R; the boundary triangles as
// an element-based surface BOUNDARY_R (each triangle a face S1-S4 of its
// tetrahedron), so that no shell element without a section appears.
void write_inp(std::ostream& o, const TetMesh& m) {
  o << "*HEADING\nimgmesh tetrahedral mesh\n*NODE\n";
  for (std::size_t i = 0; i < m.points.size(); ++i)
    o << i + 1 << ", " << m.points[i][0] << ", " << m.points[i][1] << ", " << m.points[i][2] << '\n';
  const std::set<int> regions = regions_of(m);
  // C3D4 faces: S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1.
  constexpr int face[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  // (region, sorted face of a tet) -> (element, face): a triangle of
  // region R is a face of R's tetrahedron, so the surface faces out of R.
  std::map<std::pair<int, std::array<int, 3>>, std::pair<std::size_t, int>> owner;
  for (int r : regions) {
    bool any = false;
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
      if (region_of(m.tet_region, t) != r) continue;
      if (!any) o << "*ELEMENT, TYPE=C3D4, ELSET=REGION_" << r << '\n';
      any = true;
      o << t + 1 << ", " << m.tets[t][0] + 1 << ", " << m.tets[t][1] + 1 << ", " << m.tets[t][2] + 1 << ", "
        << m.tets[t][3] + 1 << '\n';
    }
  }
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k{m.tets[t][std::size_t(face[f][0])], m.tets[t][std::size_t(face[f][1])], m.tets[t][std::size_t(face[f][2])]};
      std::sort(k.begin(), k.end());
      owner.emplace(std::make_pair(region_of(m.tet_region, t), k), std::make_pair(t, f));
    }
  for (int r : regions) {
    std::vector<std::size_t> sides[4];
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      if (region_of(m.triangle_region, t) != r) continue;
      std::array<int, 3> k = m.triangles[t];
      std::sort(k.begin(), k.end());
      const auto it = owner.find({r, k});
      if (it == owner.end()) throw Error("a boundary triangle of region " + std::to_string(r) + " is not a face of its tetrahedra");
      sides[it->second.second].push_back(it->second.first);
    }
    std::string lines;
    for (int f = 0; f < 4; ++f) {
      if (sides[f].empty()) continue;
      const std::string name = "BOUNDARY_" + std::to_string(r) + "_S" + std::to_string(f + 1);
      o << "*ELSET, ELSET=" << name << '\n';
      for (std::size_t i = 0; i < sides[f].size(); ++i)
        o << sides[f][i] + 1 << (i + 1 == sides[f].size() || i % 16 == 15 ? "\n" : ", ");
      lines += name + ", S" + std::to_string(f + 1) + "\n";
    }
    if (!lines.empty()) o << "*SURFACE, TYPE=ELEMENT, NAME=BOUNDARY_" << r << '\n' << lines;
  }
}

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

TetMesh read_msh(std::istream& in, const std::string& path) {
  Tokens t{in, path};
  if (t.next() != "$MeshFormat") throw Error("not a Gmsh .msh file", path);
  const std::string version = t.next();
  if (t.integer() != 0) throw Error("binary .msh is not supported (ASCII only)", path);
  t.next();
  if (t.next() != "$EndMeshFormat") throw Error("malformed $MeshFormat", path);
  if (version != "2.2" && version != "4.1") throw Error("unsupported .msh version " + version + " (2.2 or 4.1)", path);
  const bool v4 = version == "4.1";
  TetMesh m;
  NodeIds ids;
  std::map<std::pair<int, int>, int> physical;  // 4.1: (dim, entity) -> its first physical tag
  std::string s;
  while (t.read(s)) {
    if (s == "$Entities" && v4) {
      std::size_t n[4];
      for (auto& k : n) k = t.count("entity");
      for (int dim = 0; dim < 4; ++dim)
        for (std::size_t e = 0; e < n[dim]; ++e) {
          const int tag = int(t.integer());
          for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) t.real();
          const std::size_t np = t.count("physical tag");
          for (std::size_t k = 0; k < np; ++k) {
            const int p = int(t.integer());
            if (k == 0) physical[{dim, tag}] = p;
          }
          if (dim > 0) {
            const std::size_t nb = t.count("bounding entity");
            for (std::size_t k = 0; k < nb; ++k) t.integer();
          }
        }
      t.skip_to("$EndEntities");
    } else if (s == "$Nodes") {
      if (v4) {
        const std::size_t blocks = t.count("block");
        t.count("node");
        t.integer();
        t.integer();
        for (std::size_t b = 0; b < blocks; ++b) {
          t.integer();
          t.integer();
          if (t.integer() != 0) throw Error("parametric nodes are not supported", path);
          const std::size_t k = t.count("node");
          std::vector<long long> tags(k);
          for (auto& g : tags) g = t.integer();
          for (long long g : tags) {
            ids.id[g] = int(m.points.size());
            m.points.push_back({t.coordinate(), t.coordinate(), t.coordinate()});
          }
        }
      } else {
        const std::size_t k = t.count("node");
        for (std::size_t i = 0; i < k; ++i) {
          const long long g = t.integer();
          ids.id[g] = int(m.points.size());
          m.points.push_back({t.coordinate(), t.coordinate(), t.coordinate()});
        }
      }
      if (t.next() != "$EndNodes") throw Error("malformed $Nodes", path);
    } else if (s == "$Elements") {
      std::vector<int> v;
      if (v4) {
        const std::size_t blocks = t.count("block");
        t.count("element");
        t.integer();
        t.integer();
        for (std::size_t b = 0; b < blocks; ++b) {
          const int dim = int(t.integer()), entity = int(t.integer()), type = int(t.integer());
          const std::size_t k = t.count("element");
          const int nn = gmsh_nodes(type);
          if (nn < 0) throw Error("unsupported element type " + std::to_string(type), path);
          const auto p = physical.find({dim, entity});
          const int region = p != physical.end() ? p->second : entity;
          for (std::size_t e = 0; e < k; ++e) {
            t.integer();
            v.clear();
            for (int j = 0; j < nn; ++j) v.push_back(ids(t.integer(), path));
            add_element(m, type, v, region);
          }
        }
      } else {
        const std::size_t k = t.count("element");
        for (std::size_t e = 0; e < k; ++e) {
          t.integer();
          const int type = int(t.integer());
          const std::size_t ntags = t.count("tag");
          int region = 1;
          for (std::size_t j = 0; j < ntags; ++j) {
            const int g = int(t.integer());
            if (j == 0) region = g;
          }
          const int nn = gmsh_nodes(type);
          if (nn < 0) throw Error("unsupported element type " + std::to_string(type), path);
          v.clear();
          for (int j = 0; j < nn; ++j) v.push_back(ids(t.integer(), path));
          add_element(m, type, v, region);
        }
      }
      if (t.next() != "$EndElements") throw Error("malformed $Elements", path);
    } else if (!s.empty() && s[0] == '$' && s.rfind("$End", 0) != 0) {
      t.skip_to("$End" + s.substr(1));
    } else {
      throw Error("unexpected '" + s + "'", path);
    }
  }
  return m;
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

// The text of the DataArray named `name` (or the first in `section`), ASCII
// only, and the line of the file it starts on.
struct VtuArray {
  std::string text;
  int line = 1;
};
VtuArray vtu_array(const std::string& x, const std::string& section, const std::string& name, const std::string& path,
                   bool required = true) {
  std::size_t from = 0;
  if (!section.empty()) {
    from = x.find("<" + section);
    if (from == std::string::npos) {
      if (required) throw Error("no <" + section + "> in the .vtu file", path);
      return {};
    }
  }
  std::size_t at = from;
  for (;;) {
    at = x.find("<DataArray", at);
    if (at == std::string::npos) {
      if (required) throw Error("no DataArray " + name + " in the .vtu file", path);
      return {};
    }
    const std::size_t close = x.find('>', at);
    const std::string tag = x.substr(at, close - at);
    if (name.empty() || tag.find("Name=\"" + name + "\"") != std::string::npos) {
      if (tag.find("format=\"ascii\"") == std::string::npos) throw Error("only ASCII .vtu files are supported", path);
      const std::size_t end = x.find("</DataArray>", close);
      const auto begin = x.begin() + std::ptrdiff_t(close + 1);
      return {x.substr(close + 1, end - close - 1), 1 + int(std::count(x.begin(), begin, '\n'))};
    }
    at = close;
  }
}

TetMesh read_vtu(const std::string& path) {
  const std::string x = read_all(path);
  if (x.find("UnstructuredGrid") == std::string::npos) throw Error("not a VTK UnstructuredGrid .vtu file", path);
  TetMesh m;
  const VtuArray ap = vtu_array(x, "Points", "", path), ac = vtu_array(x, "", "connectivity", path),
                 ao = vtu_array(x, "", "offsets", path), at = vtu_array(x, "", "types", path),
                 ar = vtu_array(x, "CellData", "region", path, false);
  std::istringstream pts(ap.text), con(ac.text), off(ao.text), types(at.text), reg(ar.text);
  Tokens tp{pts, path, ap.line}, tc{con, path, ac.line}, to{off, path, ao.line}, tt{types, path, at.line},
      tr{reg, path, ar.line};
  std::vector<double> xyz;
  while (tp.more()) xyz.push_back(tp.coordinate());
  if (xyz.size() % 3) throw Error("the point count is not a multiple of 3", path);
  for (std::size_t i = 0; i < xyz.size(); i += 3) m.points.push_back({xyz[i], xyz[i + 1], xyz[i + 2]});
  const bool regions = !ar.text.empty();
  long long last = 0;
  std::vector<int> v;
  while (tt.more()) {
    const int type = int(tt.integer());
    const long long end = to.integer();
    if (end < last) to.fail("decreasing offsets");
    v.clear();
    for (long long k = last; k < end; ++k) {
      const long long id = tc.integer();
      if (id < 0 || id >= (long long)m.points.size()) tc.fail("cell refers to unknown point " + std::to_string(id));
      v.push_back(int(id));
    }
    last = end;
    const int region = regions ? int(tr.integer()) : 1;
    if (type == 10 && v.size() == 4) add_element(m, 4, v, region);
    else if (type == 5 && v.size() == 3) add_element(m, 2, v, region);
  }
  return m;
}

} // namespace

void write_tet_mesh(const std::string& path, const TetMesh& mesh, const TetWriteOptions& options) {
  const std::string ext = extension_of(path);
  if (!is_tet_mesh_path(path)) throw UsageError(std::string("tetrahedral mesh format is chosen by extension: ") + kTetMeshExtensions, path);
  if (ext == ".msh" && options.msh_version != "4.1" && options.msh_version != "2.2")
    throw UsageError("--msh-version must be 4.1 or 2.2");
  AtomicOutput out(path);
  std::ostream& o = out.stream();
  o.precision(17);
  if (ext == ".msh") (options.msh_version == "2.2" ? write_msh22 : write_msh41)(o, mesh);
  else if (ext == ".mesh") write_medit(o, mesh);
  else if (ext == ".vtu") write_vtu(o, mesh);
  else write_inp(o, mesh);
  out.commit();
}

TetMesh read_tet_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  TetMesh m;
  if (ext == ".vtu") m = read_vtu(path);
  else {
    std::ifstream in(path);
    if (!in) throw Error("cannot open", path);
    if (ext == ".msh") m = read_msh(in, path);
    else if (ext == ".mesh") m = read_medit(in, path);
    else throw Error("reading tetrahedral meshes: .msh, .mesh or .vtu", path);
  }
  if (m.tets.empty()) throw Error("no tetrahedron", path);
  check_extent(m.points, path);
  return m;
}

} // namespace imgmesh
