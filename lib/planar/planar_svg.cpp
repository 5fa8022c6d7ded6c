// SVG pictures of planar meshes: the mesh (elements filled by a scalar on a
// fixed or data colour scale, or by their region's tint), segments on top,
// an optional raster under it, a title line with the counts and a legend
// (the colour scale, or the regions' tints); framed on the foreground (the
// elements of nonzero regions and the segments that are not the image
// rectangle's, marker 1) unless the whole picture is asked for.
#include "planar/planar_formats.hpp"

#include "planar/svg_detail.hpp"
#include "util/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <set>
#include <sstream>

namespace imgmesh {
namespace {

// --- a minimal PNG encoder (stored deflate blocks) for SVG backgrounds -----
std::uint32_t crc32(const std::uint8_t* d, std::size_t n, std::uint32_t c = 0xffffffffu) {
  static std::uint32_t table[256];
  static bool init = false;
  if (!init) {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t k = i;
      for (int j = 0; j < 8; ++j) k = (k & 1) ? 0xedb88320u ^ (k >> 1) : k >> 1;
      table[i] = k;
    }
    init = true;
  }
  for (std::size_t i = 0; i < n; ++i) c = table[(c ^ d[i]) & 0xff] ^ (c >> 8);
  return c;
}

void be32(std::string& s, std::uint32_t v) {
  for (int i = 3; i >= 0; --i) s.push_back(char((v >> (8 * i)) & 0xff));
}

void chunk(std::string& png, const char* type, const std::string& data) {
  be32(png, std::uint32_t(data.size()));
  std::string body = std::string(type, 4) + data;
  png += body;
  be32(png, crc32(reinterpret_cast<const std::uint8_t*>(body.data()), body.size()) ^ 0xffffffffu);
}

// Grey, or RGB when bg.rgb holds the pixels.
std::string background_png(const SvgBackground& bg) {
  const bool colour = bg.rgb.size() == 3 * bg.width * bg.height;
  const std::vector<std::uint8_t>& px = colour ? bg.rgb : bg.grey;
  const std::size_t row = (colour ? 3 : 1) * bg.width;
  std::string raw;
  raw.reserve((row + 1) * bg.height);
  for (std::size_t r = 0; r < bg.height; ++r) {
    raw.push_back(0);  // filter: none
    raw.append(reinterpret_cast<const char*>(px.data()) + r * row, row);
  }
  std::string z = "\x78\x01";
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  for (std::size_t pos = 0; pos < raw.size() || pos == 0;) {
    const std::size_t len = std::min<std::size_t>(65535, raw.size() - pos);
    z.push_back(pos + len >= raw.size() ? 1 : 0);
    z.push_back(char(len & 0xff));
    z.push_back(char(len >> 8));
    z.push_back(char(~len & 0xff));
    z.push_back(char((~len >> 8) & 0xff));
    z.append(raw, pos, len);
    pos += len;
    if (len == 0) break;
  }
  be32(z, (b << 16) | a);
  std::string png = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  be32(ihdr, std::uint32_t(bg.width));
  be32(ihdr, std::uint32_t(bg.height));
  ihdr += std::string(colour ? "\x08\x02\x00\x00\x00" : "\x08\x00\x00\x00\x00", 5);  // 8-bit grey or RGB
  chunk(png, "IHDR", ihdr);
  chunk(png, "IDAT", z);
  chunk(png, "IEND", "");
  return png;
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t v = (std::uint8_t(in[i]) << 16) | (std::uint8_t(in[i + 1]) << 8) | std::uint8_t(in[i + 2]);
    for (int k = 3; k >= 0; --k) out.push_back(t[(v >> (6 * k)) & 63]);
  }
  if (i < in.size()) {
    std::uint32_t v = std::uint8_t(in[i]) << 16;
    if (i + 1 < in.size()) v |= std::uint8_t(in[i + 1]) << 8;
    out.push_back(t[(v >> 18) & 63]);
    out.push_back(t[(v >> 12) & 63]);
    out.push_back(i + 1 < in.size() ? t[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}


std::string hex(const std::array<std::uint8_t, 3>& c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c[0], c[1], c[2]);
  return buf;
}

// Blue (low) to yellow (high), roughly viridis.
std::array<std::uint8_t, 3> ramp(double t) {
  static const double stops[5][3] = {{0.27, 0.00, 0.33}, {0.23, 0.32, 0.55}, {0.13, 0.57, 0.55},
                                     {0.37, 0.79, 0.38}, {0.99, 0.91, 0.14}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 4;
  const int i = std::min(3, int(t));
  const double f = t - i;
  std::array<std::uint8_t, 3> c{};
  for (int k = 0; k < 3; ++k)
    c[std::size_t(k)] = std::uint8_t(std::lround(255 * (stops[i][k] + f * (stops[i + 1][k] - stops[i][k]))));
  return c;
}

std::array<std::uint8_t, 3> darker(std::array<std::uint8_t, 3> c, double factor = 0.45) {
  for (auto& v : c) v = std::uint8_t(v * factor);
  return c;
}

double region_of(const PlanarMesh& m, std::size_t e) {
  return m.element_attributes.empty() || m.element_attributes[e].empty() ? 0.0 : m.element_attributes[e][0];
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// XML text: the few characters that need escaping.
std::string xml(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  return out;
}

// The labels of the elements' regions and of the regional points.
std::set<long> labels_of(const PlanarMesh& m) {
  std::set<long> regions;
  for (std::size_t i = 0; i < m.elements.size(); ++i) regions.insert(std::lround(region_of(m, i)));
  for (const auto& r : m.regions) regions.insert(std::lround(r.attribute));
  return regions;
}

bool has_scalar(const PlanarMesh& m, const PlanarWriteOptions& opt) {
  return opt.element_scalar.size() == m.elements.size() && !m.elements.empty();
}

// The page: the world box (x0, y0)-(x1, y1) scaled to the picture's width,
// with room for the title above it and the legend below.
struct Page {
  static constexpr double margin = 10, top = 30, bottom = 46;
  double x0, y0, x1, y1;
  double w, h;  // the box's size
  double s;     // pixels a world unit
  double W, H;  // the page's size
  // World y points up, SVG y down.
  double X(double x) const { return (x - x0) * s + margin; }
  double Y(double y) const { return (y1 - y) * s + top; }
};

Page page_of(const std::array<double, 4>& box, double width_px) {
  Page p{box[0], box[1], box[2], box[3], 0, 0, 0, 0, 0};
  p.w = std::max(p.x1 - p.x0, 1e-300);
  p.h = std::max(p.y1 - p.y0, 1e-300);
  p.s = width_px / p.w;
  p.W = width_px + 2 * Page::margin;
  p.H = p.h * p.s + Page::top + Page::margin + Page::bottom;
  return p;
}

// The counts (or the title asked for) and the scalar's min and mean.
std::string title_of(const PlanarMesh& m, const PlanarWriteOptions& opt) {
  std::string title = opt.svg_title.empty() ? svg_counts(m) : opt.svg_title;
  if (opt.svg_title.empty() && has_scalar(m, opt)) {
    double sum = 0;
    for (double v : opt.element_scalar) sum += v;
    title += "; " + opt.scalar_name + " min " +
             number(*std::min_element(opt.element_scalar.begin(), opt.element_scalar.end())) + ", mean " +
             number(sum / double(opt.element_scalar.size()));
  }
  return title;
}

void write_background(std::ostream& o, const Page& page, const SvgBackground& bg) {
  // Pixel (c, r) covers [c, c+1] x [r, r+1] in image units; map to the page.
  const double ox = bg.origin[0] - 0.5 * bg.column[0] - 0.5 * bg.row[0];
  const double oy = bg.origin[1] - 0.5 * bg.column[1] - 0.5 * bg.row[1];
  char buf[320];
  std::snprintf(buf, sizeof buf, "<image transform=\"matrix(%.9g %.9g %.9g %.9g %.9g %.9g)\" ",
                bg.column[0] * page.s, -bg.column[1] * page.s, bg.row[0] * page.s, -bg.row[1] * page.s,
                page.X(ox), page.Y(oy));
  o << buf << "width=\"" << bg.width << "\" height=\"" << bg.height
    << "\" preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" xlink:href=\"data:image/png;base64,"
    << base64(background_png(bg)) << "\"/>\n";
}

// How elements are filled: by the scalar over [lo, hi] (the options' ends,
// else its range), or by their regions' tints.
struct Fill {
  bool scalar = false;
  double lo = 0, hi = 0;
  std::set<long> regions;
  // Regions told apart by their edges' dark tints in a scalar picture.
  bool tinted_edges() const { return scalar && regions.size() > 1; }
};

Fill fill_of(const PlanarMesh& m, const PlanarWriteOptions& opt) {
  Fill f;
  f.scalar = has_scalar(m, opt);
  f.lo = opt.scalar_min;
  f.hi = opt.scalar_max;
  if (f.scalar && !(std::isfinite(f.lo) && std::isfinite(f.hi) && f.hi > f.lo)) {
    f.lo = *std::min_element(opt.element_scalar.begin(), opt.element_scalar.end());
    f.hi = *std::max_element(opt.element_scalar.begin(), opt.element_scalar.end());
    if (!(f.hi > f.lo)) f.hi = f.lo + 1;
  }
  f.regions = labels_of(m);
  return f;
}

void write_elements(std::ostream& o, const Page& page, const PlanarMesh& m, const PlanarWriteOptions& opt,
                    const Fill& fill) {
  char buf[320];
  o << "<g stroke-width=\"" << (fill.tinted_edges() ? "1" : "0.5") << "\" stroke-linejoin=\"round\">\n";
  for (std::size_t i = 0; i < m.elements.size(); ++i) {
    o << "<polygon points=\"";
    for (int v : m.elements[i]) {
      std::snprintf(buf, sizeof buf, "%.2f,%.2f ", page.X(m.points[std::size_t(v)][0]), page.Y(m.points[std::size_t(v)][1]));
      o << buf;
    }
    const auto tint = region_tint(std::lround(region_of(m, i)));
    const std::string colour =
        fill.scalar ? hex(ramp((opt.element_scalar[i] - fill.lo) / (fill.hi - fill.lo))) : hex(tint);
    o << "\" fill=\"" << colour << "\" stroke=\"" << (fill.tinted_edges() ? hex(darker(tint, 0.8)) : "#333333")
      << "\"/>\n";
  }
  o << "</g>\n";
}

// The segments, the image rectangle's (marker 1) blue, the others red.
void write_segments(std::ostream& o, const Page& page, const PlanarMesh& m) {
  char buf[320];
  o << "<g stroke-width=\"1.5\" stroke-linecap=\"round\">\n";
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    const auto& a = m.points[std::size_t(m.segments[i][0])];
    const auto& b = m.points[std::size_t(m.segments[i][1])];
    const int mk = m.segment_markers.empty() ? 0 : m.segment_markers[i];
    std::snprintf(buf, sizeof buf, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\"/>\n",
                  page.X(a[0]), page.Y(a[1]), page.X(b[0]), page.Y(b[1]), mk == 1 ? "#0000cc" : "#dd0000");
    o << buf;
  }
  o << "</g>\n";
}

// The colour scale's width in the legend.
double scale_width(const Page& page) { return std::min(300.0, page.W - 2 * Page::margin - 160); }

// The colour scale with five ticks, at height ly.
void write_scale_legend(std::ostream& o, const Page& page, double ly, const std::string& name, const Fill& fill) {
  char buf[320];
  o << "<defs><linearGradient id=\"scale\">";
  for (int k = 0; k <= 8; ++k) o << "<stop offset=\"" << k / 8.0 << "\" stop-color=\"" << hex(ramp(k / 8.0)) << "\"/>";
  o << "</linearGradient></defs>\n";
  const double bw = scale_width(page), margin = Page::margin;
  std::snprintf(buf, sizeof buf,
                "<text x=\"%.2f\" y=\"%.2f\" font-size=\"12\">%s</text>\n"
                "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"12\" fill=\"url(#scale)\" stroke=\"#333333\" "
                "stroke-width=\"0.5\"/>\n",
                margin, ly + 10, xml(name).c_str(), margin + 120, ly, bw);
  o << buf;
  for (int k = 0; k <= 4; ++k) {
    std::snprintf(buf, sizeof buf, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"11\" text-anchor=\"middle\">%s</text>\n",
                  margin + 120 + bw * k / 4, ly + 26, number(fill.lo + (fill.hi - fill.lo) * k / 4).c_str());
    o << buf;
  }
}

// The regions' tints (in a scalar picture, the tints of their edges), after
// the colour scale if any, as many as fit (at most 12).
void write_region_legend(std::ostream& o, const Page& page, double ly, const Fill& fill) {
  char buf[320];
  double x = fill.scalar ? Page::margin + 120 + scale_width(page) + 30 : Page::margin;
  int shown = 0;
  for (long r : fill.regions) {
    if (++shown > 12 || x + 90 > page.W) {
      std::snprintf(buf, sizeof buf, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"12\">...</text>\n", x, ly + 10);
      o << buf;
      break;
    }
    std::snprintf(buf, sizeof buf,
                  "<rect x=\"%.2f\" y=\"%.2f\" width=\"12\" height=\"12\" fill=\"%s\" stroke=\"%s\"/>"
                  "<text x=\"%.2f\" y=\"%.2f\" font-size=\"12\">label %ld</text>\n",
                  x, ly, hex(fill.scalar ? darker(region_tint(r), 0.8) : region_tint(r)).c_str(),
                  hex(darker(region_tint(r))).c_str(), x + 16, ly + 10, r);
    o << buf;
    x += 90;
  }
}

} // namespace

namespace planar_detail {

std::array<double, 4> svg_frame(const PlanarMesh& m, const PlanarWriteOptions& opt) {
  struct Box {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    void grow(const Point2& p) {
      x0 = std::min(x0, p[0]); x1 = std::max(x1, p[0]);
      y0 = std::min(y0, p[1]); y1 = std::max(y1, p[1]);
    }
  } all, fg;  // the whole picture, the foreground
  for (const auto& p : m.points) all.grow(p);
  for (std::size_t i = 0; i < m.elements.size(); ++i)
    if (region_of(m, i) != 0)
      for (int v : m.elements[i]) fg.grow(m.points[std::size_t(v)]);
  for (std::size_t i = 0; i < m.segments.size(); ++i)
    if (m.segment_markers.empty() || m.segment_markers[i] != 1)
      for (int v : m.segments[i]) fg.grow(m.points[std::size_t(v)]);
  const SvgBackground* bg = opt.background;
  if (bg && bg->width && bg->height) {
    for (double c : {-0.5, bg->width - 0.5})
      for (double r : {-0.5, bg->height - 0.5})
        all.grow({bg->origin[0] + c * bg->column[0] + r * bg->row[0], bg->origin[1] + c * bg->column[1] + r * bg->row[1]});
  }
  double x0 = all.x0, y0 = all.y0, x1 = all.x1, y1 = all.y1;
  if (x0 > x1) { x0 = y0 = 0; x1 = y1 = 1; }
  // The frame: the foreground with a margin of a tenth of its size (at least
  // 2% of the whole), within the whole picture.
  if (opt.svg_frame_foreground && fg.x0 <= fg.x1 && (fg.x0 > x0 || fg.x1 < x1 || fg.y0 > y0 || fg.y1 < y1)) {
    const double pad = std::max(0.1 * std::max(fg.x1 - fg.x0, fg.y1 - fg.y0), 0.02 * std::max(x1 - x0, y1 - y0));
    x0 = std::max(x0, fg.x0 - pad); x1 = std::min(x1, fg.x1 + pad);
    y0 = std::max(y0, fg.y0 - pad); y1 = std::min(y1, fg.y1 + pad);
  }
  return {x0, y0, x1, y1};
}

} // namespace planar_detail

std::array<std::uint8_t, 3> region_tint(long label) {
  // Label 0 (background) light grey; others ten tints apart in hue and
  // lightness (Tableau 10, lightened), cycling.
  static const std::uint8_t palette[10][3] = {{143, 184, 222}, {245, 163, 92},  {127, 201, 127}, {229, 115, 115},
                                              {179, 157, 219}, {188, 150, 130}, {244, 143, 177}, {197, 225, 122},
                                              {128, 222, 234}, {255, 214, 102}};
  if (label == 0) return {226, 226, 226};
  const long k = ((label - 1) % 10 + 10) % 10;
  return {palette[k][0], palette[k][1], palette[k][2]};
}

std::string svg_counts(const PlanarMesh& m) {
  std::size_t tri = 0, quad = 0;
  for (const auto& e : m.elements) (e.size() == 3 ? tri : quad) += 1;
  const std::set<long> regions = labels_of(m);
  std::ostringstream s;
  s << m.points.size() << " vertices";
  if (tri) s << ", " << tri << " triangles";
  if (quad) s << ", " << quad << " quads";
  s << ", " << m.segments.size() << " segments, ";
  if (!m.regions.empty()) s << m.regions.size() << " regional points, ";
  s << regions.size() << " label" << (regions.size() == 1 ? "" : "s");
  return s.str();
}

void write_svg(const std::string& path, const PlanarMesh& m, const PlanarWriteOptions& opt) {
  const Page page = page_of(planar_detail::svg_frame(m, opt), opt.svg_width_px);
  const double margin = Page::margin, top = Page::top;
  AtomicOutput out(path);
  auto& o = out.stream();
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
                "width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.3f %.3f\" font-family=\"sans-serif\">\n",
                page.W, page.H, page.W, page.H);
  o << buf << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << margin << "\" y=\"20\" font-size=\"14\">" << xml(title_of(m, opt)) << "</text>\n";
  // The drawing, clipped to its frame.
  std::snprintf(buf, sizeof buf,
                "<clipPath id=\"frame\"><rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\"/></clipPath>\n"
                "<g clip-path=\"url(#frame)\">\n",
                margin, top, page.w * page.s, page.h * page.s);
  o << buf;
  const SvgBackground* bg = opt.background;
  if (bg && bg->width && bg->height &&
      (bg->grey.size() == bg->width * bg->height || bg->rgb.size() == 3 * bg->width * bg->height))
    write_background(o, page, *bg);
  const Fill fill = fill_of(m, opt);
  if (!m.elements.empty()) write_elements(o, page, m, opt, fill);
  if (!m.segments.empty()) write_segments(o, page, m);
  o << "</g>\n";
  std::snprintf(buf, sizeof buf, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"none\" "
                "stroke=\"#888888\"/>\n", margin, top, page.w * page.s, page.h * page.s);
  o << buf;
  // The legend, under the drawing.
  const double ly = top + page.h * page.s + 12;
  if (fill.scalar) write_scale_legend(o, page, ly, opt.scalar_name, fill);
  if (!fill.regions.empty() && (!fill.scalar || fill.regions.size() > 1)) write_region_legend(o, page, ly, fill);
  o << "</svg>\n";
  out.commit();
}

} // namespace imgmesh
