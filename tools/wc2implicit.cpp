// wc2implicit: the smooth implicit function of thesis chapter 6 from a
// well-composed binary image, written as a pu-implicit float NRRD.
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "implicit/implicit_file.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <chrono>
#include <limits>
#include <map>
#include <string>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("wc2implicit",
                 "Build the C-infinity implicit function f of a well-composed 3D binary image (Siqueira 2006, ch. 6):\n"
                 "f^-1(0) is homeomorphic to the voxel boundary; f has the image's sign at every voxel centre.");
  std::string in, out;
  tool.app.add_option("IN", in, "Well-composed 3D binary image (nonzero = foreground; - for stdin)")->required();
  tool.app.add_option("OUT", out, "Implicit function file (.nrrd; - for NRRD on stdout)")->required();
  tool.data_output(out, cli::Stream::Binary);
  bool full_distance = false;
  tool.app.add_flag("--full-distance", full_distance,
                    "Write g at every voxel centre (the whole distance map) instead of a narrow band: by default "
                    "the samples are clamped to +-T, T = 2 |spacing| + 1 voxel, beyond which the meshers at a "
                    "--max-distance up to 0.5 voxel clamp them anyway (a file many times smaller, written faster)");
  tool.add_threads();
  return tool.run(argc, argv, [&] {
    if (out != "-" && extension_of(out) != ".nrrd")
      throw UsageError("the implicit function file is NRRD: give OUT a .nrrd extension (or - for stdout)", out);
    auto t0 = std::chrono::steady_clock::now();
    std::map<std::string, std::string> fields;
    const BinaryImage im = read_foreground(in, Selection{}, &fields);
    // img2wc --label's crop: where it lies in its scan travels on.
    ScanFrame frame = ScanFrame::from_keys(fields, im, in);
    const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    tool.report_progress("signed distance and weights");
    ImplicitReport rep;
    const PartitionOfUnity f =
        naming_input(in, [&] { return implicit_from_well_composed(im, &rep, unsigned(tool.threads())); });
    if (frame.present()) frame.foreground = foreground_box(im);
    if (rep.padded_before != std::array<std::size_t, 3>{0, 0, 0} ||
        rep.padded_after != std::array<std::size_t, 3>{0, 0, 0}) {
      tool.info("the foreground touches the image border: the grid grows by one background voxel there "
                "(world coordinates unchanged) so that f^-1(0) is closed");
      if (frame.present() && !frame.grow(rep.padded_before, rep.padded_after, im)) {
        tool.info("the crop's foreground touches a side inside its scan: written without its scan frame");
        frame = ScanFrame();
      }
    }
    tool.report_progress("writing");
    t0 = std::chrono::steady_clock::now();
    const float clamp = full_distance ? std::numeric_limits<float>::infinity() : covered_clamp(f.samples());
    write_implicit(out, f, frame, clamp);
    tool.stats["input"] = in;
    tool.stats["output"] = out;
    tool.stats["read_seconds"] = read_s;
    tool.stats["clamp"] = full_distance ? Json() : Json(double(clamp));
    tool.stats["write_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    tool.debug("g_min " + std::to_string(f.g_min()) + ", L_max " + std::to_string(f.l_max()) + ", d " +
               std::to_string(f.d()[0]) + " " + std::to_string(f.d()[1]) + " " + std::to_string(f.d()[2]));
    return tool.finish(rep);
  });
}
