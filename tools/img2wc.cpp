// img2wc: make a 2D or 3D binary image well-composed (thesis chapter 5).
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "util/error.hpp"
#include "wellcomposed/well_composed.hpp"

#include <iostream>
#include <map>
#include <sstream>

using namespace imgmesh;

namespace {
const char* mode_name(RepairMode m) {
  return m == RepairMode::Add ? "add" : m == RepairMode::Remove ? "remove" : "min";
}
} // namespace

int main(int argc, char** argv) {
  cli::Tool tool("img2wc", "Make a binary image well-composed: no critical configuration (C1)/(C2) "
                           "remains, changing as few voxels as the repair of Siqueira (2006), ch. 5, finds.");
  std::string in, out, mode = "add";
  Selection sel;
  bool check = false, thesis_rules = false;
  tool.app.add_option("IN", in, "Input image (NRRD, MetaImage, NIfTI, PNG; - for stdin)")->required();
  tool.app.add_option("OUT", out, "Output 0/1 uint8 image, format by extension (- for NRRD on stdout)");
  auto* label = tool.app.add_option("--label", sel.labels,
                                    "Foreground is this label (repeatable: the union); default: nonzero");
  label->type_name("L")->allow_extra_args(false);
  auto* thr = tool.app.add_option("--threshold", sel.threshold, "Foreground is value >= T")->type_name("T");
  thr->excludes(label);
  tool.app.add_option("--mode", mode,
                      "add: only background becomes foreground (the thesis); remove: the dual; "
                      "min: both, keep the one changing fewer voxels")
      ->check(CLI::IsMember({"add", "remove", "min"}))
      ->capture_default_str();
  tool.add_seed();
  tool.app.add_flag("--thesis-rules", thesis_rules,
                    "Draw at random among all of B1(r) (rule 2) or B2(r) (rule 3), as the thesis does, "
                    "instead of among the sets that eliminate the most configurations");
  tool.app.add_flag("--check", check,
                    "Write nothing: print whether IN is well-composed and its counts; exit 0 if it is, 1 if not");

  return tool.run(argc, argv, [&] {
    sel.has_threshold = thr->count() > 0;
    if (!check && out.empty()) throw UsageError("OUT is required (or use --check)");
    if (check && !out.empty()) throw UsageError("--check writes nothing: give no OUT");
    if (out == "-" && tool.app.get_option("--stats")->as<std::string>() == "-")
      throw UsageError("OUT and --stats cannot both be standard output");

    BinaryImage img = read_foreground(in, sel);
    tool.stats["input"] = in;
    tool.stats["dimension"] = img.dimension;
    tool.stats["voxels"] = img.count();

    if (check) {
      const CriticalCounts c = count_critical_configurations(img);
      tool.stats["c1"] = c.c1;
      tool.stats["c2"] = c.c2;
      tool.stats["well_composed"] = c.total() == 0;
      std::cout << in << ": " << (c.total() ? "not well-composed" : "well-composed") << " (C1 " << c.c1
                << ", C2 " << c.c2 << ")\n";
      return c.total() ? cli::kFailure : cli::kOk;
    }

    WellComposedOptions opt;
    opt.mode = mode == "remove" ? RepairMode::Remove : mode == "min" ? RepairMode::Min : RepairMode::Add;
    opt.seed = tool.seed();
    opt.greedy = !thesis_rules;
    tool.report_progress("repairing " + std::to_string(img.count()) + " voxels");
    const WellComposedResult res = make_well_composed(img, opt);
    std::vector<std::uint8_t>().swap(img.data);  // the input is no longer needed: less memory while writing

    // The guarantee, checked on the result rather than assumed.
    const CriticalCounts left = count_critical_configurations(res.image);
    if (res.padded_before != std::array<std::size_t, 3>{0, 0, 0} ||
        res.padded_after != std::array<std::size_t, 3>{0, 0, 0}) {
      std::ostringstream msg;
      msg << "foreground touches the image border: grid grown to " << res.image.size[0] << "x"
          << res.image.size[1];
      if (res.image.dimension == 3) msg << "x" << res.image.size[2];
      msg << " (one background voxel added on those sides; origin moved, world coordinates unchanged)";
      tool.info(msg.str());
    }
    write_image(out, res.image);

    const std::size_t m = res.input.total();
    tool.stats["mode"] = mode_name(opt.mode);
    tool.stats["mode_used"] = mode_name(res.mode_used);
    tool.stats["seed"] = static_cast<unsigned long long>(opt.seed);
    tool.stats["rules"] = thesis_rules ? "thesis" : "greedy";
    tool.stats["c1"] = res.input.c1;
    tool.stats["c2"] = res.input.c2;
    tool.stats["changed"] = res.changed;
    tool.stats["ratio"] = m ? double(res.changed) / double(m) : 0.0;
    tool.stats["created"] = res.created;
    tool.stats["output_size"] = std::vector<unsigned long long>{res.image.size[0], res.image.size[1], res.image.size[2]};
    tool.stats["padded_before"] = std::vector<unsigned long long>{res.padded_before[0], res.padded_before[1], res.padded_before[2]};
    tool.stats["padded_after"] = std::vector<unsigned long long>{res.padded_after[0], res.padded_after[1], res.padded_after[2]};
    tool.stats["output_c1"] = left.c1;
    tool.stats["output_c2"] = left.c2;
    tool.stats["well_composed"] = left.total() == 0;
    tool.debug("C1 " + std::to_string(res.input.c1) + ", C2 " + std::to_string(res.input.c2) + ", changed " +
               std::to_string(res.changed) + ", created " + std::to_string(res.created));
    if (left.total()) {
      tool.info("output is NOT well-composed (" + std::to_string(left.total()) + " critical configurations left)");
      return cli::kGuarantee;
    }
    return cli::kOk;
  });
}
