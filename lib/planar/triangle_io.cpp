// Triangle's file formats, read strictly: every malformed line is an Error
// naming the file and the line, so a bad mesh never travels further down the
// pipeline. The rules follow Triangle 1.6's own readers (triangle.c):
// '#' starts a comment, blank lines are skipped, the first vertex's number
// (0 or 1) fixes the numbering, extra fields on a line are ignored, a .poly
// with 0 vertices takes them from the .node beside it, and a region line with
// only one value uses it as both attribute and area bound.
#include "planar/triangle_io.hpp"

#include "planar/text_io.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <cmath>
#include <string_view>

namespace imgmesh {
namespace {

// A Triangle file as a list of non-empty lines, each remembering its number
// in the file for error messages. Lines are kept as spans of the text and
// split into fields only when read (one line at a time, into views of the
// text): a vector of strings for every line cost ~235 bytes a triangle.
class Fields {
public:
  explicit Fields(const std::string& path) : path_(path), text_(read_all(path)) {
    int number = 0;
    for (std::size_t pos = 0; pos < text_.size();) {
      std::size_t end = text_.find('\n', pos);
      if (end == std::string::npos) end = text_.size();
      ++number;
      while (pos < end && blank(text_[pos])) ++pos;
      // A comment after data ends its line only when the line is split.
      if (pos < end && text_[pos] != '#') lines_.push_back({pos, end, number});
      pos = end + 1;
    }
  }

  bool at_end() const { return next_ >= lines_.size(); }
  const std::string& path() const { return path_; }

  // The next line with at least `min_fields` fields; `what` names it in errors.
  const std::vector<std::string_view>& next(std::size_t min_fields, const char* what) {
    if (at_end())
      throw Error("truncated: expected " + std::string(what) + " after line " +
                      std::to_string(lines_.empty() ? 0 : lines_.back().number),
                  path_);
    current_ = next_++;
    const auto& l = lines_[current_];
    split_fields(std::string_view(text_).substr(l.begin, l.end - l.begin), fields_);
    if (fields_.size() < min_fields)
      fail(std::string(what) + " needs " + std::to_string(min_fields) + " fields, has " +
           std::to_string(fields_.size()));
    return fields_;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error("line " + std::to_string(lines_[current_].number) + ": " + what, path_);
  }

  double real(std::string_view s) const {
    double v;
    if (!parse_real(s, v)) fail("'" + std::string(s) + "' is not a number");
    if (!std::isfinite(v)) fail("'" + std::string(s) + "' is not a finite number");
    return v;
  }
  // A coordinate: a number in the range every tool takes (util/coordinates.hpp).
  double coordinate(std::string_view s) const {
    double v;
    if (!parse_coordinate(s, v)) fail(coordinate_error(s));
    return v;
  }
  long long integer(std::string_view s) const {
    long long v;
    if (!parse_integer(s, v)) fail("'" + std::string(s) + "' is not an integer");
    return v;
  }
  // A count in [0, limit].
  std::size_t count(std::string_view s, const char* what, long long limit = 1LL << 40) const {
    const long long v = integer(s);
    if (v < 0 || v > limit) fail(std::string("bad ") + what + " " + std::string(s));
    return std::size_t(v);
  }
  // Counts beyond the number of remaining lines are truncation, found before
  // allocating anything for them.
  void need_lines(std::size_t n, const char* what) const {
    if (n > lines_.size() - next_)
      fail("truncated: " + std::to_string(n) + " " + what + " announced, only " +
           std::to_string(lines_.size() - next_) + " lines follow");
  }

private:
  struct Line { std::size_t begin, end; int number; };
  std::string path_;
  std::string text_;
  std::vector<Line> lines_;
  std::vector<std::string_view> fields_;  // the current line's fields
  std::size_t next_ = 0, current_ = 0;
};

// Reads the vertex block (header already parsed) into m.
void read_vertices(Fields& f, PlanarMesh& m, std::size_t n, std::size_t nattr, bool markers) {
  f.need_lines(n, "vertices");
  m.points.reserve(n);
  if (nattr) m.point_attributes.reserve(n);
  if (markers) m.point_markers.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& l = f.next(3 + nattr + (markers ? 1 : 0), "a vertex");
    const long long id = f.integer(l[0]);
    if (i == 0) {
      if (id != 0 && id != 1) f.fail("the first vertex must be numbered 0 or 1");
      m.first_index = int(id);
    } else if (id != m.first_index + (long long)i) {
      f.fail("vertex number " + std::string(l[0]) + ", expected " + std::to_string(m.first_index + i));
    }
    m.points.push_back({f.coordinate(l[1]), f.coordinate(l[2])});
    if (nattr) {
      std::vector<double> a(nattr);
      for (std::size_t k = 0; k < nattr; ++k) a[k] = f.real(l[3 + k]);
      m.point_attributes.push_back(std::move(a));
    }
    if (markers) m.point_markers.push_back(int(f.integer(l[3 + nattr])));
  }
  check_extent(m.points, f.path());
}

void read_node_header_and_vertices(Fields& f, PlanarMesh& m, bool allow_empty, bool* deferred) {
  const auto& h = f.next(1, "the vertex header");
  const std::size_t n = f.count(h[0], "vertex count");
  const std::size_t dim = h.size() > 1 ? f.count(h[1], "dimension") : 2;
  const std::size_t nattr = h.size() > 2 ? f.count(h[2], "attribute count", 1 << 20) : 0;
  const std::size_t nmark = h.size() > 3 ? f.count(h[3], "marker count") : 0;
  if (dim != 2) f.fail("dimension must be 2, is " + std::string(h[1]));
  if (nmark > 1) f.fail("marker count must be 0 or 1");
  if (n == 0) {
    if (!allow_empty) f.fail("no vertices");
    if (deferred) *deferred = true;
    return;
  }
  if (n < 3 && !allow_empty) f.fail("fewer than 3 vertices");
  read_vertices(f, m, n, nattr, nmark == 1);
}

int vertex_id(const Fields& f, const PlanarMesh& m, std::string_view s) {
  const long long id = f.integer(s) - m.first_index;
  if (id < 0 || id >= (long long)m.points.size())
    f.fail("vertex " + std::string(s) + " does not exist (vertices are " + std::to_string(m.first_index) + ".." +
           std::to_string(m.first_index + (long long)m.points.size() - 1) + ")");
  return int(id);
}

std::string node_beside(const std::string& path) { return replace_extension(path, ".node"); }

} // namespace

