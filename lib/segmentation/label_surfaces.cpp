// mesh_label_surfaces: a pool of `jobs` threads takes the labels, largest
// box first (the longest runs start early, so the pool ends together), each
// running the three chapters' library calls on its own crop of the label
// image (its box plus a margin, crop.hpp); nothing is shared between labels
// but the read-only label image, whose voxels are let go once the last
// label's crop is made (the meshers' peak does not hold the scan).
#include "segmentation/label_surfaces.hpp"

#include "implicit/crop.hpp"
#include "implicit/implicit_file.hpp"
#include "surface/implicit_surface.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <mutex>
#include <numeric>
#include <set>
#include <sstream>
#include <thread>

namespace imgmesh {
namespace {

// img2wc --label L (the label's box plus the margin), wc2implicit and
// implicit2mesh's reading (f clamped, placed back in the scan's grid), in
// memory: the pipeline's mesh, at the cost of the label's box (and of its
// clamped blocks: f is built from g a band at a time, implicit_in_scan).
template <class T>
LabelSurface mesh_one_label(const Image<T>& image, long long label, std::size_t voxels, const VoxelBox& box,
                            const LabelSurfacesOptions& opt, int threads, const std::function<void()>& crop_made) {
  const auto t0 = std::chrono::steady_clock::now();
  LabelSurface out;
  out.label = label;
  if (const auto it = opt.names.find(label); it != opt.names.end()) out.name = it->second;
  out.voxels = voxels;
  WellComposedOptions wco;
  wco.mode = opt.mode;
  wco.seed = opt.mesher.seed;
  WellComposedCrop wc = [&] {
    struct Made {  // whether the crop is made or its making threw
      const std::function<void()>& f;
      ~Made() { f(); }
    } made{crop_made};
    return well_composed_crop(
        image, box,
        [&](std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* row) {
          const T* v = &image(x0, y, z);
          for (std::size_t i = 0; i < n; ++i) row[i] = v[i] == label;
        },
        wco);
  }();
  out.changed = wc.result.changed;
  out.crop = wc.result.image.size;
  out.well_composed_failure = wc.result.failed_guarantee();
  wc.frame.foreground = foreground_box(wc.result.image);
  const PartitionOfUnity f =
      implicit_in_scan(wc.result.image, wc.frame, PartitionOfUnity::clamp_for(wc.result.image, opt.mesher.max_distance),
                       unsigned(threads));
  std::vector<std::uint8_t>().swap(wc.result.image.data);
  release_free_memory();  // the crop's pages, before the mesher's peak
  const PartitionOfUnitySurface surface(f);
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

// One pass over the image: the voxels and box of each of `labels` (ascending).
template <class T>
void label_boxes(const Image<T>& image, const std::vector<long long>& labels, std::vector<std::size_t>& voxels,
                 std::vector<VoxelBox>& boxes) {
  // A run of one value looked up once.
  voxels.assign(labels.size(), 0);
  boxes.assign(labels.size(), VoxelBox());
  for (std::size_t z = 0; z < image.size[2]; ++z)
    for (std::size_t y = 0; y < image.size[1]; ++y) {
      const T* row = &image(0, y, z);
      for (std::size_t x = 0; x < image.size[0];) {
        std::size_t end = x + 1;
        while (end < image.size[0] && row[end] == row[x]) ++end;
        const auto it = std::lower_bound(labels.begin(), labels.end(), (long long)row[x]);
        if (it != labels.end() && *it == row[x]) {
          const std::size_t i = std::size_t(it - labels.begin());
          voxels[i] += end - x;
          boxes[i].add(std::ptrdiff_t(x), std::ptrdiff_t(y), std::ptrdiff_t(z));
          boxes[i].add(std::ptrdiff_t(end - 1), std::ptrdiff_t(y), std::ptrdiff_t(z));
        }
        x = end;
      }
    }
}

} // namespace

template <class T> std::vector<long long> labels_present(const Image<T>& image) {
  std::set<long long> s(image.data.begin(), image.data.end());
  s.erase(0);
  return {s.begin(), s.end()};
}

template <class T> std::vector<long long> chosen_labels(const Image<T>& image, const std::vector<long long>& asked) {
  if (image.dimension != 3) throw Error("a 3D label image is needed (seg2mesh meshes surfaces)");
  const std::vector<long long> present = labels_present(image);
  if (present.empty()) throw Error("no label: every voxel is 0");
  std::vector<long long> labels = asked.empty() ? present : asked;
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  for (long long l : labels)
    if (!std::binary_search(present.begin(), present.end(), l))
      throw Error("label " + std::to_string(l) + " does not occur (labels present: " + list(present) + ")");
  return labels;
}

template <class T> LabelSurfacesResult mesh_label_surfaces(Image<T> image, const LabelSurfacesOptions& opt) {
  const std::vector<long long> labels = chosen_labels(image, opt.labels);
  std::vector<std::size_t> voxels;
  std::vector<VoxelBox> boxes;
  label_boxes(image, labels, voxels, boxes);
  // Largest first, by the box a label's work is proportional to (the
  // longest job must not start last); then by voxels.
  auto box_voxels = [&](std::size_t i) {
    const auto n = boxes[i].size();
    return n[0] * n[1] * n[2];
  };
  std::vector<std::size_t> order(labels.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return box_voxels(a) != box_voxels(b) ? box_voxels(a) > box_voxels(b) : voxels[a] > voxels[b];
  });

  LabelSurfacesResult res;
  res.jobs = std::max(1, std::min<int>(opt.jobs, int(labels.size())));
  const int threads = std::max(1, opt.threads / res.jobs);
  res.labels.resize(labels.size());
  std::vector<std::exception_ptr> errors(labels.size());
  std::atomic<std::size_t> next{0}, cropped{0};
  std::mutex progress_mutex;
  // Called by each label once its crop is made (or its making failed): the
  // last one lets the voxels go, no thread reading them any more.
  const auto crop_made = [&] {
    if (++cropped == labels.size()) {
      std::vector<T>().swap(image.data);
      release_free_memory();
    }
  };
  auto worker = [&] {
    for (std::size_t k; (k = next++) < order.size();) {
      const std::size_t i = order[k];
      if (opt.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        opt.progress("label " + std::to_string(labels[i]) + " (" + std::to_string(k + 1) + " of " +
                     std::to_string(labels.size()) + ")");
      }
      try {
        res.labels[i] = mesh_one_label(image, labels[i], voxels[i], boxes[i], opt, threads, crop_made);
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

#define IMGMESH_LABEL_TYPE(T)                                                                             \
  template std::vector<long long> labels_present(const Image<T>&);                                           \
  template std::vector<long long> chosen_labels(const Image<T>&, const std::vector<long long>&);             \
  template LabelSurfacesResult mesh_label_surfaces(Image<T>, const LabelSurfacesOptions&);
IMGMESH_LABEL_TYPE(std::uint8_t)
IMGMESH_LABEL_TYPE(std::uint16_t)
IMGMESH_LABEL_TYPE(std::int32_t)
#undef IMGMESH_LABEL_TYPE

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
    j["crop_size"] = std::vector<std::size_t>{l.crop[0], l.crop[1], l.crop[2]};
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
