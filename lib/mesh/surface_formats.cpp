// Writers of the formats with per-face data (surface_formats.hpp). Text
// formats print doubles with 17 digits, so that world coordinates survive.
#include "mesh/surface_formats.hpp"

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

int find(std::vector<int>& parent, int x) {
  while (parent[std::size_t(x)] != x) x = parent[std::size_t(x)] = parent[std::size_t(parent[std::size_t(x)])];
  return x;
}

// Little-endian bytes of a value (PLY binary_little_endian).
template <class T> void put(std::ostream& out, T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  const std::uint32_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  if (first != 1) std::reverse(b, b + sizeof(T));
  out.write(reinterpret_cast<const char*>(b), sizeof(T));
}

// A VTK XML DataArray in ASCII, `per_line` values a line.
template <class Range, class F>
void data_array(std::ostream& out, const char* type, const char* name, int components, const Range& items, F&& write) {
  out << "        <DataArray type=\"" << type << "\"";
  if (name) out << " Name=\"" << name << "\"";
  if (components > 1) out << " NumberOfComponents=\"" << components << "\"";
  out << " format=\"ascii\">\n";
  for (const auto& item : items) {
    out << "         ";
    write(item);
    out << '\n';
  }
  out << "        </DataArray>\n";
}

void xyz(std::ostream& out, const std::array<double, 3>& p) { out << p[0] << ' ' << p[1] << ' ' << p[2]; }

