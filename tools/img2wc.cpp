// img2wc: make a 2D or 3D binary image well-composed (thesis chapter 5).
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "implicit/crop.hpp"
#include "shared_options.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"
#include "wellcomposed/well_composed.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <algorithm>
#include <iostream>
#include <map>
#include <sstream>

using namespace imgmesh;

namespace {

// --labels: "all" or a comma-separated list of integers (the selection).
Selection parse_labels(const std::string& text) {
  Selection sel;
  if (text == "all") return sel;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(',', start);
    long long v = 0;
    if (!parse_integer(text.substr(start, end == std::string::npos ? std::string::npos : end - start), v))
      throw UsageError("--labels: '" + text + "' is not 'all' or a comma-separated list of integer labels");
    sel.labels.push_back(v);
    if (end == std::string::npos) return sel;
    start = end + 1;
  }
}

// img2wc --labels: every label well-composed at once (or counted, --check).
int run_labels(cli::Tool& tool, const std::string& in, const std::string& out, const std::string& labels,
               const PartitionOptions& opt, bool check) {
  ImageInfo info;
  LabelImage img = read_labels(in, parse_labels(labels), &info);
  tool.stats["input"] = in;
  if (check) {
    const PartitionCheck c = check_well_composed_partition(img);
    const Json totals = c.counts.to_json();
    std::cout << in << ": " << (c.counts.total() ? "not a well-composed partition" : "well-composed partition")
              << " (" << c.counts.labels.size() - 1 << " labels; C1 " << totals.at("c1").integer() << ", C2 "
              << totals.at("c2").integer() << ")\n";
    for (std::size_t i = 0; i < c.counts.labels.size(); ++i)
      if (c.counts.counts[i].total())
        std::cout << "  label " << c.counts.labels[i] << ": C1 " << c.counts.counts[i].c1 << ", C2 "
                  << c.counts.counts[i].c2 << "\n";
    return tool.finish(c);
  }
  tool.report_progress("repairing " + std::to_string(img.count()) + " voxels, every label");
  const std::array<std::size_t, 3> size = img.size;
  const PartitionResult res = make_well_composed_partition(std::move(img), opt);
  if (res.image.size != size) {
    std::ostringstream msg;
    msg << "labels touch the image border: grid grown to " << res.image.size[0] << "x" << res.image.size[1];
    if (res.image.dimension == 3) msg << "x" << res.image.size[2];
    msg << " (one background voxel added on those sides; origin moved, world coordinates unchanged)";
    tool.info(msg.str());
  }
  write_image(out, res.image, info.component);
  tool.debug("labels " + std::to_string(res.input.labels.size() - 1) + ", configurations " +
             std::to_string(res.input.total()) + ", changed " + std::to_string(res.changed));
  return tool.finish(res);
}

} // namespace

