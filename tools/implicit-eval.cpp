// implicit-eval: evaluate the implicit function f (and its gradient) of a
// pu-implicit file at given points, or at N random points as a benchmark
// (thesis Table 6.1).
#include "cli/cli.hpp"
#include "implicit/evaluate.hpp"
#include "implicit/implicit_file.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <chrono>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("implicit-eval",
                 "Evaluate the implicit function f of a pu-implicit file (made by wc2implicit) at points read as\n"
                 "'x y z' lines (world coordinates), or at N random points of the domain as a benchmark.");
  std::string implicit_path, points = "-", output = "-";
  bool gradient = false, allow_outside = false;
  std::uint64_t random_n = 0;
  tool.app.add_option("IMPLICIT", implicit_path, "Implicit function file (.nrrd from wc2implicit; - for stdin)")->required();
  tool.app.add_option("POINTS", points, "Text file of points, one 'x y z' a line (default - : stdin)");
  tool.app.add_option("-o,--output", output, "Where to write the values (default - : stdout)")->type_name("FILE|-");
  tool.data_output(output, cli::Stream::Text, [&] { return random_n == 0; });
  tool.app.add_flag("--gradient", gradient, "Also write the gradient: 'f gx gy gz' a line");
  tool.app.add_flag("--allow-outside", allow_outside,
                    "Write nan for points outside the domain instead of failing");
  tool.app.add_option("--random", random_n,
                      "Evaluate N uniform random points of the domain, write nothing per point, report the rate in --stats")
      ->type_name("N");
  tool.add_seed();
  tool.add_threads();
  return tool.run(argc, argv, [&] {
    if (random_n > 0 && tool.app.count("POINTS"))
      throw UsageError("give either POINTS or --random N, not both");
    if (implicit_path == "-" && points == "-" && random_n == 0)
      throw UsageError("IMPLICIT and POINTS cannot both be stdin");
    auto t0 = std::chrono::steady_clock::now();
    const PartitionOfUnity f = read_implicit(implicit_path);
    tool.stats["read_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (random_n > 0) {
      tool.report_progress("evaluating " + std::to_string(random_n) + " random points");
      const RandomEvaluation r = evaluate_random(f, random_n, tool.seed(), gradient, unsigned(tool.threads()));
      tool.info(std::to_string(random_n) + (gradient ? " evaluations of f and grad f in " : " evaluations of f in ") +
                std::to_string(r.seconds) + " s on " + std::to_string(tool.threads()) + " thread(s)");
      return tool.finish(r);
    }
    std::ifstream file;
    std::istream* in = &std::cin;
    if (points != "-") {
      file.open(points);
      if (!file) throw Error("cannot open the points file", points);
      in = &file;
    }
    AtomicOutput out(output);
    const PointEvaluation r = evaluate_points(f, *in, out.stream(), gradient, allow_outside, points);
    out.commit();
    return tool.finish(r);
  });
}
