// mesh_label_surface_nets: a short driver of the stages label_surface_nets.hpp
// names; each stage is a library call of lib/wellcomposed or lib/surfacenets.
#include "segmentation/label_surface_nets.hpp"

#include "conforming/conforming_surface.hpp"
#include "image/narrow_labels.hpp"
#include "mesh/triangle_quality.hpp"
#include "segmentation/label_surfaces.hpp"
#include "surfacenets/interface_certificate.hpp"
#include "surfacenets/surface_nets.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"
#include "wellcomposed/interface_complex.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace imgmesh {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

template <class T> void release(std::vector<T>& v) { std::vector<T>().swap(v); }

// The chosen labels kept, every other value background.
void keep_labels(LabelImage& image, const std::vector<long long>& labels) {
  for (std::int32_t& v : image.data)
    if (v != 0 && !std::binary_search(labels.begin(), labels.end(), (long long)v)) v = 0;
}

// One label's closed surface with its own vertices (numbered in order of
// first use), oriented out of it (label_triangles' order and orientation).
SurfaceMesh label_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                          const std::vector<std::array<std::int32_t, 2>>& pairs, std::int32_t label) {
  SurfaceMesh s;
  std::vector<int> index(points.size(), -1);
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    if (pairs[f][0] != label && pairs[f][1] != label) continue;
    auto t = triangles[f];
    if (pairs[f][1] == label) std::swap(t[1], t[2]);
    for (int& v : t) {
      if (index[std::size_t(v)] < 0) {
        index[std::size_t(v)] = int(s.points.size());
        s.points.push_back(points[std::size_t(v)]);
      }
      v = index[std::size_t(v)];
    }
    s.triangles.push_back(t);
  }
  return s;
}

