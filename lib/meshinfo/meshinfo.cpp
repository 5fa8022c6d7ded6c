#include "meshinfo/meshinfo.hpp"

#include "mesh/surface_io.hpp"
#include "mesh/triangle_quality.hpp"
#include "mesh/voxel_sides.hpp"
#include "meshinfo/label_report.hpp"
#include "meshinfo/tet_labels.hpp"
#include "planar/image_pslg.hpp"
#include "planar/planar_formats.hpp"
#include "quad/quality.hpp"
#include "util/atomic_file.hpp"
#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/path.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace imgmesh {

namespace {

// OFF with any polygons and real z (the planar reader drops z, OpenMesh's
// wants triangles). '#' comments; "OFF" header; counts; vertices; faces.
PolyMesh read_off_polygons(const std::string& path) {
  const std::string text = read_all(path);
  std::istringstream in(text);
  std::vector<std::string> tok;
  std::vector<int> tok_line;  // the line of each token, for errors
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto h = line.find('#');
    if (h != std::string::npos) line.resize(h);
    std::istringstream ls(line);
    std::string w;
    while (ls >> w) {
      tok.push_back(w);
      tok_line.push_back(number);
    }
  }
  std::size_t k = 0;
  auto next = [&](const char* what) -> const std::string& {
    if (k >= tok.size()) throw Error(std::string("truncated OFF file (expected ") + what + ")", path);
    return tok[k++];
  };
  auto fail = [&](const std::string& what) {
    throw Error("line " + std::to_string(tok_line[k - 1]) + ": " + what, path);
  };
  auto integer = [&](const char* what, long long lo, long long hi) {
    const std::string& s = next(what);
    char* end = nullptr;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (end == s.c_str() || *end || v < lo || v > hi) fail(std::string("bad ") + what + " '" + s + "'");
    return v;
  };
  auto coordinate = [&] {
    const std::string& s = next("a vertex coordinate");
    double v;
    if (!parse_coordinate(s, v)) fail(coordinate_error(s));
    return v;
  };
  if (tok.empty() || tok[0] != "OFF") throw Error("not an OFF file (no OFF header)", path);
  k = 1;
  const long long nv = integer("vertex count", 0, 1LL << 31), nf = integer("face count", 0, 1LL << 31);
  integer("edge count", 0, 1LL << 40);
  // Each vertex needs 3 numbers and each face at least 4: refuse impossible
  // counts before allocating (a bogus header must not eat the memory).
  if (std::size_t(nv) * 3 + std::size_t(nf) * 4 > tok.size()) throw Error("truncated OFF file (fewer numbers than the counts say)", path);
  PolyMesh m;
  m.format = "off";
  m.points.resize(std::size_t(nv));
  for (auto& p : m.points)
    for (double& c : p) c = coordinate();
  m.faces.resize(std::size_t(nf));
  for (auto& f : m.faces) {
    const long long n = integer("face size", 3, 1 << 20);
    f.resize(std::size_t(n));
    for (int& v : f) v = int(integer("vertex id", 0, nv - 1));
    // Colour values may follow on the same line: they were tokenised away
    // with the line structure, so OFF colours are not supported here.
  }
  if (k != tok.size()) throw Error("unexpected data after the faces (face colours are not supported)", path);
  check_extent(m.points, path);
  return m;
}

} // namespace

PolyMesh poly_mesh(const SurfaceMesh& s, const std::string& format) {
  PolyMesh m;
  m.format = format;
  m.points = s.points;
  for (const auto& t : s.triangles) m.faces.push_back({t[0], t[1], t[2]});
  for (const auto& p : s.interfaces) m.interfaces.push_back({std::int32_t(p[0]), std::int32_t(p[1])});
  return m;
}

