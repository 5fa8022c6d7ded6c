// Planar mesh formats other than Triangle's, and the choice by extension.
#include "planar/planar_formats.hpp"

#include "planar/text_io.hpp"
#include "util/atomic_file.hpp"
#include "util/binary_io.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sys/stat.h>

namespace imgmesh {
namespace {

bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

double region_of(const PlanarMesh& m, std::size_t e) {
  return m.element_attributes.empty() || m.element_attributes[e].empty() ? 0.0
                                                                         : m.element_attributes[e][0];
}

void check_mesh(const PlanarMesh& m, const std::string& path) {
  for (const auto& e : m.elements)
    for (int v : e)
      if (v < 0 || std::size_t(v) >= m.points.size())
        throw Error("internal: element refers to a missing vertex", path);
}

void write_off(const std::string& path, const PlanarMesh& m) {
  TextOutput o(path);
  o << "OFF\n" << m.points.size() << ' ' << m.elements.size() << " 0\n";
  for (const auto& p : m.points) o << p[0] << ' ' << p[1] << " 0\n";
  for (const auto& e : m.elements) {
    o << e.size();
    for (int v : e) o << ' ' << v;
    o << '\n';
  }
  o.commit();
}

// Legacy VTK, ASCII or binary (big-endian, as the format requires): the
// same numbers either way.
void write_vtk(const std::string& path, const PlanarMesh& m, const PlanarWriteOptions& opt) {
  TextOutput o(path);
  const bool binary = !opt.ascii;
  o << "# vtk DataFile Version 3.0\nimgmesh planar mesh\n" << (binary ? "BINARY" : "ASCII")
    << "\nDATASET UNSTRUCTURED_GRID\n";
  o << "POINTS " << m.points.size() << " double\n";
  std::vector<double> xyz;
  for (const auto& p : m.points) xyz.insert(xyz.end(), {p[0], p[1], 0.0});
  vtk_legacy_values(o, xyz, binary, 3);
  std::vector<int> cells, types;
  std::vector<std::size_t> rows;
  for (const auto& e : m.elements) {
    cells.push_back(int(e.size()));
    cells.insert(cells.end(), e.begin(), e.end());
    rows.push_back(e.size() + 1);
    types.push_back(e.size() == 3 ? 5 : e.size() == 4 ? 9 : 7);
  }
  o << "CELLS " << m.elements.size() << ' ' << cells.size() << '\n';
  vtk_legacy_values(o, cells, binary, rows);
  o << "CELL_TYPES " << m.elements.size() << '\n';
  vtk_legacy_values(o, types, binary, 1);
  if (!m.elements.empty()) {
    o << "CELL_DATA " << m.elements.size() << '\n';
    o << "SCALARS region double 1\nLOOKUP_TABLE default\n";
    std::vector<double> regions;
    for (std::size_t i = 0; i < m.elements.size(); ++i) regions.push_back(region_of(m, i));
    vtk_legacy_values(o, regions, binary, 1);
    if (opt.element_scalar.size() == m.elements.size()) {
      std::string name = opt.scalar_name.empty() ? "scalar" : opt.scalar_name;
      std::replace(name.begin(), name.end(), ' ', '_');
      o << "SCALARS " << name << " double 1\nLOOKUP_TABLE default\n";
      vtk_legacy_values(o, opt.element_scalar, binary, 1);
    }
  }
  if (m.point_markers.size() == m.points.size() && !m.points.empty()) {
    o << "POINT_DATA " << m.points.size() << "\nSCALARS marker int 1\nLOOKUP_TABLE default\n";
    vtk_legacy_values(o, m.point_markers, binary, 1);
  }
  o.commit();
}

// Gmsh 2.2: elements carry (physical, elementary) tags = (region attribute,
// region attribute); segments are line elements tagged with their marker.
void write_msh(const std::string& path, const PlanarMesh& m) {
  TextOutput o(path);
  o << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m.points.size() << '\n';
  for (std::size_t i = 0; i < m.points.size(); ++i)
    o << i + 1 << ' ' << m.points[i][0] << ' ' << m.points[i][1] << " 0\n";
  o << "$EndNodes\n$Elements\n" << m.segments.size() + m.elements.size() << '\n';
  std::size_t id = 1;
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    const int tag = m.segment_markers.empty() ? 0 : m.segment_markers[i];
    o << id++ << " 1 2 " << tag << ' ' << tag << ' ' << m.segments[i][0] + 1 << ' '
      << m.segments[i][1] + 1 << '\n';
  }
  for (std::size_t i = 0; i < m.elements.size(); ++i) {
    const auto& e = m.elements[i];
    const long tag = std::lround(region_of(m, i));
    o << id++ << ' ' << (e.size() == 3 ? 2 : 3) << " 2 " << tag << ' ' << tag;
    for (int v : e) o << ' ' << v + 1;
    o << '\n';
  }
  o << "$EndElements\n";
  o.commit();
}


// OFF: "OFF" [nv nf ne] on the first line or the next, '#' comments.
PlanarMesh read_off(const std::string& path, std::size_t min_face, std::size_t max_face) {
  const std::string text = read_all(path);
  std::vector<std::pair<int, std::vector<std::string_view>>> lines;  // non-empty lines' numbers and fields
  {
    int n = 0;
    std::vector<std::string_view> f;
    for (std::size_t pos = 0; pos < text.size();) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      ++n;
      split_fields(std::string_view(text).substr(pos, end - pos), f);
      if (!f.empty()) lines.push_back({n, f});
      pos = end + 1;
    }
  }
  std::size_t li = 0;
  auto fail = [&](const std::string& what) -> void {
    const int n = li < lines.size() ? lines[li].first : (lines.empty() ? 0 : lines.back().first);
    throw Error("line " + std::to_string(n) + ": " + what, path);
  };
  auto coordinate = [&](std::string_view s) {
    double v;
    if (!parse_coordinate(s, v)) fail(coordinate_error(s));
    return v;
  };
  auto integer = [&](std::string_view s) {
    long long v;
    if (!parse_integer(s, v)) fail("'" + std::string(s) + "' is not an integer");
    return v;
  };
  if (lines.empty() || lines[0].second[0] != "OFF") {
    li = 0;
    fail("not an OFF file (no OFF header)");
  }
  std::vector<std::string_view> counts(lines[0].second.begin() + 1, lines[0].second.end());
  li = 1;
  if (counts.empty()) {
    if (li >= lines.size()) fail("truncated: no counts");
    counts = lines[li++].second;
  }
  if (counts.size() < 2) fail("expected vertex and face counts");
  const long long nv = integer(counts[0]), nf = integer(counts[1]);
  if (nv < 0 || nf < 0) fail("negative count");
  if (std::size_t(nv) > lines.size() - li || std::size_t(nf) > lines.size() - li - std::size_t(nv)) fail("truncated: fewer lines than the counts announce");
  PlanarMesh m;
  for (long long i = 0; i < nv; ++i, ++li) {
    const auto& f = lines[li].second;
    if (f.size() < 2) fail("a vertex needs x y [z]");
    m.points.push_back({coordinate(f[0]), coordinate(f[1])});
    if (f.size() > 2) coordinate(f[2]);  // z is dropped, but read as the others
  }
  check_extent(m.points, path);
  for (long long i = 0; i < nf; ++i, ++li) {
    const auto& f = lines[li].second;
    const long long k = integer(f[0]);
    if (k < (long long)min_face || k > (long long)max_face)
      fail("faces must have " + std::to_string(min_face) + (max_face > 4 ? " or more" : " or 4") + " vertices");
    if ((long long)f.size() < k + 1) fail("face has fewer vertices than announced");
    std::vector<int> e;
    for (long long j = 0; j < k; ++j) {
      const long long v = integer(f[1 + j]);
      if (v < 0 || v >= nv) fail("vertex " + std::string(f[1 + j]) + " does not exist");
      e.push_back(int(v));
    }
    m.elements.push_back(std::move(e));
  }
  return m;
}

} // namespace