// The output: every triangle once with its pair, or each label's surface alone.
// pairs: per triangle, its (behind, front).
SurfaceMesh output_mesh(std::vector<Vec3>& points, std::vector<std::array<int, 3>>& triangles,
                        const std::vector<std::array<std::int32_t, 2>>& pairs, const std::vector<long long>& labels,
                        bool separate) {
  SurfaceMesh out;
  if (!separate) {
    out.points = std::move(points);
    out.triangles = std::move(triangles);
    out.interfaces.assign(pairs.begin(), pairs.end());
    return out;
  }
  for (long long label : labels) {
    const SurfaceMesh s = label_surface(points, triangles, pairs, std::int32_t(label));
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
  // The labelling function's background 0 ranks below every label: a region is a label above 0.
  if (opt.conforming && std::any_of(image.data.begin(), image.data.end(), [](std::int32_t v) { return v < 0; }))
    throw Error("negative label values: a region is a label above 0 (relabel the map)");
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
  // Past K(X) the partition is only read: held in the narrowest type its
  // labels fit (a byte a voxel for up to 255, not 4).
  const Geometry grid = wc.geometry();
  const NarrowLabelImage narrow = narrow_labels(std::move(partition.image));

  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::int32_t, 2>> pairs;
  InterfaceCertificateOptions co;
  co.threads = std::max(1u, opt.threads);
  if (opt.conforming) {
    ConformingOptions o = opt.conforming_options;
    if (!(o.max_distance > 0)) o.max_distance = 0.3 * std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
    t0 = Clock::now();
    say("labelling function");
    const LabelFunction lambda(narrow, o.max_distance, std::max(1u, opt.threads));
    res.seconds.push_back({"function", since(t0)});
    t0 = Clock::now();
    say("conforming surface");
    o.progress = opt.progress;
    o.threads = std::max(1u, opt.threads);
    co.lattice = false;  // not a surface-nets mesh
    // The rounds' certificates without the whole mesh's crossings (their
    // places do not read them; on the brain map a tenth of the time), the
    // one kept gets them once the triangulation is gone.
    InterfaceCertificate last;
    InterfaceCertificateOptions rounds = co;
    rounds.check_crossings = false;
    o.certificate = [&](const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& t,
                        const std::vector<std::array<std::int32_t, 2>>& l) {
      last = certify_interface_mesh(p, t, l, narrow, k, rounds);
      return last.failing_places(p, t, l, k, grid);
    };
    ConformingSurface c = conforming_surface(lambda, narrow, k, o);
    res.conforming = c.to_json();
    if (o.tets.on) {
      res.tetrahedra = true;
      res.tets = std::move(c.tets);
      res.cell_ratio = o.tets.cell_ratio;
      res.cell_refinement_stopped = c.cell_rounds_exhausted || c.cell_points_exhausted || c.max_points_hit;
      res.centres_checked = c.centres_checked;
      res.centres_wrong = c.centres_wrong;
      res.tet_conformity = tet_conformity(res.tets);
      res.tet_quality = tet_quality(res.tets);
      res.tet_boundary_mismatch = boundary_mismatch(res.tets);
      if (o.tets.outside) {
        res.outside = true;
        res.box_volume = c.box_volume;
        res.box_points = c.box_points;
        res.box_refused = c.box_refused;
        res.box_covered = c.box_covered;
        res.box_filled = std::abs(res.tet_quality.total_volume - c.box_volume) <= 1e-9 * c.box_volume;
        const auto zeros = narrow.visit([](const auto& im) { return std::count(im.data.begin(), im.data.end(), 0); });
        res.background_voxel_volume = double(zeros) * grid.spacing[0] * grid.spacing[1] * grid.spacing[2];
      }
    }
    points = std::move(c.points), triangles = std::move(c.triangles), pairs = std::move(c.pairs);
    res.seconds.push_back({"mesh", since(t0)});
    t0 = Clock::now();
    say("certificate");
    // The last round certified this very mesh already: its certificate is
    // kept, its crossings added.
    if (c.certified_as_is) {
      add_crossings(last, points, triangles, pairs, co);
      res.certificate = std::move(last);
    } else {
      res.certificate = certify_interface_mesh(points, triangles, pairs, narrow, k, co);
    }
  } else {
    t0 = Clock::now();
    say("surface nets");
    InterfaceMesh m = interface_mesh(grid, k);
    res.seconds.push_back({"mesh", since(t0)});

    t0 = Clock::now();
    say("smoothing");
    const bool untangled = opt.smooth_rounds > 0;
    if (untangled) {
      SmoothingOptions so;
      so.rounds = opt.smooth_rounds;
      so.untangle = false;  // below, once the relaxation graph is freed
      smooth_interface_mesh(m, so);
    }
    // The relaxation graph served the smoothing only.
    release(m.kind);
    release(m.neighbour_offsets);
    release(m.neighbours);
    if (untangled) untangle_interface_mesh(m, corner_points(m), std::max(1u, opt.threads));
    res.seconds.push_back({"smoothing", since(t0)});

    t0 = Clock::now();
    say("certificate");
    pairs.resize(m.triangles.size());
    for (std::size_t t = 0; t < pairs.size(); ++t) pairs[t] = m.triangle_labels(t);
    release(m.labels);  // per quad: pairs holds them per triangle
    // The whole mesh's crossing pairs, found before the labels' surfaces
    // are built, and what only their search needs (the quads, the corners)
    // freed. Smoothed, there are none: the untangling searched every pair
    // with crossing_pairs' exact test, then after each move every pair at a
    // moved vertex, until none crossed (untangle.cpp: no pair is left
    // unseen); no vertex has moved since, so a second search of every pair
    // would find none (it cost as much as the untangling's first). Unsmoothed (K(X)'s
    // faces) they are searched: local, every vertex in its cell.
    std::vector<std::array<std::size_t, 2>> crossings;
    if (!untangled) crossings = crossing_pairs(m, std::max(1u, opt.threads));
    release(m.quads);
    release(m.corners);
    release_free_memory();  // the smoothing's and the search's pages, before the certificate's threads
    co.crossings = [&] { return std::move(crossings); };
    res.certificate = certify_interface_mesh(m.points, m.triangles, pairs, narrow, k, co);
    co.crossings = nullptr;
    points = std::move(m.points), triangles = std::move(m.triangles);
  }
  for (long long l : labels) {
    res.labels.push_back(std::int32_t(l));
    if (const auto it = opt.names.find(std::int32_t(l)); it != opt.names.end()) {
      res.mesh.label_names[int(l)] = it->second;
      if (res.tetrahedra) res.tets.region_names[int(l)] = it->second;
    }
  }
  res.seconds.push_back({"certificate", since(t0)});

  auto names = std::move(res.mesh.label_names);
  res.mesh = output_mesh(points, triangles, pairs, labels, opt.separate);
  res.mesh.label_names = std::move(names);
  if (opt.conforming) res.conforming["smallest_angle"] = triangle_quality_report(res.mesh).smallest_angle();
  return res;
}

Json LabelSurfaceNetsResult::to_json() const {
  Json st = Json::object();
  st["mode"] = std::string(conforming.kind() == Json::Kind::Object ? "conforming" : "fast") + (separate ? ", separate" : "");
  st["vertices"] = mesh.points.size();
  st["triangles"] = mesh.triangles.size();
  st["smooth_rounds"] = smooth_rounds;
  st["repair_changed"] = changed;
  st["grid"] = std::vector<std::size_t>{grid[0], grid[1], grid[2]};
  st["interface_complex"] = complex;
  if (conforming.kind() == Json::Kind::Object) st["conforming"] = conforming;
  Json times = Json::object();
  for (const auto& [stage, s] : seconds) times[stage] = s;
  st["stage_seconds"] = times;
  bool all = true;
  Json per = Json::array();
  for (const InterfaceCertificate::Label* l : meshed_labels()) {
    Json j = Json::object();
    j["label"] = l->label;
    if (const auto it = mesh.label_names.find(int(l->label)); it != mesh.label_names.end()) j["name"] = it->second;
    j["voxels"] = l->voxels;
    j["triangles"] = l->triangles;
    j["area"] = l->area;
    j["volume"] = l->volume;
    j["voxel_volume"] = l->voxel_volume;
    j["volume_ratio"] = l->voxel_volume > 0 ? l->volume / l->voxel_volume : 0.0;
    const std::vector<long long> euler = l->surface.topology.sorted_euler();
    j["components"] = euler.size();
    j["euler"] = euler;
    j["certified"] = l->surface.ok();
    if (!l->surface.ok()) j["failure"] = l->surface.failure();
    all = all && l->surface.ok();
    per.push_back(j);
  }
  st["all_certified"] = all && certificate.ok();
  st["labels"] = per;
  Json cert = Json::object();  // the interface certificate's verdict (its per-patch lists: meshinfo)
  cert["verdict"] = certificate.ok() ? "ok" : InterfaceCertificate::name(certificate.first_failed());
  if (!certificate.ok()) cert["failure"] = certificate.failure();
  cert["summary"] = certificate.summary();
  cert["interfaces"] = certificate.interfaces.size();
  cert["intersecting_pairs"] = certificate.intersections.pairs - certificate.intersections.degenerate;
  st["certificate"] = cert;
  if (tetrahedra) {
    Json t = Json::object();
    t["tetrahedra"] = tets.tets.size();
    t["vertices"] = tets.points.size();
    t["quality"] = tet_quality.to_json();
    t["conformity"] = tet_conformity.to_json();
    t["boundaries_match"] = tet_boundary_mismatch.empty();
    t["voxel_centres_checked"] = centres_checked;
    t["voxel_centres_wrong"] = centres_wrong;
    if (outside) {
      Json b = Json::object();
      const auto q = tet_quality.by_region.find(0);
      const auto v = tet_quality.volume_by_region.find(0);
      const double volume = v == tet_quality.volume_by_region.end() ? 0.0 : v->second;
      b["tetrahedra"] = q == tet_quality.by_region.end() ? std::size_t(0) : q->second.tetrahedra;
      b["volume"] = volume;
      b["voxel_volume"] = background_voxel_volume;
      b["volume_ratio"] = background_voxel_volume > 0 ? volume / background_voxel_volume : 0.0;
      b["box_volume"] = box_volume;
      b["box_filled"] = box_filled;
      b["box_covered"] = box_covered;
      b["box_points"] = box_points;
      b["box_refused"] = box_refused;
      t["outside"] = b;
    }
    st["tetrahedra"] = t;
    st["all_certified"] = all && failed_guarantee().empty();
  }
  return st;
}

std::vector<const InterfaceCertificate::Label*> LabelSurfaceNetsResult::meshed_labels() const {
  std::vector<const InterfaceCertificate::Label*> out;
  for (const auto& l : certificate.labels)
    if (std::binary_search(labels.begin(), labels.end(), l.label)) out.push_back(&l);
  return out;
}

std::string LabelSurfaceNetsResult::failed_guarantee() const {
  if (std::string why = certificate.failure(); !why.empty() || !tetrahedra) return why;
  if (!tet_conformity.ok()) {
    const TetConformity& c = tet_conformity;
    return "tetrahedra: not conforming (" + std::to_string(c.nonpositive) + " not positively oriented, " +
           std::to_string(c.duplicates) + " duplicated, " + std::to_string(c.overfull_faces) +
           " faces in three or more, " + std::to_string(c.inconsistent_faces) + " faces traversed alike)";
  }
  if (!tet_boundary_mismatch.empty()) return "tetrahedra: " + tet_boundary_mismatch;
  if (outside && !box_filled) return "tetrahedra: --outside: they do not fill the image box (volume differs)";
  if (outside && !box_covered) return "tetrahedra: --outside: the box triangles do not cover the image box's faces";
  if (centres_wrong > 0)
    return "tetrahedra: " + std::to_string(centres_wrong) + " of " + std::to_string(centres_checked) +
           " voxel centres in a tetrahedron of another label";
  if (cell_refinement_stopped) return "tetrahedra: cell refinement stopped at its cap (--max-cell-points, --max-points)";
  if (tet_quality.max_radius_edge_ratio > cell_ratio * (1 + 1e-9))
    return "tetrahedra: radius-edge ratio " + std::to_string(tet_quality.max_radius_edge_ratio) + " above " +
           std::to_string(cell_ratio);
  return "";
}

} // namespace imgmesh
