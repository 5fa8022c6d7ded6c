// Writing tetrahedral meshes (reading: volume_read.cpp).
#include "mesh/volume_io.hpp"

#include "mesh/binary_formats.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

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

// The surface entities: one per region, or, with triangle pairs, one per
// (region, pair); per triangle its entity's index.
struct SurfaceEntities {
  std::vector<std::pair<int, std::array<int, 2>>> of;  // (region, pair); pair {0, 0} without pairs
  std::vector<std::size_t> of_triangle;
  bool pairs = false;
  int first_interface_tag = 0;  // pairs: entity k's own physical group is first_interface_tag + k
};
SurfaceEntities surface_entities(const TetMesh& m, const std::set<int>& regions) {
  SurfaceEntities e;
  e.pairs = !m.triangle_pair.empty();
  std::map<std::pair<int, std::array<int, 2>>, std::size_t> index;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    index.emplace(std::make_pair(region_of(m.triangle_region, t),
                                 e.pairs && t < m.triangle_pair.size() ? m.triangle_pair[t] : std::array<int, 2>{0, 0}),
                  0);
  for (auto& [key, k] : index) {
    k = e.of.size();
    e.of.push_back(key);
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    e.of_triangle.push_back(index.at({region_of(m.triangle_region, t),
                                      e.pairs && t < m.triangle_pair.size() ? m.triangle_pair[t] : std::array<int, 2>{0, 0}}));
  e.first_interface_tag = (regions.empty() ? 0 : std::max(0, *regions.rbegin())) + 1;
  return e;
}

// Region R's groups: "boundary_R" and "region_R", or "NAME boundary" and
// "NAME" for a named region; with pairs (4.1), each interface's "a|b".
void physical_names(std::ostream& o, const TetMesh& m, const std::set<int>& regions, const SurfaceEntities* e) {
  o << "$PhysicalNames\n" << 2 * regions.size() + (e && e->pairs ? e->of.size() : 0) << '\n';
  for (int r : regions) {
    const auto name = m.region_names.find(r);
    if (name == m.region_names.end() || name->second.empty())
      o << "2 " << r << " \"boundary_" << r << "\"\n3 " << r << " \"region_" << r << "\"\n";
    else
      o << "2 " << r << " \"" << mesh_detail::msh_name(name->second + " boundary") << "\"\n3 " << r << " \""
        << mesh_detail::msh_name(name->second) << "\"\n";
  }
  auto named = [&](int r) {
    const auto name = m.region_names.find(r);
    return name == m.region_names.end() || name->second.empty() ? std::to_string(r) : name->second;
  };
  if (e && e->pairs)
    for (std::size_t k = 0; k < e->of.size(); ++k) {
      const auto& p = e->of[k].second;
      o << "2 " << e->first_interface_tag + int(k) << " \""
        << mesh_detail::msh_name(p == std::array<int, 2>{0, 0} ? "box" : named(p[0]) + "|" + named(p[1])) << "\"\n";
    }
  o << "$EndPhysicalNames\n";
}

// An Abaqus name of a named region: letters, digits and underscores,
// starting with a letter, at most 80 characters (the others as '_').
std::string abaqus_name(const std::string& name) {
  std::string s;
  for (const char c : name) s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) s = "R_" + s;
  return s.substr(0, 80);
}

void write_msh22(std::ostream& o, const TetMesh& m, bool binary) {
  mesh_detail::MshWriter w(o, binary);
  w.format("2.2");
  const std::set<int> regions = regions_of(m);
  const SurfaceEntities entities = surface_entities(m, regions);
  physical_names(o, m, regions, nullptr);
  o << "$Nodes\n" << m.points.size() << '\n';
  for (std::size_t i = 0; i < m.points.size(); ++i) w.i((long long)(i + 1)).d(m.points[i][0]).d(m.points[i][1]).d(m.points[i][2]).eol();
  w.end("Nodes");
  o << "$Elements\n" << m.triangles.size() + m.tets.size() << '\n';
  std::size_t id = 0;
  w.block22(2, m.triangles.size(), 2);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const int r = region_of(m.triangle_region, t);
    // With pairs, the elementary tag tells the interfaces apart (2.2 gives
    // an element one physical group: its region's boundary).
    const int elementary = entities.pairs ? int(entities.of_triangle[t]) + 1 : r;
    w.element22(++id, 2, {r, elementary},
                std::array<int, 3>{m.triangles[t][0] + 1, m.triangles[t][1] + 1, m.triangles[t][2] + 1});
  }
  w.block22(4, m.tets.size(), 2);
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const int r = region_of(m.tet_region, t);
    const auto& v = m.tets[t];
    w.element22(++id, 4, {r, r}, std::array<int, 4>{v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1});
  }
  w.end("Elements");
}

