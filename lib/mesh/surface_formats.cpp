// Writers of the formats with per-face data (surface_formats.hpp). Text
// formats print doubles with 17 digits, so that world coordinates survive.
#include "mesh/surface_formats.hpp"

#include "mesh/binary_formats.hpp"
#include "util/binary_io.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <set>

namespace imgmesh {
namespace {

bool has_normals(const SurfaceMesh& m) { return !m.normals.empty() && m.normals.size() == m.points.size(); }
bool has_labels(const SurfaceMesh& m) { return !m.labels.empty() && m.labels.size() == m.triangles.size(); }
bool has_pairs(const SurfaceMesh& m) { return !m.interfaces.empty() && m.interfaces.size() == m.triangles.size(); }

int find(std::vector<int>& parent, int x) {
  while (parent[std::size_t(x)] != x) x = parent[std::size_t(x)] = parent[std::size_t(parent[std::size_t(x)])];
  return x;
}

// The coordinates of `items` one after the other, as T.
template <class T, class U, std::size_t N> std::vector<T> flat(const std::vector<std::array<U, N>>& items) {
  std::vector<T> out;
  out.reserve(items.size() * N);
  for (const auto& item : items)
    for (U x : item) out.push_back(T(x));
  return out;
}

// Value i of `items` laid one after the other (flat's, without the copy).
template <class U, std::size_t N> auto flat_value(const std::vector<std::array<U, N>>& items) {
  return [&items](std::size_t i) { return items[i / N][i % N]; };
}

// The names of the labels the faces carry (empty names left out), by label.
std::map<int, std::string> names_used(const SurfaceMesh& m) {
  std::map<int, std::string> out;
  if ((!has_labels(m) && !has_pairs(m)) || m.label_names.empty()) return out;
  std::set<int> used;
  if (has_labels(m)) used.insert(m.labels.begin(), m.labels.end());
  if (has_pairs(m))
    for (const auto& p : m.interfaces) used.insert(p.begin(), p.end());
  for (const auto& [label, name] : m.label_names)
    if (used.count(label) && !name.empty()) out.emplace(label, name);
  return out;
}

// A name on one header line: control characters as spaces.
std::string one_line(std::string name) {
  for (char& c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return name;
}


// Legacy VTK's string values, one a line, with VTK's own escapes
// (vtkDataWriter::EncodeString): %XX for a space, '"', '%' and every byte
// outside 33..126.
std::string vtk_legacy_string(const std::string& name) {
  std::string out;
  for (unsigned char c : name) {
    if (c < 33 || c > 126 || c == '"' || c == '%') {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    } else {
      out += char(c);
    }
  }
  return out;
}

// The labels' values and names as VTK XML field data; an ASCII String
// array holds each string's bytes as numbers (signed char, as VTK writes
// them) ended by 0.
void vtp_field_data(std::ostream& out, const std::map<int, std::string>& names) {
  if (names.empty()) return;
  out << "    <FieldData>\n      <DataArray type=\"Int32\" Name=\"label_values\" NumberOfTuples=\"" << names.size()
      << "\" format=\"ascii\">\n        ";
  for (const auto& [label, name] : names) out << label << ' ';
  out << "\n      </DataArray>\n      <DataArray type=\"String\" Name=\"label_names\" NumberOfTuples=\""
      << names.size() << "\" format=\"ascii\">\n";
  for (const auto& [label, name] : names) {
    out << "        ";
    for (char c : name) out << short(static_cast<signed char>(c)) << ' ';
    out << "0\n";
  }
  out << "      </DataArray>\n    </FieldData>\n";
}

} // namespace

std::vector<int> face_components(const SurfaceMesh& m) {
  std::vector<int> parent(m.points.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& f : m.triangles) {
    const int a = find(parent, f[0]);
    for (int k = 1; k < 3; ++k) parent[std::size_t(find(parent, f[std::size_t(k)]))] = a;
  }
  // Roots in order of first face, then renumbered by decreasing face count.
  std::map<int, int> root_index;
  std::vector<std::size_t> count;
  std::vector<int> raw(m.triangles.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const int r = find(parent, m.triangles[i][0]);
    auto it = root_index.emplace(r, int(count.size())).first;
    if (std::size_t(it->second) == count.size()) count.push_back(0);
    ++count[std::size_t(it->second)];
    raw[i] = it->second;
  }
  std::vector<int> order(count.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return count[std::size_t(a)] > count[std::size_t(b)]; });
  std::vector<int> rank(count.size());
  for (std::size_t i = 0; i < order.size(); ++i) rank[std::size_t(order[i])] = int(i);
  for (int& c : raw) c = rank[std::size_t(c)];
  return raw;
}

void write_vtp(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component, bool binary) {
  out.precision(17);
  mesh_detail::VtkXmlArrays arrays(out, binary, "        ", "         ");
  out << "<?xml version=\"1.0\"?>\n<!-- imgmesh surface, world coordinates SPACE=LPS (as ITK) -->\n"
      << "<VTKFile type=\"PolyData\" " << arrays.file_attributes() << ">\n  <PolyData>\n";
  vtp_field_data(out, names_used(m));
  out << "    <Piece NumberOfPoints=\"" << m.points.size() << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
      << "NumberOfStrips=\"0\" NumberOfPolys=\"" << m.triangles.size() << "\">\n";
  // Every array straight from the mesh's vectors (flat_value): in binary
  // only its compressed blocks are held.
  if (has_normals(m)) {
    out << "      <PointData Normals=\"Normals\">\n";
    arrays.array<double>("Float64", "Normals", 3, 3 * m.normals.size(), flat_value(m.normals));
    out << "      </PointData>\n";
  }
  out << "      <CellData Scalars=\"" << (has_pairs(m) ? "labels" : has_labels(m) ? "label" : "component") << "\">\n";
  arrays.array("Int32", "component", 1, component);
  if (has_labels(m)) arrays.array("Int32", "label", 1, m.labels);
  if (has_pairs(m)) arrays.array<std::int32_t>("Int32", "labels", 2, 2 * m.interfaces.size(), flat_value(m.interfaces));
  out << "      </CellData>\n      <Points>\n";
  arrays.array<double>("Float64", "Points", 3, 3 * m.points.size(), flat_value(m.points));
  out << "      </Points>\n      <Polys>\n";
  const std::size_t n = m.triangles.size();
  arrays.array<std::int64_t>("Int64", "connectivity", 1, 3 * n, flat_value(m.triangles), n, [](std::size_t) { return 3; });
  arrays.array<std::int64_t>("Int64", "offsets", 1, n, [](std::size_t i) { return 3 * (i + 1); });
  out << "      </Polys>\n    </Piece>\n  </PolyData>\n";
  arrays.appended_data();
  out << "</VTKFile>\n";
}

// Legacy VTK's strings in binary (vtkDataWriter): each behind its length,
// one byte 0xC0 | n under 64, two big-endian bytes 0x8000 | n under 16384.
void vtk_legacy_binary_strings(std::ostream& out, const std::map<int, std::string>& names) {
  for (const auto& [label, name] : names) {
    std::string n = name.substr(0, 16383);
    if (n.size() < 64) put_bytes(out, std::uint8_t(0xC0 | n.size()));
    else put_bytes(out, std::uint16_t(0x8000 | n.size()), ByteOrder::Big);
    out << n;
  }
  out << '\n';
}

void write_vtk_legacy(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component, bool binary) {
  out.precision(17);
  // Version 4.2: the POLYGONS layout every VTK reader (and meshio) takes.
  // Binary legacy VTK is big-endian, as the format says.
  out << "# vtk DataFile Version 4.2\nimgmesh surface, world coordinates SPACE=LPS (as ITK)\n"
      << (binary ? "BINARY" : "ASCII") << "\nDATASET POLYDATA\n";
  if (const auto names = names_used(m); !names.empty()) {
    out << "FIELD FieldData 2\nlabel_values 1 " << names.size() << " int\n";
    std::vector<int> values;
    for (const auto& [label, name] : names) values.push_back(label);
    if (binary) {
      vtk_legacy_values(out, values, true, 1);
    } else {
      for (int label : values) out << label << ' ';
      out << '\n';
    }
    out << "label_names 1 " << names.size() << " string\n";
    if (binary) vtk_legacy_binary_strings(out, names);
    else
      for (const auto& [label, name] : names) out << vtk_legacy_string(name) << '\n';
  }
  out << "POINTS " << m.points.size() << " double\n";
  vtk_legacy_values(out, flat<double>(m.points), binary, 3);
  out << "POLYGONS " << m.triangles.size() << ' ' << 4 * m.triangles.size() << '\n';
  std::vector<int> polygons;
  polygons.reserve(4 * m.triangles.size());
  for (const auto& f : m.triangles) polygons.insert(polygons.end(), {3, f[0], f[1], f[2]});
  vtk_legacy_values(out, polygons, binary, 4);
  out << "CELL_DATA " << m.triangles.size() << "\nSCALARS component int 1\nLOOKUP_TABLE default\n";
  vtk_legacy_values(out, component, binary, 1);
  if (has_labels(m)) {
    out << "SCALARS label int 1\nLOOKUP_TABLE default\n";
    vtk_legacy_values(out, m.labels, binary, 1);
  }
  if (has_pairs(m)) {
    out << "SCALARS labels int 2\nLOOKUP_TABLE default\n";
    vtk_legacy_values(out, flat<int>(m.interfaces), binary, 2);
  }
  if (has_normals(m)) {
    out << "POINT_DATA " << m.points.size() << "\nNORMALS Normals double\n";
    vtk_legacy_values(out, flat<double>(m.normals), binary, 3);
  }
}

namespace {

// The surface entities of a .msh: per face its entity (0-based), per entity
// its physical tag, and the physical groups' names by tag. Without label
// pairs an entity is a component, its group its label (or the component);
// with them an entity is one pair's triangles, its group tag the pair's
// rank (1-based, pairs in increasing order), named "a|b" or by the labels'
// names, and pairs[tag] = (behind, front) for the $LabelPairs section.
struct MshEntities {
  std::vector<int> of_face, physical;
  std::map<int, std::string> names;
  std::map<int, std::array<int, 2>> pairs;
};

MshEntities msh_entities(const SurfaceMesh& m, const std::vector<int>& component) {
  MshEntities e;
  const std::map<int, std::string> label_names = names_used(m);
  const auto name = [&](int label) {
    const auto named = label_names.find(label);
    return named != label_names.end() ? named->second : std::to_string(label);
  };
  if (has_pairs(m)) {
    std::map<std::array<int, 2>, int> rank;
    for (const auto& p : m.interfaces) rank.emplace(p, 0);
    for (auto& [pair, r] : rank) {
      r = int(e.physical.size());
      e.physical.push_back(r + 1);
      e.pairs[r + 1] = pair;
      e.names[r + 1] = mesh_detail::msh_name(name(pair[0]) + "|" + name(pair[1]));
    }
    for (const auto& p : m.interfaces) e.of_face.push_back(rank[p]);
    return e;
  }
  const bool labels = has_labels(m);
  e.of_face = component;
  e.physical.assign(component.empty() ? 0 : std::size_t(*std::max_element(component.begin(), component.end()) + 1), 0);
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    e.physical[std::size_t(component[i])] = labels ? m.labels[i] : component[i] + 1;
  for (std::size_t c = 0; c < e.physical.size(); ++c) {
    const int tag = e.physical[c];
    e.names[tag] = labels ? (label_names.count(tag) ? mesh_detail::msh_name(label_names.at(tag)) : "label " + std::to_string(tag))
                          : "component " + std::to_string(c);
  }
  return e;
}

} // namespace

void write_msh(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& face_component,
               const std::string& version, bool binary) {
  out.precision(17);
  const MshEntities entities = msh_entities(m, face_component);
  const std::vector<int>& component = entities.of_face;  // a face's entity
  const std::vector<int>& physical = entities.physical;
  const int components = int(physical.size());
  mesh_detail::MshWriter w(out, binary);
  w.format(version);
  out << "$PhysicalNames\n" << entities.names.size() << '\n';
  for (const auto& [tag, name] : entities.names) out << "2 " << tag << " \"" << name << "\"\n";
  out << "$EndPhysicalNames\n";
  // Which labels each pair's group separates, for read_surface (Gmsh and
  // meshio skip a section they do not know).
  if (!entities.pairs.empty()) {
    out << "$LabelPairs\n" << entities.pairs.size() << '\n';
    for (const auto& [tag, pair] : entities.pairs) out << tag << ' ' << pair[0] << ' ' << pair[1] << '\n';
    out << "$EndLabelPairs\n";
  }
  // The entity of each vertex: its faces' (a vertex in no face joins entity 1).
  std::vector<int> entity(m.points.size(), 0);
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (int v : m.triangles[i]) entity[std::size_t(v)] = component[i];
  // Node tags: v + 1 in 2.2; in 4.1 the order of the entity blocks, so that
  // readers that keep the file's order (meshio) agree with the tags.
  std::vector<std::size_t> tag(m.points.size());
  auto point = [&](const std::array<double, 3>& p) { w.d(p[0]).d(p[1]).d(p[2]); };
  if (version == "2.2") {
    out << "$Nodes\n" << m.points.size() << '\n';
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      tag[v] = v + 1;
      w.i((long long)(v + 1));
      point(m.points[v]);
      w.eol();
    }
    w.end("Nodes");
    out << "$Elements\n" << m.triangles.size() << '\n';
    w.block22(2, m.triangles.size(), 2);
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      const auto& f = m.triangles[i];
      w.element22(i + 1, 2, {physical[std::size_t(component[i])], component[i] + 1},
                  std::array<int, 3>{f[0] + 1, f[1] + 1, f[2] + 1});
    }
    w.end("Elements");
  } else {
    auto nodes = std::vector<std::vector<std::size_t>>(std::size_t(components)), faces = nodes;
    if (components > 0)
      for (std::size_t v = 0; v < m.points.size(); ++v) nodes[std::size_t(entity[v])].push_back(v);
    for (std::size_t i = 0; i < m.triangles.size(); ++i) faces[std::size_t(component[i])].push_back(i);
    std::size_t next = 0;
    for (const auto& block : nodes)
      for (std::size_t v : block) tag[v] = ++next;
    out << "$Entities\n";
    w.z(0).z(0).z(std::size_t(components)).z(0).eol();
    for (int c = 0; c < components; ++c) {
      std::array<double, 3> lo, hi;
      lo.fill(std::numeric_limits<double>::infinity());
      hi.fill(-std::numeric_limits<double>::infinity());
      // Over its faces' vertices: a pair's triangles may have every vertex
      // in another entity's node block (a small patch of a conforming mesh,
      // all its vertices on curves), which left the box empty (inf).
      for (std::size_t f : faces[std::size_t(c)])
        for (int v : m.triangles[f])
          for (int a = 0; a < 3; ++a) {
            lo[std::size_t(a)] = std::min(lo[std::size_t(a)], m.points[std::size_t(v)][std::size_t(a)]);
            hi[std::size_t(a)] = std::max(hi[std::size_t(a)], m.points[std::size_t(v)][std::size_t(a)]);
          }
      w.i(c + 1);
      point(lo);
      point(hi);
      w.z(1).i(physical[std::size_t(c)]).z(0).eol();
    }
    w.end("Entities");
    out << "$Nodes\n";
    w.z(std::size_t(components)).z(next).z(1).z(next).eol();
    for (int c = 0; c < components; ++c) {
      w.i(2).i(c + 1).i(0).z(nodes[std::size_t(c)].size()).eol();
      for (std::size_t v : nodes[std::size_t(c)]) w.z(tag[v]).eol();
      for (std::size_t v : nodes[std::size_t(c)]) {
        point(m.points[v]);
        w.eol();
      }
    }
    w.end("Nodes");
    out << "$Elements\n";
    w.z(std::size_t(components)).z(m.triangles.size()).z(1).z(m.triangles.size()).eol();
    for (int c = 0; c < components; ++c) {
      w.i(2).i(c + 1).i(2).z(faces[std::size_t(c)].size()).eol();
      for (std::size_t i : faces[std::size_t(c)]) {
        const auto& f = m.triangles[i];
        w.z(i + 1).z(tag[std::size_t(f[0])]).z(tag[std::size_t(f[1])]).z(tag[std::size_t(f[2])]).eol();
      }
    }
    w.end("Elements");
  }
  if (has_normals(m) && (components > 0 || version == "2.2")) {
    out << "$NodeData\n1\n\"normals\"\n1\n0.0\n3\n0\n3\n" << m.points.size() << '\n';
    std::vector<std::size_t> by_tag(m.points.size());
    for (std::size_t v = 0; v < m.points.size(); ++v) by_tag[tag[v] - 1] = v;
    for (std::size_t v : by_tag) {
      w.i((long long)tag[v]);
      point(m.normals[v]);
      w.eol();
    }
    w.end("NodeData");
  }
}

