// Reading Abaqus .inp tetrahedral meshes: what write_inp writes (C3D4
// elements in element sets REGION_R, the boundary as element-face surfaces
// BOUNDARY_R) and what Gmsh writes for a mesh with physical volumes
// (element sets PhysicalVolumeR, named groups under their names, triangles
// as CPS3 elements). A tetrahedron's region is the R of the one region set
// (REGION_R or PhysicalVolumeR) that holds it: a name alone carries no
// label, so a tetrahedron in no such set is an error, not a guess.
// Keywords, parameters and names are case-insensitive, as in Abaqus.
#include "mesh/mesh_read_detail.hpp"

#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"

#include <cctype>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <unordered_map>
#include <vector>

namespace imgmesh::mesh_detail {
namespace {

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::string upper(std::string s) {
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// A line's comma-separated fields, trimmed; a trailing comma ends the line
// (Gmsh writes one after each run of ids).
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> f;
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = line.find(',', at);
    f.push_back(trim(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at)));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  if (f.size() > 1 && f.back().empty()) f.pop_back();
  return f;
}

// The R of a region set's name (upper case): REGION_R or PHYSICALVOLUMER, R >= 0.
bool region_set(const std::string& name, int& r, const char* const (&prefixes)[2]) {
  for (const char* p : prefixes) {
    const std::string prefix(p);
    long long v;
    if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
        std::isdigit(static_cast<unsigned char>(name[prefix.size()])) && parse_integer(name.substr(prefix.size()), v) &&
        v <= 2147483647) {
      r = int(v);
      return true;
    }
  }
  return false;
}
constexpr const char* kVolumeSets[2] = {"REGION_", "PHYSICALVOLUME"};
constexpr const char* kSurfaceSets[2] = {"BOUNDARY_", "PHYSICALSURFACE"};

enum class Kind { Tet, Triangle, Skipped };

// The element types read: linear tetrahedra, 3-node triangles (Gmsh's
// CPS3, shells, membranes), and lines and points, left out as the .msh
// reader leaves them out.
bool element_kind(const std::string& type, Kind& k) {
  static const std::map<std::string, Kind> kinds = {
      {"C3D4", Kind::Tet},       {"C3D4H", Kind::Tet},      {"DC3D4", Kind::Tet},      {"CPS3", Kind::Triangle},
      {"CPE3", Kind::Triangle},  {"S3", Kind::Triangle},    {"S3R", Kind::Triangle},   {"STRI3", Kind::Triangle},
      {"M3D3", Kind::Triangle},  {"SFM3D3", Kind::Triangle}, {"R3D3", Kind::Triangle}, {"T2D2", Kind::Skipped},
      {"T3D2", Kind::Skipped},   {"B21", Kind::Skipped},    {"B31", Kind::Skipped},    {"MASS", Kind::Skipped}};
  const auto it = kinds.find(type);
  if (it == kinds.end()) return false;
  k = it->second;
  return true;
}

struct Element {
  Kind kind;
  std::vector<int> nodes;  // 0-based
};

// A set's members as written: element ids and names of other sets.
struct SetItems {
  std::vector<long long> ids;
  std::vector<std::string> sets;
};

class InpReader {
public:
  InpReader(std::istream& in, const std::string& path) : in_(in), path_(path) {}