// The names of the labels the faces carry (empty names left out), by label.
std::map<int, std::string> names_used(const SurfaceMesh& m) {
  std::map<int, std::string> out;
  if (!has_labels(m) || m.label_names.empty()) return out;
  const std::set<int> used(m.labels.begin(), m.labels.end());
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

// A Gmsh physical name: one line, no double quote, at most 127 bytes (the
// format's limit), not cut inside a UTF-8 character.
std::string msh_name(const std::string& name) {
  std::string s = one_line(name);
  std::replace(s.begin(), s.end(), '"', '\'');
  if (s.size() > 127) {
    std::size_t end = 127;
    while (end > 0 && (static_cast<unsigned char>(s[end]) & 0xc0) == 0x80) --end;
    s.resize(end);
  }
  return s;
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

void write_vtp(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component) {
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<!-- imgmesh surface, world coordinates SPACE=LPS (as ITK) -->\n"
      << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <PolyData>\n";
  vtp_field_data(out, names_used(m));
  out << "    <Piece NumberOfPoints=\"" << m.points.size() << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
      << "NumberOfStrips=\"0\" NumberOfPolys=\"" << m.triangles.size() << "\">\n";
  if (has_normals(m)) {
    out << "      <PointData Normals=\"Normals\">\n";
    data_array(out, "Float64", "Normals", 3, m.normals, [&](const auto& n) { xyz(out, n); });
    out << "      </PointData>\n";
  }
  out << "      <CellData Scalars=\"" << (has_labels(m) ? "label" : "component") << "\">\n";
  data_array(out, "Int32", "component", 1, component, [&](int c) { out << c; });
  if (has_labels(m)) data_array(out, "Int32", "label", 1, m.labels, [&](int l) { out << l; });
  out << "      </CellData>\n      <Points>\n";
  data_array(out, "Float64", "Points", 3, m.points, [&](const auto& p) { xyz(out, p); });
  out << "      </Points>\n      <Polys>\n";
  data_array(out, "Int64", "connectivity", 1, m.triangles,
             [&](const auto& f) { out << f[0] << ' ' << f[1] << ' ' << f[2]; });
  std::vector<std::size_t> offsets(m.triangles.size());
  for (std::size_t i = 0; i < offsets.size(); ++i) offsets[i] = 3 * (i + 1);
  data_array(out, "Int64", "offsets", 1, offsets, [&](std::size_t o) { out << o; });
  out << "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
}

void write_vtk_legacy(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component) {
  out.precision(17);
  // Version 4.2: the POLYGONS layout every VTK reader (and meshio) takes.
  out << "# vtk DataFile Version 4.2\nimgmesh surface, world coordinates SPACE=LPS (as ITK)\nASCII\n"
      << "DATASET POLYDATA\n";
  if (const auto names = names_used(m); !names.empty()) {
    out << "FIELD FieldData 2\nlabel_values 1 " << names.size() << " int\n";
    for (const auto& [label, name] : names) out << label << ' ';
    out << "\nlabel_names 1 " << names.size() << " string\n";
    for (const auto& [label, name] : names) out << vtk_legacy_string(name) << '\n';
  }
  out << "POINTS " << m.points.size() << " double\n";
  for (const auto& p : m.points) {
    xyz(out, p);
    out << '\n';
  }
  out << "POLYGONS " << m.triangles.size() << ' ' << 4 * m.triangles.size() << '\n';
  for (const auto& f : m.triangles) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  out << "CELL_DATA " << m.triangles.size() << "\nSCALARS component int 1\nLOOKUP_TABLE default\n";
  for (int c : component) out << c << '\n';
  if (has_labels(m)) {
    out << "SCALARS label int 1\nLOOKUP_TABLE default\n";
    for (int l : m.labels) out << l << '\n';
  }
  if (has_normals(m)) {
    out << "POINT_DATA " << m.points.size() << "\nNORMALS Normals double\n";
    for (const auto& n : m.normals) {
      xyz(out, n);
      out << '\n';
    }
  }
}

void write_msh(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component, const std::string& version) {
  out.precision(17);
  const bool labels = has_labels(m);
  const int components = component.empty() ? 0 : *std::max_element(component.begin(), component.end()) + 1;
  // Entity e = component e - 1; its physical group.
  std::vector<int> physical(std::size_t(components), 0);
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    physical[std::size_t(component[i])] = labels ? m.labels[i] : component[i] + 1;
  const std::map<int, std::string> label_names = names_used(m);
  std::map<int, std::string> names;
  for (int c = 0; c < components; ++c) {
    const int tag = physical[std::size_t(c)];
    const auto named = label_names.find(tag);
    names[tag] = !labels ? "component " + std::to_string(c)
                 : named != label_names.end() ? msh_name(named->second)
                                              : "label " + std::to_string(tag);
  }
  out << "$MeshFormat\n" << version << " 0 8\n$EndMeshFormat\n$PhysicalNames\n" << names.size() << '\n';
  for (const auto& [tag, name] : names) out << "2 " << tag << " \"" << name << "\"\n";
  out << "$EndPhysicalNames\n";
  // The entity of each vertex: its faces' (a vertex in no face joins entity 1).
  std::vector<int> entity(m.points.size(), 0);
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (int v : m.triangles[i]) entity[std::size_t(v)] = component[i];
  // Node tags: v + 1 in 2.2; in 4.1 the order of the entity blocks, so that
  // readers that keep the file's order (meshio) agree with the tags.
  std::vector<std::size_t> tag(m.points.size());
  if (version == "2.2") {
    out << "$Nodes\n" << m.points.size() << '\n';
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      tag[v] = v + 1;
      out << v + 1 << ' ';
      xyz(out, m.points[v]);
      out << '\n';
    }
    out << "$EndNodes\n$Elements\n" << m.triangles.size() << '\n';
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      const auto& f = m.triangles[i];
      out << i + 1 << " 2 2 " << physical[std::size_t(component[i])] << ' ' << component[i] + 1 << ' ' << f[0] + 1
          << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
    }
    out << "$EndElements\n";
  } else {
    auto nodes = std::vector<std::vector<std::size_t>>(std::size_t(components)), faces = nodes;
    if (components > 0)
      for (std::size_t v = 0; v < m.points.size(); ++v) nodes[std::size_t(entity[v])].push_back(v);
    for (std::size_t i = 0; i < m.triangles.size(); ++i) faces[std::size_t(component[i])].push_back(i);
    std::size_t next = 0;
    for (const auto& block : nodes)
      for (std::size_t v : block) tag[v] = ++next;
    out << "$Entities\n0 0 " << components << " 0\n";
    for (int c = 0; c < components; ++c) {
      std::array<double, 3> lo, hi;
      lo.fill(std::numeric_limits<double>::infinity());
      hi.fill(-std::numeric_limits<double>::infinity());
      for (std::size_t v : nodes[std::size_t(c)])
        for (int a = 0; a < 3; ++a) {
          lo[std::size_t(a)] = std::min(lo[std::size_t(a)], m.points[v][std::size_t(a)]);
          hi[std::size_t(a)] = std::max(hi[std::size_t(a)], m.points[v][std::size_t(a)]);
        }
      out << c + 1 << ' ';
      xyz(out, lo);
      out << ' ';
      xyz(out, hi);
      out << " 1 " << physical[std::size_t(c)] << " 0\n";
    }
    out << "$EndEntities\n$Nodes\n" << components << ' ' << next << " 1 " << next << '\n';
    for (int c = 0; c < components; ++c) {
      out << "2 " << c + 1 << " 0 " << nodes[std::size_t(c)].size() << '\n';
      for (std::size_t v : nodes[std::size_t(c)]) out << tag[v] << '\n';
      for (std::size_t v : nodes[std::size_t(c)]) {
        xyz(out, m.points[v]);
        out << '\n';
      }
    }
    out << "$EndNodes\n$Elements\n"
        << components << ' ' << m.triangles.size() << " 1 " << m.triangles.size() << '\n';
    for (int c = 0; c < components; ++c) {
      out << "2 " << c + 1 << " 2 " << faces[std::size_t(c)].size() << '\n';
      for (std::size_t i : faces[std::size_t(c)]) {
        const auto& f = m.triangles[i];
        out << i + 1 << ' ' << tag[std::size_t(f[0])] << ' ' << tag[std::size_t(f[1])] << ' '
            << tag[std::size_t(f[2])] << '\n';
      }
    }
    out << "$EndElements\n";
  }
  if (has_normals(m) && (components > 0 || version == "2.2")) {
    out << "$NodeData\n1\n\"normals\"\n1\n0.0\n3\n0\n3\n" << m.points.size() << '\n';
    std::vector<std::size_t> by_tag(m.points.size());
    for (std::size_t v = 0; v < m.points.size(); ++v) by_tag[tag[v] - 1] = v;
    for (std::size_t v : by_tag) {
      out << tag[v] << ' ';
      xyz(out, m.normals[v]);
      out << '\n';
    }
    out << "$EndNodeData\n";
  }
}

void write_ply(std::ostream& out, const SurfaceMesh& m, const std::vector<int>& component) {
  const bool normals = has_normals(m), labels = has_labels(m);
  out << "ply\nformat binary_little_endian 1.0\ncomment imgmesh surface, world coordinates SPACE=LPS (as ITK)\n";
  for (const auto& [label, name] : names_used(m)) out << "comment label_name " << label << ' ' << one_line(name) << '\n';
  out << "element vertex " << m.points.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
  out << "element face " << m.triangles.size() << "\nproperty list uchar int vertex_indices\nproperty int component\n";
  if (labels) out << "property int label\n";
  out << "end_header\n";
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    for (double c : m.points[i]) put(out, float(c));
    if (normals)
      for (double c : m.normals[i]) put(out, float(c));
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    put(out, std::uint8_t(3));
    for (int v : m.triangles[i]) put(out, std::int32_t(v));
    put(out, std::int32_t(component[i]));
    if (labels) put(out, std::int32_t(m.labels[i]));
  }
}

} // namespace imgmesh
