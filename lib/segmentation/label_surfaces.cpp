// mesh_label_surfaces: a pool of `jobs` threads takes the labels, largest
// first (the longest runs start early, so the pool ends together), each
// running the three chapters' library calls on its own data; nothing is
// shared between labels but the read-only label image.
#include "segmentation/label_surfaces.hpp"

#include "implicit/implicit_file.hpp"
#include "surface/implicit_surface.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <numeric>
#include <set>
#include <sstream>
#include <thread>

namespace imgmesh {
namespace {

LabelSurface mesh_one_label(const LabelImage& image, long long label, std::size_t voxels,
                            const LabelSurfacesOptions& opt, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  LabelSurface out;
  out.label = label;
  if (const auto it = opt.names.find(label); it != opt.names.end()) out.name = it->second;
  out.voxels = voxels;
  BinaryImage fg(image, 0);
  for (std::size_t i = 0; i < image.data.size(); ++i) fg.data[i] = image.data[i] == label ? 1 : 0;
  WellComposedOptions wco;
  wco.mode = opt.mode;
  wco.seed = opt.mesher.seed;
  WellComposedResult wc = make_well_composed(fg, wco);
  std::vector<std::uint8_t>().swap(fg.data);
  out.changed = wc.changed;
  out.well_composed_failure = wc.failed_guarantee();
  const PartitionOfUnity pu = implicit_from_well_composed(wc.image, nullptr, unsigned(threads));
  std::vector<std::uint8_t>().swap(wc.image.data);
  const PartitionOfUnitySurface surface(pu);
  RestrictedDelaunayOptions mo = opt.mesher;
  mo.threads = threads;
  mo.progress = nullptr;
  out.mesh = restricted_delaunay_mesh(surface, mo);
  if (opt.normals) add_normals(surface, out.mesh.mesh);
  std::vector<Vec3>().swap(out.mesh.centers);  // not needed past the certificate
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

std::string list(const std::vector<long long>& v) {
  std::ostringstream s;
  for (std::size_t i = 0; i < v.size() && i < 20; ++i) s << (i ? " " : "") << v[i];
  if (v.size() > 20) s << " ...";
  return s.str();
}

} // namespace

std::vector<long long> labels_present(const LabelImage& image) {
  std::set<long long> s(image.data.begin(), image.data.end());
  s.erase(0);
  return {s.begin(), s.end()};
}

LabelSurfacesResult mesh_label_surfaces(const LabelImage& image, const LabelSurfacesOptions& opt) {
  if (image.dimension != 3) throw Error("a 3D label image is needed (seg2mesh meshes surfaces)");
  const std::vector<long long> present = labels_present(image);
  if (present.empty()) throw Error("no label: every voxel is 0");
  std::vector<long long> labels = opt.labels.empty() ? present : opt.labels;
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  for (long long l : labels)
    if (!std::binary_search(present.begin(), present.end(), l))
      throw Error("label " + std::to_string(l) + " does not occur (labels present: " + list(present) + ")");

  std::vector<std::size_t> voxels(labels.size(), 0);
  for (std::int32_t v : image.data) {
    auto it = std::lower_bound(labels.begin(), labels.end(), (long long)v);
    if (it != labels.end() && *it == v) ++voxels[std::size_t(it - labels.begin())];
  }
  std::vector<std::size_t> order(labels.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return voxels[a] > voxels[b]; });

  LabelSurfacesResult res;
  res.jobs = std::max(1, std::min<int>(opt.jobs, int(labels.size())));
  const int threads = std::max(1, opt.threads / res.jobs);
  res.labels.resize(labels.size());
  std::vector<std::exception_ptr> errors(labels.size());
  std::atomic<std::size_t> next{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (std::size_t k; (k = next++) < order.size();) {
      const std::size_t i = order[k];
      if (opt.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        opt.progress("label " + std::to_string(labels[i]) + " (" + std::to_string(k + 1) + " of " +
                     std::to_string(labels.size()) + ")");
      }
      try {
        res.labels[i] = mesh_one_label(image, labels[i], voxels[i], opt, threads);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < res.jobs; ++j) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (errors[i]) try {
        std::rethrow_exception(errors[i]);
      } catch (const UsageError&) {
        throw;
      } catch (const Error& e) {
        throw Error("label " + std::to_string(labels[i]) + ": " + e.what(), e.path());
      }

  // Join: vertices renumbered after those of the labels before.
  for (LabelSurface& l : res.labels) {
    const SurfaceMesh& m = l.mesh.mesh;
    const int base = int(res.mesh.points.size());
    l.first_face = res.mesh.triangles.size();
    res.mesh.points.insert(res.mesh.points.end(), m.points.begin(), m.points.end());
    if (opt.normals) res.mesh.normals.insert(res.mesh.normals.end(), m.normals.begin(), m.normals.end());
    for (const auto& f : m.triangles) res.mesh.triangles.push_back({f[0] + base, f[1] + base, f[2] + base});
    res.mesh.labels.insert(res.mesh.labels.end(), m.triangles.size(), int(l.label));
    if (!l.name.empty()) res.mesh.label_names[int(l.label)] = l.name;
  }
  return res;
}

Json LabelSurfacesResult::to_json() const {
  Json st = Json::object();
  st["jobs"] = jobs;
  st["vertices"] = mesh.points.size();
  st["triangles"] = mesh.triangles.size();
  bool all = true;
  Json per = Json::array();
  for (const LabelSurface& l : labels) {
    Json j = l.mesh.to_json();
    j["label"] = l.label;
    if (!l.name.empty()) j["name"] = l.name;
    j["voxels"] = l.voxels;
    j["well_composed_changed"] = l.changed;
    j["seconds"] = l.seconds;
    j["certified"] = l.mesh.failed_guarantee().empty() && l.well_composed_failure.empty();
    all = all && l.mesh.failed_guarantee().empty() && l.well_composed_failure.empty();
    per.push_back(j);
  }
  st["all_certified"] = all;
  st["labels"] = per;
  return st;
}

std::string LabelSurfacesResult::failed_guarantee() const {
  std::string out;
  for (const LabelSurface& l : labels) {
    std::string why = l.well_composed_failure;
    const std::string m = l.mesh.failed_guarantee();
    if (!m.empty()) why += (why.empty() ? "" : "; ") + m;
    if (!why.empty()) out += (out.empty() ? "label " : "; label ") + std::to_string(l.label) + ": " + why;
  }
  return out;
}

} // namespace imgmesh