// Gmsh 4.1: one surface entity (tag R) and one volume entity (tag R) per
// region, each in the physical group R of its dimension; with pairs, a
// surface entity per (region, pair), in R's group and its own.
// background: the tag region 0 is written as (gmsh_background), 0 if none;
// the pairs still name region 0 as 0.
void write_msh41(std::ostream& o, const TetMesh& m, bool binary, int background) {
  const std::set<int> regions = regions_of(m);
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int i = 0; i < 3 && !m.points.empty(); ++i) {
    lo[std::size_t(i)] = hi[std::size_t(i)] = m.points[0][std::size_t(i)];
    for (const auto& p : m.points) {
      lo[std::size_t(i)] = std::min(lo[std::size_t(i)], p[std::size_t(i)]);
      hi[std::size_t(i)] = std::max(hi[std::size_t(i)], p[std::size_t(i)]);
    }
  }
  mesh_detail::MshWriter w(o, binary);
  auto box = [&] {
    for (const auto* b : {&lo, &hi})
      for (double x : *b) w.d(x, std::to_string(x));
  };
  w.format("4.1");
  const SurfaceEntities entities = surface_entities(m, regions);
  physical_names(o, m, regions, &entities);
  o << "$Entities\n";
  w.z(0).z(0).z(entities.pairs ? entities.of.size() : regions.size()).z(regions.size()).eol();
  if (entities.pairs) {
    for (std::size_t k = 0; k < entities.of.size(); ++k) {
      w.i(int(k) + 1);
      box();
      w.z(2).i(entities.of[k].first).i(entities.first_interface_tag + int(k)).z(0).eol();
    }
  } else {
    for (int r : regions) {
      w.i(r);
      box();
      w.z(1).i(r).z(0).eol();
    }
  }
  for (int r : regions) {
    w.i(r);
    box();
    if (!entities.pairs) {
      w.z(1).i(r).z(1).i(r).eol();
      continue;
    }
    // Its bounding surfaces: the pairs' entities on its side (negative
    // where it is the front).
    std::vector<int> bounding;
    for (std::size_t k = 0; k < entities.of.size(); ++k) {
      const auto& pair = entities.of[k].second;
      if (entities.of[k].first == r) bounding.push_back(int(k) + 1);  // its region (the box's: the background's)
      else if ((pair[1] == 0 && background ? background : pair[1]) == r) bounding.push_back(-int(k) - 1);
    }
    w.z(1).i(r).z(bounding.size());
    for (const int b : bounding) w.i(b);
    w.eol();
  }
  w.end("Entities");
  const std::size_t n = m.points.size();
  o << "$Nodes\n";
  w.z(1).z(n).z(1).z(n).eol();
  w.i(3).i(*regions.begin()).i(0).z(n).eol();
  for (std::size_t i = 0; i < n; ++i) w.z(i + 1).eol();
  for (const auto& p : m.points) w.d(p[0]).d(p[1]).d(p[2]).eol();
  w.end("Nodes");
  std::map<std::pair<int, int>, std::vector<std::size_t>> blocks;  // (dim, entity) -> elements
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    blocks[{2, entities.pairs ? int(entities.of_triangle[t]) + 1 : region_of(m.triangle_region, t)}].push_back(t);
  for (std::size_t t = 0; t < m.tets.size(); ++t) blocks[{3, region_of(m.tet_region, t)}].push_back(t);
  const std::size_t total = m.triangles.size() + m.tets.size();
  o << "$Elements\n";
  w.z(blocks.size()).z(total).z(1).z(total).eol();
  std::size_t id = 0;
  for (const auto& [key, elems] : blocks) {
    w.i(key.first).i(key.second).i(key.first == 2 ? 2 : 4).z(elems.size()).eol();
    for (std::size_t e : elems) {
      w.z(++id);
      if (key.first == 2)
        for (int v : m.triangles[e]) w.z(std::size_t(v + 1));
      else
        for (int v : m.tets[e]) w.z(std::size_t(v + 1));
      w.eol();
    }
  }
  w.end("Elements");
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