PolyMesh read_poly_mesh(const std::string& path) {
  const std::string ext = path == "-" ? ".off" : extension_of(path);
  if (ext == ".off") {
    PolyMesh m = read_off_polygons(path);
    m.planar = std::all_of(m.points.begin(), m.points.end(), [](const auto& p) { return p[2] == 0; });
    return m;
  }
  if (ext == ".ele") {
    const PlanarMesh pm = read_planar_mesh(path);
    PolyMesh m;
    m.format = "ele";
    m.planar = true;
    for (const auto& p : pm.points) m.points.push_back({p[0], p[1], 0.0});
    m.faces = pm.elements;
    if (!pm.element_attributes.empty())
      for (std::size_t e = 0; e < pm.elements.size(); ++e) {
        const auto& a = pm.element_attributes[e];
        const double l = a.empty() ? 0.0 : a[0];
        if (!(std::abs(l) < 2147483647.0) || l != std::round(l))
          throw Error("element " + std::to_string(e) + ": region attribute " + std::to_string(l) +
                      " is not an integer label", path);
        m.region.push_back(std::int32_t(l));
      }
    return m;
  }
  if (ext == ".ply" || ext == ".obj" || ext == ".stl" || ext == ".vtp" || ext == ".vtk")
    return poly_mesh(read_surface(path), ext.substr(1));
  throw Error("unknown mesh format '" + ext + "' (use .off, .ply, .obj, .stl, .vtp, .vtk or .ele)", path);
}

Json mesh_report(const PolyMesh& m) {
  const MeshTopology t = mesh_topology(m.points.size(), m.faces);
  Json j = Json::object();
  // The two keys scripts rely on come first.
  j["components"] = t.components.size();
  j["euler"] = t.euler_list();
  j["format"] = m.format;
  j["vertices"] = m.points.size();
  j["faces"] = m.faces.size();
  std::size_t tris = 0, quads = 0, other = 0;
  for (const auto& f : m.faces) (f.size() == 3 ? tris : f.size() == 4 ? quads : other)++;
  j["triangles"] = tris;
  j["quads"] = quads;
  j["other_polygons"] = other;
  j["planar"] = m.planar;
  const Json tj = t.to_json();
  Json topo = Json::object();
  for (const char* k : {"component_list", "euler_total", "closed", "manifold", "oriented", "boundary_loops",
                        "boundary_edges", "nonmanifold_edges", "nonmanifold_vertices", "inconsistent_edges",
                        "isolated_vertices"})
    topo[k] = tj.at(k);
  j["topology"] = topo;
  // Bounding box.
  if (!m.points.empty()) {
    std::array<double, 3> lo = m.points[0], hi = m.points[0];
    for (const auto& p : m.points)
      for (int i = 0; i < 3; ++i) { lo[i] = std::min(lo[i], p[i]); hi[i] = std::max(hi[i], p[i]); }
    Json bb = Json::object();
    bb["min"] = std::vector<double>(lo.begin(), lo.end());
    bb["max"] = std::vector<double>(hi.begin(), hi.end());
    j["bounding_box"] = bb;
  }
  if (tris) j["triangle_quality"] = triangle_quality_report(m.points, m.faces).to_json();
  if (!m.interfaces.empty() && tris == m.faces.size()) {
    std::vector<std::array<int, 3>> t;
    t.reserve(tris);
    for (const auto& f : m.faces) t.push_back({f[0], f[1], f[2]});
    j["label_surfaces"] = label_report(m.points, t, m.interfaces);
  }
  if (quads && m.planar) {
    std::vector<Point2> pts;
    for (const auto& p : m.points) pts.push_back({p[0], p[1]});
    std::vector<std::array<int, 4>> qs;
    for (const auto& f : m.faces)
      if (f.size() == 4) qs.push_back({f[0], f[1], f[2], f[3]});
    j["quad_quality"] = quality_report(pts, qs).to_json();
  }
  return j;
}

Json image_comparison(const MeshTopology& image, const SurfaceCertificate& cert) {
  Json j = Json::object();
  j["components"] = image.components.size();
  j["euler"] = image.euler_list();
  j["manifold"] = image.manifold;
  j["matches"] = cert.ok();
  j["correspondence"] = cert.correspondence.to_json();
  j["certificate"] = cert.to_json();
  return j;
}