PlanarMesh read_node(const std::string& path) {
  Fields f(path);
  PlanarMesh m;
  read_node_header_and_vertices(f, m, false, nullptr);
  return m;
}

PlanarMesh read_poly(const std::string& path) {
  Fields f(path);
  PlanarMesh m;
  bool deferred = false;
  read_node_header_and_vertices(f, m, true, &deferred);
  if (deferred) {
    if (path == "-") throw Error("a .poly without vertices needs its .node beside it, not stdin", path);
    PlanarMesh n = read_node(node_beside(path));
    m.points = std::move(n.points);
    m.point_attributes = std::move(n.point_attributes);
    m.point_markers = std::move(n.point_markers);
    m.first_index = n.first_index;
  }
  const auto& sh = f.next(1, "the segment header");
  const std::size_t ns = f.count(sh[0], "segment count");
  const std::size_t smark = sh.size() > 1 ? f.count(sh[1], "segment marker count") : 0;
  if (smark > 1) f.fail("segment marker count must be 0 or 1");
  f.need_lines(ns, "segments");
  m.segments.reserve(ns);
  for (std::size_t i = 0; i < ns; ++i) {
    const auto& l = f.next(3 + smark, "a segment");
    const int a = vertex_id(f, m, l[1]), b = vertex_id(f, m, l[2]);
    if (a == b) f.fail("segment " + std::string(l[0]) + " joins vertex " + std::string(l[1]) + " to itself");
    m.segments.push_back({a, b});
    if (smark) m.segment_markers.push_back(int(f.integer(l[3])));
  }
  // Holes and regions are optional at the end of the file (Triangle's rule).
  if (f.at_end()) return m;
  const std::size_t nh = f.count(f.next(1, "the hole count")[0], "hole count");
  f.need_lines(nh, "holes");
  for (std::size_t i = 0; i < nh; ++i) {
    const auto& l = f.next(3, "a hole");
    m.holes.push_back({f.coordinate(l[1]), f.coordinate(l[2])});
  }
  if (f.at_end()) return m;
  const std::size_t nr = f.count(f.next(1, "the region count")[0], "region count");
  f.need_lines(nr, "regions");
  for (std::size_t i = 0; i < nr; ++i) {
    const auto& l = f.next(4, "a region (number x y attribute [max area])");
    PlanarMesh::Region r;
    r.point = {f.coordinate(l[1]), f.coordinate(l[2])};
    r.attribute = f.real(l[3]);
    r.max_area = l.size() > 4 ? f.real(l[4]) : r.attribute;
    m.regions.push_back(r);
  }
  if (!f.at_end()) {
    f.next(0, "");
    f.fail("unexpected data after the regions");
  }
  return m;
}