// Tetrahedra first, then the boundary triangles, as cells.
void write_vtu(std::ostream& o, const TetMesh& m, bool binary, const std::string& name) {
  const std::size_t cells = m.tets.size() + m.triangles.size();
  mesh_detail::VtkXmlArrays arrays(o, binary, "", "");
  o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" " << arrays.file_attributes() << ">\n"
       "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << m.points.size() << "\" NumberOfCells=\"" << cells << "\">\n"
       "<Points>\n";
  std::vector<double> xyz;
  for (const auto& p : m.points) xyz.insert(xyz.end(), p.begin(), p.end());
  arrays.array("Float64", nullptr, 3, xyz);
  o << "</Points>\n<Cells>\n";
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::size_t> rows;
  std::vector<std::uint8_t> types;
  std::vector<std::int32_t> region, boundary;
  auto cell = [&](const auto& v, std::uint8_t type, int r, int on_boundary) {
    connectivity.insert(connectivity.end(), v.begin(), v.end());
    rows.push_back(v.size());
    offsets.push_back(std::int64_t(connectivity.size()));
    types.push_back(type);
    region.push_back(r);
    boundary.push_back(on_boundary);
  };
  for (std::size_t t = 0; t < m.tets.size(); ++t) cell(m.tets[t], 10, region_of(m.tet_region, t), 0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) cell(m.triangles[t], 5, region_of(m.triangle_region, t), 1);
  arrays.array("Int64", "connectivity", 1, connectivity, rows);
  arrays.array("Int64", "offsets", 1, offsets);
  arrays.array("UInt8", "types", 1, types);
  o << "</Cells>\n<CellData Scalars=\"" << name << "\">\n";
  arrays.array("Int32", name.c_str(), 1, region);
  arrays.array("Int32", "boundary", 1, boundary);
  o << "</CellData>\n</Piece>\n</UnstructuredGrid>\n";
  arrays.appended_data();
  o << "</VTKFile>\n";
}

