// wc2implicit: the smooth implicit function of thesis chapter 6 from a
// well-composed binary image, written as a pu-implicit float NRRD.
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "implicit/implicit_file.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"
#include "wellcomposed/well_composed.hpp"

#include <chrono>
#include <ctime>
#include <string>

using namespace imgmesh;

namespace {
// Process CPU time: on a shared machine it says more than the wall clock.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
} // namespace

int main(int argc, char** argv) {
  cli::Tool tool("wc2implicit",
                 "Build the C-infinity implicit function f of a well-composed 3D binary image (Siqueira 2006, ch. 6):\n"
                 "f^-1(0) is homeomorphic to the voxel boundary; f has the image's sign at every voxel centre.");
  std::string in, out;
  tool.app.add_option("IN", in, "Well-composed 3D binary image (nonzero = foreground; - for stdin)")->required();
  tool.app.add_option("OUT", out, "Implicit function file (.nrrd; - for NRRD on stdout)")->required();
  tool.add_threads();
  return tool.run(argc, argv, [&] {
    if (out != "-" && extension_of(out) != ".nrrd")
      throw UsageError("the implicit function file is NRRD: give OUT a .nrrd extension (or - for stdout)", out);
    auto t0 = std::chrono::steady_clock::now();
    const BinaryImage im = read_foreground(in, Selection{});
    const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (im.dimension != 3) throw Error("wc2implicit needs a 3D image (this one is 2D)", in);
    tool.report_progress("checking well-composedness");
    const CriticalCounts cc = count_critical_configurations(im);
    if (cc.total() != 0)
      throw Error("not well-composed (" + std::to_string(cc.c1) + " C1 and " + std::to_string(cc.c2) +
                      " C2 critical configurations); make it well-composed first: img2wc " + in + " OUT.nrrd",
                  in);
    tool.report_progress("signed distance and weights");
    ImplicitReport rep;
    t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_seconds();
    const PartitionOfUnity f = implicit_from_well_composed(im, &rep, unsigned(tool.threads()));
    const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double build_cpu = cpu_seconds() - c0;
    const bool padded = rep.padded_before != std::array<std::size_t, 3>{0, 0, 0} ||
                        rep.padded_after != std::array<std::size_t, 3>{0, 0, 0};
    if (padded)
      tool.info("the foreground touches the image border: the grid grows by one background voxel there "
                "(world coordinates unchanged) so that f^-1(0) is closed");
    tool.report_progress("writing");
    t0 = std::chrono::steady_clock::now();
    write_implicit(out, f);
    const double write_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const FloatImage& g = f.samples();
    tool.stats["input"] = in;
    tool.stats["output"] = out;
    tool.stats["input_size"] = std::vector<std::size_t>{im.size[0], im.size[1], im.size[2]};
    tool.stats["size"] = std::vector<std::size_t>{g.size[0], g.size[1], g.size[2]};
    tool.stats["spacing"] = std::vector<double>{g.spacing[0], g.spacing[1], g.spacing[2]};
    tool.stats["padded_before"] = std::vector<std::size_t>{rep.padded_before[0], rep.padded_before[1], rep.padded_before[2]};
    tool.stats["padded_after"] = std::vector<std::size_t>{rep.padded_after[0], rep.padded_after[1], rep.padded_after[2]};
    tool.stats["voxels"] = g.count();
    tool.stats["foreground_voxels"] = rep.foreground;
    tool.stats["cells"] = (g.size[0] - 1) * (g.size[1] - 1) * (g.size[2] - 1);
    tool.stats["g_min"] = f.g_min();
    tool.stats["L_max"] = f.l_max();
    tool.stats["d"] = std::vector<double>{f.d()[0], f.d()[1], f.d()[2]};
    tool.stats["threads"] = tool.threads();
    tool.stats["read_seconds"] = read_s;
    tool.stats["distance_seconds"] = rep.distance_seconds;
    tool.stats["weights_seconds"] = rep.weights_seconds;
    tool.stats["construction_seconds"] = build_s;
    tool.stats["construction_cpu_seconds"] = build_cpu;
    tool.stats["write_seconds"] = write_s;
    Json checked = Json::object();
    checked["well_composed"] = true;
    checked["sign_at_voxel_centres"] = true;  // f = g at every centre, g never 0 (|g| >= g_min > 0)
    checked["d_within_thesis_bound"] = true;  // PartitionOfUnity refuses a larger d
    tool.stats["guarantees"] = checked;
    tool.debug("g_min " + std::to_string(f.g_min()) + ", L_max " + std::to_string(f.l_max()) + ", d " +
               std::to_string(f.d()[0]) + " " + std::to_string(f.d()[1]) + " " + std::to_string(f.d()[2]));
    return cli::kOk;
  });
}
