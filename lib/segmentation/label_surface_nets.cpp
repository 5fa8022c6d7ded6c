// mesh_label_surface_nets: a short driver of the stages label_surface_nets.hpp
// names; each stage is a library call of lib/wellcomposed or lib/surfacenets.
#include "segmentation/label_surface_nets.hpp"

#include "mesh/surface_certificate.hpp"
#include "mesh/topology.hpp"
#include "segmentation/label_surfaces.hpp"
#include "surfacenets/surface_nets.hpp"
#include "util/error.hpp"
#include "wellcomposed/interface_complex.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace imgmesh {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& u, const Vec3& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}
double dot(const Vec3& u, const Vec3& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

// The chosen labels kept, every other value background.
void keep_labels(LabelImage& image, const std::vector<long long>& labels) {
  for (std::int32_t& v : image.data)
    if (v != 0 && !std::binary_search(labels.begin(), labels.end(), (long long)v)) v = 0;
}

// One label's closed surface with its own vertices (numbered in order of
// first use), oriented out of it.
SurfaceMesh label_surface(const InterfaceMesh& m, std::int32_t label) {
  SurfaceMesh s;
  std::vector<int> index(m.points.size(), -1);
  for (auto t : label_triangles(m, label)) {
    for (int& v : t) {
      if (index[std::size_t(v)] < 0) {
        index[std::size_t(v)] = int(s.points.size());
        s.points.push_back(m.points[std::size_t(v)]);
      }
      v = index[std::size_t(v)];
    }
    s.triangles.push_back(t);
  }
  return s;
}

// The indicator of `label` on its box grown by one voxel (within the grid),
// in the world frame of the image: the grid its voxel boundary is certified on.
BinaryImage label_crop(const LabelImage& image, std::int32_t label, const VoxelBox& box) {
  Index3 lo, hi;
  Geometry g = image.geometry();
  for (int a = 0; a < 3; ++a) {
    lo[std::size_t(a)] = std::max<std::ptrdiff_t>(0, box.lo[std::size_t(a)] - 1);
    hi[std::size_t(a)] = std::min<std::ptrdiff_t>(std::ptrdiff_t(image.size[std::size_t(a)]) - 1, box.hi[std::size_t(a)] + 1);
    g.size[std::size_t(a)] = std::size_t(hi[std::size_t(a)] - lo[std::size_t(a)] + 1);
  }
  g.origin = image.world(double(lo[0]), double(lo[1]), double(lo[2]));
  BinaryImage b(g, 0);
  for (std::size_t z = 0; z < g.size[2]; ++z)
    for (std::size_t y = 0; y < g.size[1]; ++y)
      for (std::size_t x = 0; x < g.size[0]; ++x)
        b(x, y, z) = image(x + std::size_t(lo[0]), y + std::size_t(lo[1]), z + std::size_t(lo[2])) == label;
  return b;
}

// The figures of one label's surface, and its certificate: lib/mesh's
// surface certificate against the label's voxel boundary. The one call
// site of the certificate: the interface certificate (per label, per
// interface, crossings) takes its place when it lands.
LabelNet certify_label(const InterfaceMesh& m, const LabelImage& image, std::int32_t label, std::size_t voxels,
                       const VoxelBox& box) {
  LabelNet n;
  n.label = label;
  n.voxels = voxels;
  n.voxel_volume = double(voxels) * image.spacing[0] * image.spacing[1] * image.spacing[2];
  const SurfaceMesh s = label_surface(m, label);
  n.triangles = s.triangles.size();
  for (const auto& t : s.triangles) {
    const Vec3 &a = s.points[std::size_t(t[0])], &b = s.points[std::size_t(t[1])], &c = s.points[std::size_t(t[2])];
    const Vec3 normal = cross(sub(b, a), sub(c, a));
    n.area += std::sqrt(dot(normal, normal)) / 2;
    n.volume += dot(a, cross(b, c)) / 6;
  }
  const BinaryImage crop = label_crop(image, label, box);
  const VoxelBoundary boundary = voxel_boundary(crop);
  const SurfaceCertificate c = certify_surface(s.points, s.triangles, crop, boundary, mesh_topology(boundary));
  n.euler = c.topology.sorted_euler();
  n.failure = c.failure();
  return n;
}

// The output: every triangle once with its pair, or each label's surface alone.
SurfaceMesh output_mesh(InterfaceMesh& m, const std::vector<long long>& labels, bool separate) {
  SurfaceMesh out;
  if (!separate) {
    out.points = std::move(m.points);
    out.triangles = std::move(m.triangles);
    out.interfaces.reserve(out.triangles.size());
    for (std::size_t t = 0; t < out.triangles.size(); ++t) {
      const auto l = m.triangle_labels(t);
      out.interfaces.push_back({int(l[0]), int(l[1])});
    }
    return out;
  }
  for (long long label : labels) {
    const SurfaceMesh s = label_surface(m, std::int32_t(label));
    const int base = int(out.points.size());
    out.points.insert(out.points.end(), s.points.begin(), s.points.end());
    for (const auto& t : s.triangles) out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    out.labels.insert(out.labels.end(), s.triangles.size(), int(label));
  }
  return out;
}

} // namespace