// Abaqus: C3D4 elements in element sets REGION_R; the boundary triangles as
// an element-based surface BOUNDARY_R (each triangle a face S1-S4 of its
// tetrahedron), so that no shell element without a section appears.
void write_inp(std::ostream& o, const TetMesh& m) {
  o << "*HEADING\nimgmesh tetrahedral mesh\n*NODE\n";
  for (std::size_t i = 0; i < m.points.size(); ++i)
    o << i + 1 << ", " << m.points[i][0] << ", " << m.points[i][1] << ", " << m.points[i][2] << '\n';
  const std::set<int> regions = regions_of(m);
  std::set<std::string> names;  // the named regions' set names, each once
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
  // An element-based surface NAME of the triangles `tris` of region r: an
  // element set NAME_Sf per face f of r's tetrahedra that they are.
  auto surface = [&](const std::string& name, const std::vector<std::size_t>& tris, int r) {
    std::vector<std::size_t> sides[4];
    for (const std::size_t t : tris) {
      std::array<int, 3> k = m.triangles[t];
      std::sort(k.begin(), k.end());
      const auto it = owner.find({r, k});
      if (it == owner.end()) throw Error("a boundary triangle of region " + std::to_string(r) + " is not a face of its tetrahedra");
      sides[it->second.second].push_back(it->second.first);
    }
    std::string lines;
    for (int f = 0; f < 4; ++f) {
      if (sides[f].empty()) continue;
      const std::string set = name + "_S" + std::to_string(f + 1);
      o << "*ELSET, ELSET=" << set << '\n';
      for (std::size_t i = 0; i < sides[f].size(); ++i)
        o << sides[f][i] + 1 << (i + 1 == sides[f].size() || i % 16 == 15 ? "\n" : ", ");
      lines += set + ", S" + std::to_string(f + 1) + "\n";
    }
    if (!lines.empty()) o << "*SURFACE, TYPE=ELEMENT, NAME=" << name << '\n' << lines;
    return lines;
  };
  for (int r : regions) {
    std::vector<std::size_t> tris;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      if (region_of(m.triangle_region, t) == r) tris.push_back(t);
    const std::string lines = surface("BOUNDARY_" + std::to_string(r), tris, r);
    // A named region: its element set and surface under its name too.
    const auto named = m.region_names.find(r);
    if (named == m.region_names.end() || named->second.empty()) continue;
    std::string name = abaqus_name(named->second);
    if (!names.insert(name).second) name += "_" + std::to_string(r);
    o << "*ELSET, ELSET=" << name << "\nREGION_" << r << '\n';
    if (!lines.empty()) o << "*SURFACE, TYPE=ELEMENT, NAME=" << name << "_BOUNDARY\n" << lines;
  }
  // Pairs: a surface per interface, INTERFACE_a_b (its region a first).
  const SurfaceEntities e = surface_entities(m, regions);
  if (!e.pairs) return;
  std::vector<std::vector<std::size_t>> of(e.of.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) of[e.of_triangle[t]].push_back(t);
  for (std::size_t k = 0; k < e.of.size(); ++k) {
    const auto& [r, pair] = e.of[k];
    surface(pair == std::array<int, 2>{0, 0} ? "BOX" : "INTERFACE_" + std::to_string(pair[0]) + "_" + std::to_string(pair[1]), of[k], r);
  }
}

// Region 0 as Gmsh's tag max + 1, "background" (a copy), when there is
// one; tag: that tag.
std::optional<TetMesh> gmsh_background(const TetMesh& m, int& tag) {
  const std::set<int> regions = regions_of(m);
  if (!regions.count(0)) return std::nullopt;
  TetMesh t = m;
  tag = *regions.rbegin() + 1;
  for (int& r : t.tet_region) r = r == 0 ? tag : r;
  for (int& r : t.triangle_region) r = r == 0 ? tag : r;
  const auto name = m.region_names.find(0);
  t.region_names[tag] = name == m.region_names.end() || name->second.empty() ? kBackgroundName : name->second;
  t.region_names.erase(0);
  return t;
}

} // namespace

void write_tet_mesh(const std::string& path, const TetMesh& mesh, const TetWriteOptions& options) {
  const std::string ext = extension_of(path);
  if (!is_tet_mesh_path(path)) throw UsageError(std::string("tetrahedral mesh format is chosen by extension: ") + kTetMeshExtensions, path);
  if (ext == ".msh" && options.msh_version != "4.1" && options.msh_version != "2.2")
    throw UsageError("--msh-version must be 4.1 or 2.2");
  AtomicOutput out(path, (ext == ".vtu" && !options.ascii) || (ext == ".msh" && options.msh_binary));
  std::ostream& o = out.stream();
  o.precision(17);
  if (ext == ".msh") {
    int background = 0;
    const std::optional<TetMesh> tagged = gmsh_background(mesh, background);
    if (options.msh_version == "2.2") write_msh22(o, tagged ? *tagged : mesh, options.msh_binary);
    else write_msh41(o, tagged ? *tagged : mesh, options.msh_binary, background);
    // Region 0's tag (0: none) in a section Gmsh and meshio skip, where the
    // name "background" alone would mislead our reader: region 0 present
    // (named otherwise, or not), or another region so named.
    if (tagged || std::any_of(mesh.region_names.begin(), mesh.region_names.end(),
                              [](const auto& n) { return n.second == kBackgroundName; }))
      o << "$BackgroundRegion\n" << background << "\n$EndBackgroundRegion\n";
  }
  else if (ext == ".mesh") write_medit(o, mesh);
  else if (ext == ".vtu") write_vtu(o, mesh, !options.ascii, options.vtu_cell_data);
  else write_inp(o, mesh);
  out.commit();
}

} // namespace imgmesh