void write_ply(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component, bool binary) {
  const bool normals = has_normals(m), labels = has_labels(m);
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii")
      << " 1.0\ncomment imgmesh surface, world coordinates SPACE=LPS (as ITK)\n";
  for (const auto& [label, name] : names_used(m)) out << "comment label_name " << label << ' ' << one_line(name) << '\n';
  out << "element vertex " << m.points.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
  out << "element face " << m.triangles.size() << "\nproperty list uchar int vertex_indices\nproperty int component\n";
  if (labels) out << "property int label\n";
  if (has_pairs(m)) out << "property int label_behind\nproperty int label_front\n";
  out << "end_header\n";
  // ASCII: 9 significant digits give each float back exactly.
  out.precision(9);
  auto floats = [&](const std::array<double, 3>& p, bool first) {
    for (double c : p) {
      if (binary) put_bytes(out, float(c));
      else out << (first ? "" : " ") << float(c);
      first = false;
    }
  };
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    floats(m.points[i], true);
    if (normals) floats(m.normals[i], false);
    if (!binary) out << '\n';
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    std::vector<std::int32_t> row{m.triangles[i][0], m.triangles[i][1], m.triangles[i][2], component[i]};
    if (labels) row.push_back(m.labels[i]);
    if (has_pairs(m)) row.insert(row.end(), {m.interfaces[i][0], m.interfaces[i][1]});
    if (binary) {
      put_bytes(out, std::uint8_t(3));
      for (std::int32_t x : row) put_bytes(out, x);
    } else {
      out << '3';
      for (std::int32_t x : row) out << ' ' << x;
      out << '\n';
    }
  }
}

} // namespace imgmesh