LabelSurfaceNetsResult mesh_label_surface_nets(LabelImage image, const LabelSurfaceNetsOptions& opt) {
  if (opt.smooth_rounds < 0) throw Error("the smoothing rounds must be 0 or more");
  const auto say = [&](const std::string& what) {
    if (opt.progress) opt.progress(what);
  };
  LabelSurfaceNetsResult res;
  res.smooth_rounds = opt.smooth_rounds;
  res.separate = opt.separate;

  auto t0 = Clock::now();
  say("repairing the partition");
  const std::vector<long long> labels = chosen_labels(image, opt.labels);
  keep_labels(image, labels);
  PartitionResult partition = make_well_composed_partition(std::move(image));
  if (const std::string why = partition.failed_guarantee(); !why.empty())
    throw Error("the partition repair failed: " + why);
  const LabelImage& wc = partition.image;
  res.changed = partition.changed;
  res.grid = wc.size;
  res.seconds.push_back({"repair", since(t0)});

  t0 = Clock::now();
  say("interface complex");
  const InterfaceComplex k = interface_complex(wc);
  res.complex = k.to_json();
  res.seconds.push_back({"complex", since(t0)});

  t0 = Clock::now();
  say("surface nets");
  InterfaceMesh m = interface_mesh(wc, k);
  res.seconds.push_back({"mesh", since(t0)});

  t0 = Clock::now();
  say("smoothing");
  if (opt.smooth_rounds > 0) {
    SmoothingOptions so;
    so.rounds = opt.smooth_rounds;
    smooth_interface_mesh(m, so);
  }
  res.seconds.push_back({"smoothing", since(t0)});

  t0 = Clock::now();
  say("certificate");
  std::vector<std::size_t> voxels;
  std::vector<VoxelBox> boxes;
  label_boxes(wc, labels, voxels, boxes);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    res.labels.push_back(certify_label(m, wc, std::int32_t(labels[i]), voxels[i], boxes[i]));
    if (const auto it = opt.names.find(labels[i]); it != opt.names.end()) {
      res.labels.back().name = it->second;
      res.mesh.label_names[int(labels[i])] = it->second;
    }
  }
  res.seconds.push_back({"certificate", since(t0)});

  auto names = std::move(res.mesh.label_names);
  res.mesh = output_mesh(m, labels, opt.separate);
  res.mesh.label_names = std::move(names);
  return res;
}

Json LabelSurfaceNetsResult::to_json() const {
  Json st = Json::object();
  st["mode"] = separate ? "fast, separate" : "fast";
  st["vertices"] = mesh.points.size();
  st["triangles"] = mesh.triangles.size();
  st["smooth_rounds"] = smooth_rounds;
  st["repair_changed"] = changed;
  st["grid"] = std::vector<std::size_t>{grid[0], grid[1], grid[2]};
  st["interface_complex"] = complex;
  Json times = Json::object();
  for (const auto& [stage, s] : seconds) times[stage] = s;
  st["stage_seconds"] = times;
  bool all = true;
  Json per = Json::array();
  for (const LabelNet& l : labels) {
    Json j = Json::object();
    j["label"] = l.label;
    if (!l.name.empty()) j["name"] = l.name;
    j["voxels"] = l.voxels;
    j["triangles"] = l.triangles;
    j["area"] = l.area;
    j["volume"] = l.volume;
    j["voxel_volume"] = l.voxel_volume;
    j["volume_ratio"] = l.voxel_volume > 0 ? l.volume / l.voxel_volume : 0.0;
    j["components"] = l.euler.size();
    j["euler"] = l.euler;
    j["certified"] = l.failure.empty();
    if (!l.failure.empty()) j["failure"] = l.failure;
    all = all && l.failure.empty();
    per.push_back(j);
  }
  st["all_certified"] = all;
  st["labels"] = per;
  return st;
}

std::string LabelSurfaceNetsResult::failed_guarantee() const {
  for (const LabelNet& l : labels)
    if (!l.failure.empty()) return "label " + std::to_string(l.label) + ": " + l.failure;
  return "";
}

} // namespace imgmesh