namespace {

// A line per label's surface and per interface (label_report), with the
// interface certificate's voxel volume, verdict and K(X) patches when an
// image was given.
void format_label_surfaces(std::ostream& o, const Json& r) {
  const Json* image = r.contains("interface_image") ? &r.at("interface_image") : nullptr;
  auto in_image = [&](const char* list, const char* key, const Json& value) -> const Json* {
    if (!image) return nullptr;
    for (const Json& e : image->at(list).items())
      if (e.at(key).kind() == value.kind() && (value.kind() == Json::Kind::String ? e.at(key).string() == value.string()
                                                                                   : e.at(key).integer() == value.integer()))
        return &e;
    return nullptr;
  };
  const Json& ls = r.at("label_surfaces");
  char buf[512];
  for (const Json& l : ls.at("labels").items()) {
    std::vector<long long> euler;
    for (const Json& e : l.at("euler").items()) euler.push_back(e.integer());
    const long long label = l.at("label").integer();
    std::snprintf(buf, sizeof buf, "label %-6lld %lld triangles, %lld component(s), euler ", label,
                  l.at("triangles").integer(), l.at("components").integer());
    o << buf << euler_summary(euler);
    std::snprintf(buf, sizeof buf, ", %s %s %s, area %.6g, volume %.6g, smallest angle %.2f",
                  l.at("closed").boolean() ? "closed" : "NOT CLOSED", l.at("manifold").boolean() ? "manifold" : "NON-MANIFOLD",
                  l.at("oriented").boolean() ? "oriented" : "NOT ORIENTED", l.at("area").number(), l.at("volume").number(),
                  l.at("min_angle").number());
    o << buf << (label == 0 ? " (the labels' union)" : "");
    if (const Json* c = in_image("labels", "label", l.at("label"))) {
      std::snprintf(buf, sizeof buf, "; voxels' volume %.6g, certificate %s", c->at("voxel_volume").number(),
                    c->at("verdict").string() == "ok" ? "holds" : c->at("verdict").string().c_str());
      o << buf;
    }
    o << "\n";
  }
  for (const Json& i : ls.at("interfaces").items()) {
    std::snprintf(buf, sizeof buf, "interface %-6s %lld triangles in %lld patch(es), area %.6g, smallest angle %.2f",
                  i.at("pair").string().c_str(), i.at("triangles").integer(), i.at("patches").integer(),
                  i.at("area").number(), i.at("min_angle").number());
    o << buf;
    if (const Json* c = in_image("interfaces", "pair", i.at("pair")))
      o << "; K(X) " << c->at("complex_patches").integer() << " patch(es)";
    o << "\n";
  }
}

// The 3D certificate's lines: the verdict, then each check.
void format_certificate(std::ostream& o, const Json& c) {
  const bool ok = c.at("verdict").string() == "ok";
  o << "; mesh " << (ok ? "MATCHES" : "DOES NOT MATCH") << " (certificate " << (ok ? "holds" : "fails") << ")\n";
  o << "certificate";
  const Json& checks = c.at("checks");
  for (std::size_t i = 0; i < checks.keys().size(); ++i) {
    const Json& v = checks.items()[i];
    o << ' ' << checks.keys()[i] << (v.kind() == Json::Kind::Null ? " -" : v.boolean() ? " yes" : " NO") << (i + 1 < checks.keys().size() ? "," : "");
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", c.at("place_tolerance").number());
  o << " (place tolerance " << buf << ")\n";
  if (!ok) o << "  first failure: " << c.at("failure").string() << "\n";
}

// Issue 38's count (not part of the verdict).
void format_voxel_sides(std::ostream& o, const Json& v) {
  o << "voxel sides " << v.at("wrong_side").integer() << " of the " << v.at("voxel_centres_checked").integer()
    << " voxel centres next to bdCA(X) on the wrong side of the mesh (" << v.at("foreground_outside").integer()
    << " foreground outside, " << v.at("background_inside").integer() << " background inside, "
    << v.at("on_surface").integer() << " on it; reported, not certified)\n";
}

} // namespace

std::string format_report(const Json& r) {
  std::ostringstream o;
  char buf[256];
  o << "format      " << r.at("format").string() << (r.at("planar").boolean() ? " (planar)" : "") << "\n";
  o << "vertices    " << r.at("vertices").integer() << "\n";
  o << "faces       " << r.at("faces").integer() << " (" << r.at("triangles").integer() << " triangles, "
    << r.at("quads").integer() << " quads, " << r.at("other_polygons").integer() << " other)\n";
  const Json& t = r.at("topology");
  o << "components  " << r.at("components").integer() << "\n";
  int i = 0;
  for (const Json& c : t.at("component_list").items()) {
    std::snprintf(buf, sizeof buf, "  #%d: V %lld E %lld F %lld, euler %lld, genus %lld, %s, %s, %s, %lld boundary loop(s)\n",
                  i++, c.at("vertices").integer(), c.at("edges").integer(), c.at("faces").integer(),
                  c.at("euler").integer(), c.at("genus").integer(), c.at("closed").boolean() ? "closed" : "open",
                  c.at("manifold").boolean() ? "manifold" : "NON-MANIFOLD",
                  c.at("oriented").boolean() ? "oriented" : (c.at("orientable").boolean() ? "NOT oriented" : "non-orientable"),
                  c.at("boundary_loops").integer());
    o << buf;
    if (i == 20 && t.at("component_list").items().size() > 21) {
      o << "  ... (" << t.at("component_list").items().size() - 20 << " more)\n";
      break;
    }
  }
  o << "closed " << (t.at("closed").boolean() ? "yes" : "no") << ", manifold "
    << (t.at("manifold").boolean() ? "yes" : "no") << ", oriented " << (t.at("oriented").boolean() ? "yes" : "no")
    << ", boundary loops " << t.at("boundary_loops").integer() << ", non-manifold edges "
    << t.at("nonmanifold_edges").integer() << ", non-manifold vertices " << t.at("nonmanifold_vertices").integer()
    << (r.contains("label_surfaces") ? " (all labels' interfaces together: each label's own surface below)" : "")
    << "\n";
  if (r.contains("triangle_quality")) {
    const Json& q = r.at("triangle_quality");
    if (q.contains("min_angle")) {
      std::snprintf(buf, sizeof buf,
                    "triangles   angles %.2f..%.2f deg (mean smallest %.2f), radius-edge max %.3f mean %.3f, area %.4g..%.4g\n",
                    q.at("min_angle").number(), q.at("max_angle").number(), q.at("mean_min_angle").number(),
                    q.at("max_radius_edge_ratio").number(), q.at("mean_radius_edge_ratio").number(),
                    q.at("min_area").number(), q.at("max_area").number());
      o << buf;
    }
  }
  if (r.contains("quad_quality")) {
    const Json& q = r.at("quad_quality");
    std::snprintf(buf, sizeof buf,
                  "quads       non-convex %lld, Joe's mu min %.2f median %.2f mean %.2f, scaled Jacobian min %.3f, "
                  "angles in [45,135] %.1f%%, area mean %.4g sd %.4g\n",
                  q.at("non_convex").integer(), q.at("min_mu").number(), q.at("median_mu").number(),
                  q.at("mean_mu").number(), q.at("min_scaled_jacobian").number(),
                  100 * q.at("angles_45_135").number(), q.at("mean_area").number(), q.at("area_stddev").number());
    o << buf << "  mu histogram:";
    const auto& bins = q.at("mu_histogram").items();
    for (std::size_t i = 0; i < bins.size(); ++i)
      o << " [" << bins[i].at("from").number() << "," << bins[i].at("to").number()
        << (i + 1 == bins.size() ? "] " : ") ") << bins[i].at("count").integer();
    o << "\n";
  }
  if (r.contains("tetrahedra")) {
    const Json& q = r.at("tetrahedra");
    std::snprintf(buf, sizeof buf,
                  "tetrahedra  %lld, conforming %s, radius-edge max %.3f mean %.3f, dihedral %.2f..%.2f deg, "
                  "under 10 deg %.2f%%, volume %.6g\n",
                  q.at("tetrahedra").integer(), q.at("conformity").at("conforming").boolean() ? "yes" : "no",
                  q.at("max_radius_edge_ratio").number(), q.at("mean_radius_edge_ratio").number(),
                  q.at("min_dihedral_degrees").number(), q.at("max_dihedral_degrees").number(),
                  100 * q.at("share_dihedral_under_10").number(), q.at("volume").number());
    o << buf << "  smallest dihedral histogram (10 deg bins):";
    for (const Json& n : q.at("min_dihedral_histogram_10deg").items()) o << ' ' << n.integer();
    o << "\n";
    if (q.contains("volume_by_region") && q.at("volume_by_region").keys().size() > 1) {
      const Json& v = q.at("volume_by_region");
      o << "  volume by region:";
      for (std::size_t i = 0; i < v.keys().size(); ++i) o << ' ' << v.keys()[i] << ": " << v.items()[i].number();
      o << "\n";
    }
    if (q.contains("regions")) {
      for (const Json& g : q.at("regions").items()) {
        std::snprintf(buf, sizeof buf, "  region %lld: %lld tetrahedra, volume %.6g", g.at("region").integer(),
                      g.at("tetrahedra").integer(), g.at("volume").number());
        o << buf;
        if (g.contains("voxel_volume")) {
          std::snprintf(buf, sizeof buf, " against %.6g of voxels (%.4f)", g.at("voxel_volume").number(),
                        g.at("volume_ratio").number());
          o << buf;
        }
        std::snprintf(buf, sizeof buf, ", radius-edge max %.3f, smallest dihedral %.2f deg\n",
                      g.at("max_radius_edge_ratio").number(), g.at("min_dihedral_degrees").number());
        o << buf;
        const Json& b = g.at("boundary");
        auto list = [](const Json& e) {
          std::string s;
          for (const Json& x : e.items()) s += (s.empty() ? "" : " ") + std::to_string(x.integer());
          return s;
        };
        o << "    boundary " << b.at("triangles").integer() << " triangles, " << b.at("components").integer()
          << " component(s), euler " << list(b.at("euler"));
        if (b.contains("voxel_euler"))
          o << "; bdCA " << b.at("voxel_components").integer() << " component(s), euler " << list(b.at("voxel_euler"))
            << ": " << b.at("verdict").string();
        o << "\n";
      }
    }
    if (q.contains("foreground_voxel_volume")) o << "  foreground voxel volume " << q.at("foreground_voxel_volume").number() << "\n";
  }
  if (r.contains("label_surfaces")) format_label_surfaces(o, r);
  if (r.contains("interface_image")) {
    const Json& im = r.at("interface_image");
    o << "labels      " << im.at("labels").items().size() << " (0 the background), interfaces " << im.at("interfaces").items().size()
      << ", repaired voxels " << im.at("repaired_voxels").integer() << "; interface certificate "
      << (im.at("verdict").string() == "ok" ? "HOLDS" : "FAILS: " + im.at("failure").string()) << "\n";
  }
  if (r.contains("certificate")) {  // tetrahedra against a label map
    const Json& c = r.at("certificate");
    const bool ok = c.at("verdict").string() == "ok";
    o << "regions     " << c.at("regions").items().size() << " against " << c.at("labels").items().size()
      << " labels; tetrahedra " << (ok ? "CERTIFIED" : "NOT CERTIFIED") << " against the label map\n";
    o << "certificate";
    const Json& checks = c.at("checks");
    for (std::size_t i = 0; i < checks.keys().size(); ++i) {
      const Json& v = checks.items()[i];
      o << ' ' << checks.keys()[i] << (v.kind() == Json::Kind::Null ? " -" : v.boolean() ? " yes" : " NO")
        << (i + 1 < checks.keys().size() ? "," : "\n");
    }
    if (!ok) o << "  first failure: " << c.at("failure").string() << "\n";
  }
  if (r.contains("image")) {
    const Json& im = r.at("image");
    const bool planar = im.contains("labels");
    const char* bd = planar ? "region" : "bdCA";
    o << (planar ? "regions     " : "bdCA(X)     ") << im.at("components").integer() << " component(s), euler";
    for (const Json& e : im.at("euler").items()) o << ' ' << e.integer();
    if (planar) o << "; mesh " << (im.at("matches").boolean() ? "MATCHES" : "DOES NOT MATCH") << " component by component\n";
    else format_certificate(o, im.at("certificate"));
    if (im.contains("voxel_sides")) format_voxel_sides(o, im.at("voxel_sides"));
    if (im.contains("correspondence")) {
      int m = 0;
      for (const Json& c : im.at("correspondence").at("mesh_components").items()) {
        if (c.at("verdict").string() != "ok") {
          o << "  mesh #" << m << ": " << c.at("verdict").string();
          if (c.at("boundary_component").integer() >= 0)
            o << " (on " << bd << " #" << c.at("boundary_component").integer() << ", euler " << c.at("euler").integer()
              << " vs " << c.at("boundary_euler").integer() << ")";
          o << "\n";
        }
        ++m;
      }
      int b = 0;
      for (const Json& c : im.at("correspondence").at("boundary_components").items())
        if (c.at("verdict").string() == "unmatched")
          o << "  " << bd << " #" << b++ << ": unmatched (euler " << c.at("euler").integer() << ")\n";
        else ++b;
    }
  }
  return o.str();
}

MeshInfo planar_mesh_info(const PolyMesh& mesh, const std::string& mesh_name, const LabelImage& labels,
                          const std::string& image_name, double reach) {
  if (mesh.faces.empty()) throw Error("mesh has no faces", mesh_name);
  if (!mesh.planar) throw Error("a 2D image needs a planar mesh (every z 0)", mesh_name);
  MeshInfo r;
  r.report = naming_input(mesh_name, [&] { return mesh_report(mesh); });
  // Without region labels every face is foreground: one label for the image's too.
  LabelImage fg = labels;
  if (mesh.region.empty())
    for (auto& v : fg.data) v = v != 0;
  const PixelRegions pr = pixel_regions(fg);
  if (pr.label.empty()) throw Error("the image has no foreground", image_name);
  const MeshRegions mr = naming_input(mesh_name, [&] { return mesh_regions(mesh.points.size(), mesh.faces, mesh.region); });
  r.compared = true;
  r.image_name = image_name;
  r.by_place = match_regions(mr, mesh.points, mesh.faces, pr, reach);
  r.matches = r.by_place.matches();
  Json j = Json::object();
  j["components"] = pr.label.size();
  j["euler"] = pr.euler;
  j["labels"] = std::vector<long long>(pr.label.begin(), pr.label.end());
  j["matches"] = r.matches;
  j["correspondence"] = r.by_place.to_json();
  r.report["image"] = j;
  return r;
}

MeshInfo mesh_info(const PolyMesh& mesh, const std::string& mesh_name, const BinaryImage* image,
                   const std::string& image_name, const CertificateOptions& options) {
  if (image && (image->dimension == 2 || image->size[2] == 1)) {
    LabelImage labels(image->geometry());
    for (std::size_t i = 0; i < labels.data.size(); ++i) labels.data[i] = image->data[i] != 0;
    return planar_mesh_info(mesh, mesh_name, well_composed_labels(labels), image_name);
  }
  if (mesh.faces.empty()) throw Error("mesh has no faces", mesh_name);
  MeshInfo r;
  r.report = naming_input(mesh_name, [&] { return mesh_report(mesh); });
  if (!image) return r;
  const MeshTopology it = naming_input(image_name, [&] { return voxel_boundary_topology(*image); });
  if (!it.manifold)
    throw Error("bdCA(X) is not a manifold: the image is not well-composed (run img2wc first)", image_name);
  r.compared = true;
  r.image_name = image_name;
  // Polygons as fans of triangles (the same V - E + F); voxel_boundary_topology
  // counted the same quads.
  std::vector<std::array<int, 3>> triangles;
  for (const auto& f : mesh.faces)
    for (std::size_t k = 1; k + 1 < f.size(); ++k) triangles.push_back({f[0], f[k], f[k + 1]});
  const VoxelBoundary vb = voxel_boundary(*image);
  r.certificate = certify_surface(mesh.points, triangles, *image, vb, mesh_topology(vb), options);
  r.report["image"] = image_comparison(it, r.certificate);
  // Issue 38's count, on a surface with sides (closed, manifold, oriented):
  // reported, not part of the verdict.
  if (r.certificate.state[SurfaceCertificate::kIntersections] >= 0) {
    std::vector<int> component(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
      component[t] = r.certificate.topology.component_of[std::size_t(triangles[t][0])];
    r.report["image"]["voxel_sides"] =
        voxel_sides(mesh.points, triangles, component, r.certificate.topology.components.size(), *image).to_json();
  }
  r.matches = r.certificate.ok();
  return r;
}

MeshInfo interface_mesh_info(const PolyMesh& mesh, const std::string& mesh_name, LabelImage labels,
                             const std::string& image_name, const InterfaceCertificateOptions& options) {
  if (mesh.faces.empty()) throw Error("mesh has no faces", mesh_name);
  if (labels.dimension == 2 || labels.size[2] == 1) throw Error("label pairs are certified against a 3D label image", image_name);
  std::vector<std::array<int, 3>> triangles;
  for (const auto& f : mesh.faces) {
    if (f.size() != 3) throw Error("a mesh with label pairs must be triangles", mesh_name);
    triangles.push_back({f[0], f[1], f[2]});
  }
  MeshInfo r;
  r.report = naming_input(mesh_name, [&] { return mesh_report(mesh); });
  const PartitionResult p = naming_input(image_name, [&] { return make_well_composed_partition(std::move(labels)); });
  if (const std::string why = p.failed_guarantee(); !why.empty()) throw Error("the partition repair failed: " + why, image_name);
  r.compared = r.by_interfaces = true;
  r.image_name = image_name;
  r.interfaces = certify_interface_mesh(mesh.points, triangles, mesh.interfaces, p.image, options);
  r.matches = r.interfaces.ok();
  Json j = r.interfaces.to_json();
  j["repaired_voxels"] = p.changed;
  r.report["interface_image"] = j;
  return r;
}

namespace {

// The boundary triangles on their own vertices (interior ones would count
// as isolated), as a surface for mesh_report.
PolyMesh boundary_surface(const TetMesh& mesh, const std::vector<std::array<int, 3>>& triangles) {
  PolyMesh b;
  b.format = "tetrahedra";
  std::vector<int> index(mesh.points.size(), -1);
  for (const auto& t : triangles) {
    std::vector<int> f;
    for (int v : t) {
      int& k = index[std::size_t(v)];
      if (k < 0) {
        k = int(b.points.size());
        b.points.push_back(mesh.points[std::size_t(v)]);
      }
      f.push_back(k);
    }
    b.faces.push_back(f);
  }
  return b;
}

// The "tetrahedra" section: quality, counts, conformity.
Json tetrahedra_section(const TetMesh& mesh, const TetQualityReport& q, const TetConformity& c) {
  Json tj = q.to_json();
  tj["vertices"] = mesh.points.size();
  tj["boundary_triangles_in_file"] = mesh.triangles.size();
  tj["conformity"] = c.to_json();
  return tj;
}

std::vector<long long> descending(std::vector<long long> v) {
  std::sort(v.rbegin(), v.rend());
  return v;
}

// A region's boundary (the faces of its tetrahedra with none of it
// across): triangles, components, their Euler characteristics. With a
// label certificate, from its surface of that label (the same faces: the
// interfaces out of the label), beside bdCA of the label's voxels and the
// verdict of the label's surface certificate; else from the tetrahedra.
Json region_boundary(const TetMesh& mesh, int region, const InterfaceCertificate* ic) {
  Json b = Json::object();
  const InterfaceCertificate::Label* l = nullptr;
  if (ic && region != 0)  // region 0 (--outside) also bounds the box: not label 0's surface
    for (const auto& x : ic->labels)
      if (x.label == region && x.in_image && x.surface.state[SurfaceCertificate::kClosed] >= 0) l = &x;
  if (!l) {
    const auto triangles = tet_boundary(mesh, region);
    const MeshTopology t = mesh_topology(mesh.points.size(), triangles);
    b["triangles"] = triangles.size();
    b["components"] = t.components.size();
    b["euler"] = descending(t.euler_list());
    return b;
  }
  b["triangles"] = l->triangles;
  b["components"] = l->surface.topology.components.size();
  b["euler"] = descending(l->surface.topology.euler_list());
  std::vector<long long> voxel_euler;
  for (const auto& c : l->surface.correspondence.boundary) voxel_euler.push_back(c.euler);
  b["voxel_components"] = voxel_euler.size();
  b["voxel_euler"] = descending(voxel_euler);
  b["verdict"] = l->surface.ok() ? "ok" : SurfaceCertificate::name(l->surface.first_failed());
  return b;
}

// Per region: tetrahedra, volume, largest radius-edge ratio, smallest
// dihedral, its boundary's topology; with `voxels` (per label, its voxel
// volume) that too.
Json regions_section(const TetMesh& mesh, const TetQualityReport& q, const std::map<std::int32_t, double>* voxels,
                     const InterfaceCertificate* ic) {
  Json a = Json::array();
  for (const auto& [region, g] : q.by_region) {
    Json j = Json::object();
    j["region"] = region;
    j["tetrahedra"] = g.tetrahedra;
    const double volume = q.volume_by_region.at(region);
    j["volume"] = volume;
    if (voxels) {
      const auto v = voxels->find(region);
      const double vv = v == voxels->end() ? 0.0 : v->second;
      j["voxel_volume"] = vv;
      j["volume_ratio"] = vv > 0 ? volume / vv : 0.0;
    }
    j["max_radius_edge_ratio"] = g.max_radius_edge_ratio;
    j["min_dihedral_degrees"] = g.min_dihedral;
    j["boundary"] = region_boundary(mesh, region, ic);
    a.push_back(j);
  }
  return a;
}

} // namespace

MeshInfo tet_mesh_info(const TetMesh& mesh, const std::string& mesh_name, const BinaryImage* image,
                       const std::string& image_name, const CertificateOptions& options) {
  // With region 1 among others (implicit2tet --outside: region 2 fills the
  // box around it), region 1's boundary: the surface of the foreground.
  const bool others = std::any_of(mesh.tet_region.begin(), mesh.tet_region.end(), [](int r) { return r != 1; });
  const bool has1 = std::find(mesh.tet_region.begin(), mesh.tet_region.end(), 1) != mesh.tet_region.end();
  MeshInfo r = mesh_info(boundary_surface(mesh, tet_boundary(mesh, others && has1 ? 1 : 0)), mesh_name, image,
                         image_name, options);
  const TetConformity c = tet_conformity(mesh);
  r.conforming = c.ok();
  const TetQualityReport q = tet_quality(mesh);
  Json tj = tetrahedra_section(mesh, q, c);
  if (image) {
    std::size_t n = 0;
    for (auto v : image->data) n += v != 0;
    const double voxel = image->spacing[0] * image->spacing[1] * (image->dimension == 3 ? image->spacing[2] : 1);
    tj["foreground_voxel_volume"] = double(n) * voxel;
  } else if (q.by_region.size() > 1) {
    tj["regions"] = regions_section(mesh, q, nullptr, nullptr);
  }
  r.report["tetrahedra"] = tj;
  return r;
}

MeshInfo label_tet_mesh_info(const TetMesh& mesh, const std::string& mesh_name, LabelImage labels,
                             const std::string& image_name, const InterfaceCertificateOptions& options) {
  if (mesh.tets.empty()) throw Error("mesh has no tetrahedra", mesh_name);
  if (labels.dimension == 2 || labels.size[2] == 1) throw Error("regions are certified against a 3D label image", image_name);
  const PartitionResult p = naming_input(image_name, [&] { return make_well_composed_partition(std::move(labels)); });
  if (const std::string why = p.failed_guarantee(); !why.empty()) throw Error("the partition repair failed: " + why, image_name);
  const LabelImage& x = p.image;
  MeshInfo r;
  r.compared = r.by_tet_labels = true;
  r.image_name = image_name;
  const TetLabelCertificate cert = certify_tet_labels(mesh, x, options);
  // The report's surface: the regions' interfaces (those the certificate
  // judged, when it could build them).
  std::vector<std::array<int, 3>> triangles = cert.triangles;
  if (triangles.empty()) {
    std::vector<std::array<std::int32_t, 2>> pairs;
    region_interfaces(mesh, triangles, pairs);
  }
  r.report = naming_input(mesh_name, [&] { return mesh_report(boundary_surface(mesh, triangles)); });
  const TetQualityReport q = tet_quality(mesh);
  Json tj = tetrahedra_section(mesh, q, cert.conformity);
  std::map<std::int32_t, double> voxels;
  const double voxel = x.spacing[0] * x.spacing[1] * x.spacing[2];
  for (std::int32_t v : x.data) voxels[v] += voxel;  // 0 too: seg2tet --outside's region 0
  tj["regions"] = regions_section(mesh, q, &voxels,
                                  cert.state[TetLabelCertificate::kInterfaces] >= 0 ? &cert.interfaces : nullptr);
  r.report["tetrahedra"] = tj;
  if (cert.state[TetLabelCertificate::kInterfaces] >= 0 && !cert.triangles.empty()) {
    Json j = cert.interfaces.to_json();
    j["repaired_voxels"] = p.changed;
    r.report["interface_image"] = j;
  }
  r.report["certificate"] = cert.to_json();
  r.matches = cert.ok();
  r.tet_labels_failure = cert.failure();
  return r;
}

Json MeshInfo::to_json() const {
  Json j = Json::object();
  for (const char* k : {"vertices", "faces", "components", "euler"}) j[k] = report.at(k);
  if (compared) j["matches_image"] = matches;
  return j;
}

std::string MeshInfo::failed_guarantee() const {
  if (by_tet_labels)
    return matches ? "" : "the tetrahedra are not certified against the partition of " + image_name + ": " + tet_labels_failure;
  if (!conforming) return "the tetrahedra are not all positively oriented and conforming";
  if (matches) return "";
  if (by_interfaces) return "the mesh is not certified against the partition of " + image_name + ": " + interfaces.failure();
  if (!by_place.planar) return "the mesh is not certified against bdCA(X) of " + image_name + ": " + certificate.failure();
  const std::string why = by_place.failed_guarantee();
  return "the mesh's regions do not match the pixel regions of " + image_name + " component by component" +
         (why.empty() ? "" : ": " + why);
}

} // namespace imgmesh