int main(int argc, char** argv) {
  cli::Tool tool("img2wc", "Make a binary image well-composed: no critical configuration (C1)/(C2) "
                           "remains, changing as few voxels as the repair of Siqueira (2006), ch. 5, finds; "
                           "with --labels, every label of a label image at once.");
  std::string in, out;
  Selection sel;
  WellComposedOptions opt;
  bool check = false, thesis_rules = false;
  std::string labels;
  PartitionOptions popt;
  tool.app.add_option("IN", in, "Input image (NRRD, MetaImage, NIfTI, PNG; - for stdin)")->required();
  tool.app.add_option("OUT", out,
                      "Output 0/1 uint8 image (--labels: a label image of IN's type), format by extension "
                      "(- for NRRD on stdout)");
  tool.data_output(out, cli::Stream::Binary);
  auto* label = tool.app.add_option("--label", sel.labels,
                                    "Foreground is this label (repeatable: the union); default: nonzero");
  label->type_name("L")->allow_extra_args(false);
  auto* thr = tool.app.add_option("--threshold", sel.threshold, "Foreground is value >= T")->type_name("T");
  thr->excludes(label);
  auto* all = tool.app.add_option("--labels", labels,
                                  "Every label at once: all, or a list 1,3,5 (others become 0); OUT is a label image "
                                  "of IN's type in which each label and the background are well-composed");
  all->type_name("all|L,L,...")->excludes(label)->excludes(thr);
  tool.app.add_option("--min-voxels", popt.min_voxels,
                      "With --labels: a label of fewer voxels may vanish (default: every label is kept)")
      ->type_name("N")
      ->needs(all);
  tool.app
      .add_option_function<std::string>(
          "--priority",
          [&popt](const std::string& p) {
            popt.priority = p == "larger" ? PartitionOptions::Priority::Larger : PartitionOptions::Priority::Smaller;
          },
          "With --labels: which label of a configuration grows: smaller (the label of fewer voxels; small "
          "structures never thin out) or larger (a few % fewer changes)")
      ->check(CLI::IsMember({"smaller", "larger"}))
      ->default_str("smaller")
      ->needs(all);
  bool full_grid = false;
  tool.app.add_flag("--full-grid", full_grid,
                    "With --label: write the whole grid, not the label's box plus the background margin the next "
                    "stages need (the same meshes either way)")
      ->needs(label);
  add_repair_mode_option(tool, opt.mode,
                         "add: only background becomes foreground (the thesis); remove: the dual; "
                         "min: both, keep the one changing fewer voxels");
  tool.add_seed();
  tool.app.add_flag("--thesis-rules", thesis_rules,
                    "Draw at random among all of B1(r) (rule 2) or B2(r) (rule 3), as the thesis does, "
                    "instead of among the sets that eliminate the most configurations");
  // Tests only (hidden): pad but do not repair, so that the final count must
  // catch the critical configurations (exit 3, the output written).
  bool skip_repair = false;
  tool.app.add_flag("--skip-repair", skip_repair)->group("");
  tool.app.add_flag("--check", check,
                    "Write nothing: print whether IN is well-composed and its counts; exit 0 if it is, 1 if not "
                    "(with --labels: the counts per label, exit 3 if any is left)");

  return tool.run(argc, argv, [&] {
    sel.has_threshold = thr->count() > 0;
    if (!check && out.empty()) throw UsageError("OUT is required (or use --check)");
    if (check && !out.empty()) throw UsageError("--check writes nothing: give no OUT");
    if (all->count()) {
      if (tool.app.get_option("--mode")->count() || thesis_rules || tool.app.get_option("--seed")->count())
        throw UsageError("--labels has no --mode, --thesis-rules or --seed: its moves are its own, drawn from "
                         "nothing at random (see the man page)");
      popt.repair = !skip_repair;
      return run_labels(tool, in, out, labels, popt, check);
    }

    // A label: read as the runs of its rows (the scan's values not kept),
    // cut to its box plus the margin, placed in the scan by its frame.
    ForegroundRuns runs;
    BinaryImage img;
    if (!sel.labels.empty() && !full_grid && !check) {
      runs = read_foreground_runs(in, sel);
      if (runs.geometry().dimension != 3) img = runs.image();
    } else {
      img = read_foreground(in, sel);
    }
    const bool crop = runs.count() && runs.geometry().dimension == 3;
    tool.stats["input"] = in;

    if (check) {
      const WellComposedCheck c = check_well_composed(img);
      std::cout << in << ": " << (c.counts.total() ? "not well-composed" : "well-composed") << " (C1 " << c.counts.c1
                << ", C2 " << c.counts.c2 << ")\n";
      const int code = tool.finish(c);
      return c.counts.total() ? cli::kFailure : code;
    }

    opt.seed = tool.seed();
    opt.greedy = !thesis_rules;
    opt.repair = !skip_repair;
    tool.report_progress("repairing " + std::to_string(crop ? runs.geometry().count() : img.count()) + " voxels");
    ScanFrame frame;
    WellComposedResult res;
    if (crop) {
      VoxelBox box;
      box.lo = runs.lo();
      box.hi = runs.hi();
      WellComposedCrop c = well_composed_crop(
          runs.geometry(), box,
          [&](std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* row) {
            runs.row(y, z, x0, n, row);
          },
          opt);
      res = std::move(c.result);
      frame = c.frame;
    } else {
      res = make_well_composed(img, opt);
    }
    std::vector<std::uint8_t>().swap(img.data);  // the input is no longer needed: less memory while writing
    runs = ForegroundRuns();

    if (res.padded_before != std::array<std::size_t, 3>{0, 0, 0} ||
        res.padded_after != std::array<std::size_t, 3>{0, 0, 0}) {
      const std::array<std::size_t, 3>& grown = crop ? frame.size : res.image.size;
      std::ostringstream msg;
      msg << "foreground touches the image border: grid grown to " << grown[0] << "x" << grown[1];
      if (res.image.dimension == 3) msg << "x" << grown[2];
      msg << " (one background voxel added on those sides; origin moved, world coordinates unchanged)";
      tool.info(msg.str());
    }
    if (crop) {
      tool.stats["scan_size"] = std::vector<std::size_t>{frame.size[0], frame.size[1], frame.size[2]};
      tool.stats["crop_index"] = std::vector<std::ptrdiff_t>{frame.index[0], frame.index[1], frame.index[2]};
    }
    write_image(out, res.image, crop ? frame.keys() : std::map<std::string, std::string>{});
    tool.debug("C1 " + std::to_string(res.input.c1) + ", C2 " + std::to_string(res.input.c2) + ", changed " +
               std::to_string(res.changed) + ", created " + std::to_string(res.created));
    return tool.finish(res);
  });
}