void write_planar_mesh(const std::string& path, const PlanarMesh& m, const PlanarWriteOptions& opt) {
  check_mesh(m, path);
  // "-": OFF on standard output, the one single-file planar mesh format.
  const std::string ext = path == "-" ? std::string(".off") : extension_of(path);
  if (ext == ".ele") {
    write_node(replace_extension(path, ".node"), m);
    if (!m.segments.empty()) write_poly(replace_extension(path, ".poly"), m, false);
    write_ele(path, m);
  } else if (ext == ".node") {
    write_node(path, m);
  } else if (ext == ".poly") {
    write_poly(path, m, true);
  } else if (ext == ".off") {
    write_off(path, m);
  } else if (ext == ".vtk") {
    write_vtk(path, m, opt);
  } else if (ext == ".msh") {
    write_msh(path, m);
  } else if (ext == ".svg") {
    write_svg(path, m, opt);
  } else {
    throw UsageError("unknown planar mesh format '" + ext + "' (use .ele, .off, .vtk, .msh or .svg)", path);
  }
}

std::vector<std::array<int, 2>> segments_on_mesh(const PlanarMesh& poly, const PlanarMesh& m,
                                                 const std::string& poly_path, std::vector<int>* markers) {
  const bool own_ids = poly.points.empty() || poly.points == m.points;
  const std::size_t n = own_ids ? m.points.size() : poly.points.size();
  std::vector<int> map;
  if (!own_ids) {
    std::map<Point2, int> at;
    for (std::size_t i = 0; i < m.points.size(); ++i) at.emplace(m.points[i], int(i));
    map.resize(poly.points.size());
    for (std::size_t i = 0; i < map.size(); ++i) {
      auto it = at.find(poly.points[i]);
      if (it == at.end()) throw Error("a segment vertex is not a vertex of the mesh", poly_path);
      map[i] = it->second;
    }
  }
  std::vector<std::array<int, 2>> out;
  out.reserve(poly.segments.size());
  for (std::size_t k = 0; k < poly.segments.size(); ++k) {
    auto e = poly.segments[k];
    for (int& v : e) {
      if (v < 0 || std::size_t(v) >= n)
        throw Error("segment " + std::to_string(k + std::size_t(poly.first_index)) + " has a vertex id out of range",
                    poly_path);
      if (!own_ids) v = map[std::size_t(v)];
    }
    out.push_back(e);
  }
  if (markers) *markers = poly.segment_markers;
  return out;
}