PlanarMesh read_ele(const std::string& ele_path) {
  if (ele_path == "-") throw Error("an .ele needs its .node beside it, not stdin", ele_path);
  PlanarMesh m = read_node(node_beside(ele_path));
  Fields f(ele_path);
  const auto& h = f.next(2, "the element header");
  const std::size_t n = f.count(h[0], "element count");
  const std::size_t per = f.count(h[1], "nodes per element");
  const std::size_t nattr = h.size() > 2 ? f.count(h[2], "attribute count", 1 << 20) : 0;
  // 6-node (quadratic) triangles keep their three corners, as Triangle lists them first.
  if (per != 3 && per != 4 && per != 6) f.fail("nodes per element must be 3, 4 or 6, is " + std::string(h[1]));
  const std::size_t corners = per == 6 ? 3 : per;
  f.need_lines(n, "elements");
  m.elements.reserve(n);
  if (nattr) m.element_attributes.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& l = f.next(1 + per + nattr, "an element");
    std::vector<int> e(corners);
    for (std::size_t k = 0; k < corners; ++k) e[k] = vertex_id(f, m, l[1 + k]);
    for (std::size_t k = 0; k < corners; ++k)
      for (std::size_t j = k + 1; j < corners; ++j)
        if (e[k] == e[j]) f.fail("element " + std::string(l[0]) + " repeats vertex " + std::string(l[1 + k]));
    for (std::size_t k = corners; k < per; ++k) vertex_id(f, m, l[1 + k]);
    m.elements.push_back(std::move(e));
    if (nattr) {
      std::vector<double> a(nattr);
      for (std::size_t k = 0; k < nattr; ++k) a[k] = f.real(l[1 + per + k]);
      m.element_attributes.push_back(std::move(a));
    }
  }
  return m;
}

namespace {
void write_vertices(TextOutput& o, const PlanarMesh& m) {
  const std::size_t nattr = m.point_attributes.empty() ? 0 : m.point_attributes[0].size();
  const bool markers = !m.point_markers.empty();
  if (markers && m.point_markers.size() != m.points.size())
    throw Error("internal: point markers do not match the points");
  o << m.points.size() << " 2 " << nattr << ' ' << (markers ? 1 : 0) << '\n';
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    o << i + m.first_index << ' ' << m.points[i][0] << ' ' << m.points[i][1];
    for (std::size_t k = 0; k < nattr; ++k)
      o << ' ' << (k < m.point_attributes[i].size() ? m.point_attributes[i][k] : 0.0);
    if (markers) o << ' ' << m.point_markers[i];
    o << '\n';
  }
}
} // namespace

void write_node(const std::string& path, const PlanarMesh& m) {
  TextOutput o(path);
  o << "# " << m.points.size() << " vertices (imgmesh)\n";
  write_vertices(o, m);
  o.commit();
}

void write_ele(const std::string& path, const PlanarMesh& m) {
  const std::size_t per = m.elements.empty() ? 3 : m.elements[0].size();
  const std::size_t nattr = m.element_attributes.empty() ? 0 : m.element_attributes[0].size();
  for (const auto& e : m.elements)
    if (e.size() != per) throw Error("internal: mixed element sizes cannot be written as .ele", path);
  TextOutput o(path);
  o << "# " << m.elements.size() << (per == 4 ? " quadrilaterals" : " triangles") << " (imgmesh)\n";
  o << m.elements.size() << ' ' << per << ' ' << nattr << '\n';
  for (std::size_t i = 0; i < m.elements.size(); ++i) {
    o << i + m.first_index;
    for (int v : m.elements[i]) o << ' ' << v + m.first_index;
    for (std::size_t k = 0; k < nattr; ++k)
      o << ' ' << (k < m.element_attributes[i].size() ? m.element_attributes[i][k] : 0.0);
    o << '\n';
  }
  o.commit();
}

void write_poly(const std::string& path, const PlanarMesh& m, bool with_points) {
  TextOutput o(path);
  if (with_points) {
    o << "# vertices\n";
    write_vertices(o, m);
  } else {
    o << "# vertices in the .node file\n";
    const std::size_t nattr = m.point_attributes.empty() ? 0 : m.point_attributes[0].size();
    o << "0 2 " << nattr << ' ' << (m.point_markers.empty() ? 0 : 1) << '\n';
  }
  const bool markers = !m.segment_markers.empty();
  if (markers && m.segment_markers.size() != m.segments.size())
    throw Error("internal: segment markers do not match the segments", path);
  o << "# segments\n" << m.segments.size() << ' ' << (markers ? 1 : 0) << '\n';
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    o << i + m.first_index << ' ' << m.segments[i][0] + m.first_index << ' '
      << m.segments[i][1] + m.first_index;
    if (markers) o << ' ' << m.segment_markers[i];
    o << '\n';
  }
  o << "# holes\n" << m.holes.size() << '\n';
  for (std::size_t i = 0; i < m.holes.size(); ++i) {
    o << i + m.first_index << ' ' << m.holes[i][0] << ' ' << m.holes[i][1] << '\n';
  }
  if (!m.regions.empty()) {
    o << "# regions: x y attribute max-area\n" << m.regions.size() << '\n';
    for (std::size_t i = 0; i < m.regions.size(); ++i) {
      const auto& r = m.regions[i];
      o << i + m.first_index << ' ' << r.point[0] << ' ' << r.point[1] << ' ' << r.attribute << ' '
        << r.max_area << '\n';
    }
  }
  o.commit();
}

} // namespace imgmesh