  TetMesh read() {
    std::string raw;
    while (std::getline(in_, raw)) {
      ++line_;
      if (!raw.empty() && raw.back() == '\r') raw.pop_back();
      const std::string l = trim(raw);
      if (l.empty() || l.compare(0, 2, "**") == 0) continue;
      if (l[0] == '*') keyword(l);
      else data(fields(l));
    }
    return mesh();
  }

private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("line " + std::to_string(line_) + ": " + what, path_);
  }
  long long integer(const std::string& s, const char* what) const {
    long long v;
    if (!parse_integer(s, v)) fail(std::string("expected ") + what + ", found '" + s.substr(0, 40) + "'");
    return v;
  }

  // "*KEYWORD, NAME=value, FLAG": the keyword and its parameters, upper case.
  void keyword(const std::string& l) {
    const std::vector<std::string> f = fields(l.substr(1));
    keyword_ = upper(f[0]);
    params_.clear();
    for (std::size_t k = 1; k < f.size(); ++k) {
      const std::size_t eq = f[k].find('=');
      params_[upper(trim(f[k].substr(0, eq)))] = eq == std::string::npos ? "" : upper(trim(f[k].substr(eq + 1)));
    }
    if (keyword_ == "INCLUDE") fail("*INCLUDE is not supported (one file holds the mesh)");
    if (keyword_ == "ELEMENT") {
      const auto type = params_.find("TYPE");
      if (type == params_.end() || type->second.empty()) fail("*ELEMENT without TYPE");
      if (!element_kind(type->second, kind_))
        fail("unsupported element type " + type->second + " (C3D4 tetrahedra, 3-node triangles)");
    }
    if ((keyword_ == "ELEMENT" || keyword_ == "ELSET") && params_.count("ELSET")) {
      set_ = params_["ELSET"];
      if (set_.empty()) fail("an empty element set name");
      sets_[set_];
    } else {
      set_.clear();
    }
    if (keyword_ == "ELSET" && set_.empty()) fail("*ELSET without ELSET=");
    if (keyword_ == "SURFACE") {
      surface_ = params_.count("TYPE") && params_["TYPE"] != "ELEMENT" ? "" : params_["NAME"];
      if (params_.count("NAME") == 0 || params_["NAME"].empty()) fail("*SURFACE without NAME=");
    }
  }

  void data(const std::vector<std::string>& f) {
    if (keyword_.empty()) fail("data before any keyword");
    if (keyword_ == "NODE") node(f);
    else if (keyword_ == "ELEMENT") element(f);
    else if (keyword_ == "ELSET") elset(f);
    else if (keyword_ == "SURFACE" && !surface_.empty()) {
      if (f.size() != 2) fail("an element surface line is 'element or set, face'");
      surfaces_[surface_].push_back({upper(f[0]), upper(f[1])});
    }
    // The rest (*HEADING's text, *NSET, materials, steps): not the mesh's.
  }

  void node(const std::vector<std::string>& f) {
    if (f.size() != 4) fail("a node is 'id, x, y, z'");
    const long long id = integer(f[0], "a node id");
    std::array<double, 3> p;
    for (std::size_t k = 0; k < 3; ++k)
      if (!parse_coordinate(f[k + 1], p[k])) fail(coordinate_error(f[k + 1]));
    if (!node_.emplace(id, int(points_.size())).second) fail("node " + std::to_string(id) + " defined twice");
    points_.push_back(p);
  }

  void element(const std::vector<std::string>& f) {
    const long long id = integer(f[0], "an element id");
    if (element_.count(id)) fail("element " + std::to_string(id) + " defined twice");
    Element e{kind_, {}};
    if (kind_ != Kind::Skipped) {
      const std::size_t n = kind_ == Kind::Tet ? 4 : 3;
      if (f.size() != n + 1) fail("element " + std::to_string(id) + ": " + std::to_string(n) + " nodes expected");
      for (std::size_t k = 1; k <= n; ++k) {
        const long long v = integer(f[k], "a node id");
        const auto it = node_.find(v);
        if (it == node_.end()) fail("element " + std::to_string(id) + " refers to unknown node " + std::to_string(v));
        e.nodes.push_back(it->second);
      }
    }
    element_.emplace(id, std::move(e));
    order_.push_back(id);
    if (!set_.empty()) sets_[set_].ids.push_back(id);
  }

  void elset(const std::vector<std::string>& f) {
    SetItems& s = sets_[set_];
    if (params_.count("GENERATE")) {
      if (f.size() < 2 || f.size() > 3) fail("a GENERATE line is 'first, last[, step]'");
      const long long a = integer(f[0], "an element id"), b = integer(f[1], "an element id"),
                      step = f.size() == 3 ? integer(f[2], "a step") : 1;
      if (step < 1 || b < a || (b - a) / step > 200000000) fail("a bad GENERATE range");
      for (long long v = a; v <= b; v += step) s.ids.push_back(v);
      return;
    }
    for (const std::string& x : f) {
      if (x.empty()) fail("an empty item in an element set");
      long long v;
      if (parse_integer(x, v)) s.ids.push_back(v);
      else s.sets.push_back(upper(x));
    }
  }

  // A set's element ids, its named sets expanded (each set once).
  std::vector<long long> members(const std::string& name) const {
    std::vector<long long> out;
    std::set<std::string> seen;
    std::function<void(const std::string&)> add = [&](const std::string& n) {
      if (!seen.insert(n).second) return;
      const auto it = sets_.find(n);
      if (it == sets_.end()) throw Error("element set " + n + " is not defined", path_);
      for (const long long id : it->second.ids) {
        if (!element_.count(id)) throw Error("element set " + n + " holds unknown element " + std::to_string(id), path_);
        out.push_back(id);
      }
      for (const std::string& s : it->second.sets) add(s);
    };
    add(name);
    return out;
  }

  TetMesh mesh() const {
    TetMesh m;
    m.points = points_;
    // Each element's region from the region sets (triangles: the surface sets).
    std::unordered_map<long long, int> region;
    for (const auto& [name, items] : sets_) {
      int r;
      const bool volume = region_set(name, r, kVolumeSets);
      if (!volume && !region_set(name, r, kSurfaceSets)) continue;
      for (const long long id : members(name)) {
        if ((element_.at(id).kind == Kind::Tet) != volume) continue;
        const auto [it, inserted] = region.emplace(id, r);
        if (!inserted && it->second != r)
          throw Error("element " + std::to_string(id) + " is in the sets of regions " + std::to_string(it->second) +
                          " and " + std::to_string(r),
                      path_);
      }
    }
    std::unordered_map<long long, std::size_t> tet_of;  // element id -> its index in m.tets
    for (const long long id : order_) {
      const Element& e = element_.at(id);
      const auto r = region.find(id);
      if (e.kind == Kind::Tet) {
        if (r == region.end())
          throw Error("tetrahedron " + std::to_string(id) + " is in no region set (REGION_R or PhysicalVolumeR; a name alone carries no label)",
                      path_);
        tet_of[id] = m.tets.size();
        m.tets.push_back({e.nodes[0], e.nodes[1], e.nodes[2], e.nodes[3]});
        m.tet_region.push_back(r->second);
      } else if (e.kind == Kind::Triangle) {
        m.triangles.push_back({e.nodes[0], e.nodes[1], e.nodes[2]});
        m.triangle_region.push_back(r == region.end() ? 0 : r->second);
      }
    }
    // The surfaces BOUNDARY_R: each face of a tetrahedron, turned to face
    // out of it (C3D4's faces S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1
    // are seen from outside clockwise).
    constexpr int face[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
    for (const auto& [name, lines] : surfaces_) {
      int r;
      if (!region_set(name, r, kSurfaceSets)) continue;
      for (const auto& [what, side] : lines) {
        int f = -1;
        if (side.size() == 2 && side[0] == 'S' && side[1] >= '1' && side[1] <= '4') f = side[1] - '1';
        if (f < 0) throw Error("surface " + name + ": face " + side + " is not S1-S4 of a tetrahedron", path_);
        long long id;
        const std::vector<long long> ids = parse_integer(what, id) ? std::vector<long long>{id} : members(what);
        for (const long long e : ids) {
          const auto t = tet_of.find(e);
          if (t == tet_of.end()) throw Error("surface " + name + ": element " + std::to_string(e) + " is not a tetrahedron", path_);
          const auto& v = m.tets[t->second];
          m.triangles.push_back({v[std::size_t(face[f][0])], v[std::size_t(face[f][2])], v[std::size_t(face[f][1])]});
          m.triangle_region.push_back(r);
        }
      }
    }
    return m;
  }

  std::istream& in_;
  const std::string& path_;
  int line_ = 0;
  std::string keyword_, set_, surface_;
  std::map<std::string, std::string> params_;
  Kind kind_ = Kind::Skipped;
  std::vector<std::array<double, 3>> points_;
  std::unordered_map<long long, int> node_;  // node id -> index
  std::unordered_map<long long, Element> element_;
  std::vector<long long> order_;  // element ids as they come
  std::map<std::string, SetItems> sets_;
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> surfaces_;  // name -> (element or set, face)
};

} // namespace

TetMesh read_inp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open", path);
  return InpReader(in, path).read();
}

} // namespace imgmesh::mesh_detail