PlanarMesh read_planar_mesh(const std::string& path) {
  // "-": OFF on standard input, parsed from memory as a file would be (the
  // one single-file planar mesh format; errors name "-").
  const std::string ext = path == "-" ? std::string(".off") : extension_of(path);
  if (ext == ".ele") {
    PlanarMesh m = read_ele(path);
    const std::string poly = replace_extension(path, ".poly");
    if (exists(poly)) {
      PlanarMesh p = read_poly(poly);
      m.segments = segments_on_mesh(p, m, poly, &m.segment_markers);
      m.holes = p.holes;
      m.regions = p.regions;
    }
    return m;
  }
  if (ext == ".off") return read_off(path, 3, 4);
  throw Error("unknown planar mesh format '" + ext + "' (use .ele with its .node, or .off)", path);
}

PlanarMesh read_pslg(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext == ".poly" || path == "-") return read_poly(path);  // stdin: .poly text
  if (ext == ".node") {  // the .poly beside it holds the segments that bound the domain
    const std::string poly = replace_extension(path, ".poly");
    if (!exists(poly)) throw Error("no " + poly + " beside it (the segments that bound the domain)", path);
    return read_poly(poly);
  }
  if (ext == ".off") {
    PlanarMesh m = read_off(path, 2, 1 << 30);
    std::set<std::pair<int, int>> seen;
    for (const auto& f : m.elements)
      for (std::size_t i = 0; i < f.size(); ++i) {
        int a = f[i], b = f[(i + 1) % f.size()];
        if (f.size() == 2 && i == 1) break;
        if (a == b) throw Error("a polygon repeats a vertex on consecutive corners", path);
        if (seen.insert({std::min(a, b), std::max(a, b)}).second) {
          m.segments.push_back({a, b});
          m.segment_markers.push_back(1);
        }
      }
    m.elements.clear();
    return m;
  }
  throw Error("unknown PSLG format '" + ext + "' (use .poly, .node or .off)", path);
}

} // namespace imgmesh
