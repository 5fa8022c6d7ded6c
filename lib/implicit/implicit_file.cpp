// Construction (thesis 6.3.3) and the pu-implicit file format (doc/design.md "Data contracts").
#include "implicit/implicit_file.hpp"
#include "image/nrrd_float.hpp"
#include "util/cpu_time.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"
#include "wellcomposed/well_composed.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

namespace imgmesh {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

namespace {

// implicit_from_well_composed's checks of its input, and where the grid
// grows (rep's padded_*, foreground).
void check_well_composed_sides(const BinaryImage& wc, ImplicitReport& rep) {
  if (wc.dimension != 3) throw Error("wc2implicit needs a 3D image (thesis chapter 6 is 3D)");
  if (wc.data.size() != wc.count() || wc.count() == 0) throw Error("empty image");
  const CriticalCounts cc = count_critical_configurations(wc);
  if (cc.total() != 0)
    throw Error("not well-composed (" + std::to_string(cc.c1) + " C1 and " + std::to_string(cc.c2) +
                " C2 critical configurations); make it well-composed first: img2wc IN OUT.nrrd");
  // Restriction (2) of thesis 6.3: no foreground on the border of D.
  for (int a = 0; a < 3; ++a) {
    const std::size_t n = wc.size[a];
    for (std::size_t z = 0; z < wc.size[2]; ++z)
      for (std::size_t y = 0; y < wc.size[1]; ++y)
        for (std::size_t x = 0; x < wc.size[0]; ++x) {
          const std::size_t c = a == 0 ? x : a == 1 ? y : z;
          if (c != 0 && c + 1 != n) continue;
          if (wc(x, y, z)) {
            if (c == 0) rep.padded_before[a] = 1;
            if (c + 1 == n) rep.padded_after[a] = 1;
          }
        }
  }
  for (std::uint8_t v : wc.data) rep.foreground += v != 0;
  if (rep.foreground == 0) throw Error("the foreground is empty");
}

bool padding_needed(const ImplicitReport& rep) {
  return rep.padded_before != std::array<std::size_t, 3>{0, 0, 0} ||
         rep.padded_after != std::array<std::size_t, 3>{0, 0, 0};
}

} // namespace

PartitionOfUnity implicit_from_well_composed(const BinaryImage& wc, ImplicitReport* report, unsigned threads) {
  const auto t_start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  ImplicitReport rep;
  check_well_composed_sides(wc, rep);
  const bool pad_needed = padding_needed(rep);
  auto t0 = std::chrono::steady_clock::now();
  FloatImage g = pad_needed ? signed_distance_to_boundary(pad(wc, rep.padded_before, rep.padded_after, std::uint8_t(0)), threads)
                            : signed_distance_to_boundary(wc, threads);
  rep.distance_seconds = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  PartitionOfUnity f(std::move(g), {0, 0, 0}, threads);
  rep.weights_seconds = seconds_since(t0);
  rep.input_size = wc.size;
  rep.size = f.samples().size;
  rep.spacing = f.samples().spacing;
  rep.d = f.d();
  rep.g_min = f.g_min();
  rep.l_max = f.l_max();
  rep.threads = threads;
  rep.construction_seconds = seconds_since(t_start);
  rep.construction_cpu_seconds = process_cpu_seconds() - cpu_start;
  if (report) *report = rep;
  return f;
}

PartitionOfUnity implicit_in_scan(const BinaryImage& wc, ScanFrame frame, float clamp, unsigned threads,
                                  bool* placed, std::size_t band_bytes, SampleGrid::Storage storage) {
  ImplicitReport rep;
  check_well_composed_sides(wc, rep);
  BinaryImage padded;
  if (padding_needed(rep)) padded = pad(wc, rep.padded_before, rep.padded_after, std::uint8_t(0));
  const BinaryImage& image = padding_needed(rep) ? padded : wc;
  if (frame.present() && !frame.grow(rep.padded_before, rep.padded_after, wc)) frame = ScanFrame();
  const bool in_scan = placed_in_scan(image, frame, clamp);
  if (placed) *placed = in_scan;
  const VoxelBox fg = foreground_box(image);
  return PartitionOfUnity::from_bands(in_scan ? frame.scan(image) : image.geometry(), in_scan ? frame.index : Index3{0, 0, 0},
                                      image, fg.lo, fg.hi, clamp,
                                      [&](std::size_t x0, std::size_t x1, float* band) {
                                        signed_distance_band(image, x0, x1, band, threads);
                                      },
                                      threads, storage, band_bytes);
}

Json ImplicitReport::to_json() const {
  auto triple = [](const std::array<std::size_t, 3>& a) { return std::vector<std::size_t>{a[0], a[1], a[2]}; };
  Json j = Json::object();
  j["input_size"] = triple(input_size);
  j["size"] = triple(size);
  j["spacing"] = std::vector<double>{spacing[0], spacing[1], spacing[2]};
  j["padded_before"] = triple(padded_before);
  j["padded_after"] = triple(padded_after);
  j["voxels"] = size[0] * size[1] * size[2];
  j["foreground_voxels"] = foreground;
  j["cells"] = (size[0] - 1) * (size[1] - 1) * (size[2] - 1);
  j["g_min"] = g_min;
  j["L_max"] = l_max;
  j["d"] = std::vector<double>{d[0], d[1], d[2]};
  j["threads"] = threads;
  j["distance_seconds"] = distance_seconds;
  j["weights_seconds"] = weights_seconds;
  j["construction_seconds"] = construction_seconds;
  j["construction_cpu_seconds"] = construction_cpu_seconds;
  Json checked = Json::object();
  checked["well_composed"] = true;  // checked before the construction
  checked["sign_at_voxel_centres"] = true;
  checked["d_within_thesis_bound"] = true;
  j["guarantees"] = checked;
  return j;
}

PartitionOfUnity read_implicit(const std::string& path, const std::function<float(const Geometry&)>& clamp,
                               ScanFrame* frame_out, bool* placed) {
  // Read without ITK (image/nrrd_float.hpp), as it streams; "-" is standard
  // input, spooled to a file first so that its header is checked against
  // its data before anything is allocated.
  std::unique_ptr<StdinSpool> spool;
  if (path == "-") spool = std::make_unique<StdinSpool>();
  std::ifstream data(spool ? spool->path() : path, std::ios::binary);
  if (!data) throw Error(std::string("cannot open: ") + std::strerror(errno), path);
  const NrrdHeader header = read_nrrd_header(data, path);
  const std::map<std::string, std::string>& fields = header.keys;
  auto it = fields.find("imgmesh_kind");
  if (it == fields.end() || it->second != kImplicitKind)
    throw Error("not an implicit function file (no imgmesh_kind:=pu-implicit field; make one with wc2implicit)", path);
  it = fields.find("imgmesh_version");
  if (it == fields.end() || it->second != kImplicitVersion)
    throw Error("unsupported pu-implicit version '" + (it == fields.end() ? std::string("none") : it->second) +
                    "' (this build reads version " + kImplicitVersion + ")",
                path);
  it = fields.find("imgmesh_d");
  Vec3 d{0, 0, 0};
  if (it == fields.end()) throw Error("missing imgmesh_d field", path);
  {
    std::istringstream in(it->second);
    std::string extra;
    if (!(in >> d[0] >> d[1] >> d[2]) || (in >> extra))
      throw Error("bad imgmesh_d field '" + it->second + "' (want three numbers)", path);
    for (double x : d)
      if (!(x > 0) || !std::isfinite(x)) throw Error("bad imgmesh_d field '" + it->second + "' (must be > 0)", path);
  }
  NrrdFloatStream samples(header, data, path);
  const Geometry& grid = samples.geometry();
  float file_clamp = std::numeric_limits<float>::infinity();
  it = fields.find("imgmesh_clamp");
  if (it != fields.end()) {
    std::istringstream in(it->second);
    std::string extra;
    if (!(in >> file_clamp) || (in >> extra) || !(file_clamp >= PartitionOfUnity::clamp_for(grid, 0)))
      throw Error("bad imgmesh_clamp field '" + it->second + "' (want one number, at least 2 |spacing|)", path);
  }
  const ScanFrame frame = ScanFrame::from_keys(fields, grid, path);
  if (frame_out) *frame_out = frame;
  const std::size_t slice = grid.size[0] * grid.size[1];
  try {
    const float t = std::min(clamp ? clamp(grid) : std::numeric_limits<float>::infinity(), file_clamp);
    return function_in_scan(grid, frame, d, t, [&](float* out) { samples.read(out, slice); }, placed);
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw Error(e.what(), e.path().empty() ? path : e.path());
  }
}

} // namespace imgmesh
