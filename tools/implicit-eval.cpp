// implicit-eval: evaluate the implicit function f (and its gradient) of a
// pu-implicit file at given points, or at N random points as a benchmark
// (thesis Table 6.1).
#include "cli/cli.hpp"
#include "implicit/implicit_file.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <ctime>
#include <vector>

using namespace imgmesh;

namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
double unit(std::uint64_t x) { return double(x >> 11) * (1.0 / 9007199254740992.0); }

struct RandomRun {
  double seconds = 0, cpu_seconds = 0, checksum = 0, gradient_checksum = 0;
};

// Process CPU time: on a shared machine it says more than the wall clock.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Point i is a function of (seed, i) only, and blocks are summed in order, so
// the checksum does not depend on the number of threads. Threads take the
// next block as they finish one: on a shared machine a thread that gets less
// CPU does fewer blocks instead of holding up the end.
RandomRun random_run(const PartitionOfUnity& f, std::uint64_t n, std::uint64_t seed, bool gradient, unsigned threads) {
  const FloatImage& g = f.samples();
  const double ext[3] = {double(g.size[0] - 1), double(g.size[1] - 1), double(g.size[2] - 1)};
  constexpr std::uint64_t kBlock = 1 << 16;
  const std::uint64_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<double> sum(blocks, 0.0), gsum(blocks, 0.0);
  const std::uint64_t key = splitmix64(seed);
  std::atomic<std::uint64_t> next_block{0};
  auto work = [&] {
    constexpr std::uint64_t kBatch = 256;  // points handed to f.values() at once
    Vec3 p[kBatch], gr[kBatch];
    double v[kBatch];
    for (std::uint64_t b = next_block++; b < blocks; b = next_block++) {
      double s = 0, gs = 0;
      const std::uint64_t end = std::min(n, (b + 1) * kBlock);
      for (std::uint64_t i0 = b * kBlock; i0 < end; i0 += kBatch) {
        const std::uint64_t m = std::min(kBatch, end - i0);
        for (std::uint64_t j = 0; j < m; ++j) {
          const std::uint64_t h = splitmix64(key ^ ((i0 + j) * 3));
          p[j] = g.world(unit(h) * ext[0], unit(splitmix64(h + 1)) * ext[1], unit(splitmix64(h + 2)) * ext[2]);
        }
        f.values(p, m, v, gradient ? gr : nullptr);
        for (std::uint64_t j = 0; j < m; ++j) {
          s += v[j];
          if (gradient) gs += gr[j][0] + gr[j][1] + gr[j][2];
        }
      }
      sum[b] = s;
      gsum[b] = gs;
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  if (threads <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);
    for (auto& th : pool) th.join();
  }
  RandomRun r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_seconds = cpu_seconds() - c0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    r.checksum += sum[b];
    r.gradient_checksum += gsum[b];
  }
  return r;
}

} // namespace

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
    const FloatImage& g = f.samples();
    tool.stats["size"] = std::vector<std::size_t>{g.size[0], g.size[1], g.size[2]};
    tool.stats["d"] = std::vector<double>{f.d()[0], f.d()[1], f.d()[2]};
    if (random_n > 0) {
      tool.report_progress("evaluating " + std::to_string(random_n) + " random points");
      const RandomRun r = random_run(f, random_n, tool.seed(), gradient, unsigned(tool.threads()));
      tool.stats["mode"] = "random";
      tool.stats["evaluations"] = random_n;
      tool.stats["gradient"] = gradient;
      tool.stats["threads"] = tool.threads();
      tool.stats["seed"] = tool.seed();
      tool.stats["evaluation_seconds"] = r.seconds;
      tool.stats["evaluation_cpu_seconds"] = r.cpu_seconds;
      tool.stats["evaluations_per_second"] = r.seconds > 0 ? double(random_n) / r.seconds : 0.0;
      tool.stats["checksum"] = r.checksum;
      if (gradient) tool.stats["gradient_checksum"] = r.gradient_checksum;
      tool.info(std::to_string(random_n) + (gradient ? " evaluations of f and grad f in " : " evaluations of f in ") +
                std::to_string(r.seconds) + " s on " + std::to_string(tool.threads()) + " thread(s)");
      return cli::kOk;
    }
    std::ifstream file;
    std::istream* in = &std::cin;
    if (points != "-") {
      file.open(points);
      if (!file) throw Error("cannot open the points file", points);
      in = &file;
    }
    AtomicOutput out(output);
    std::ostream& os = out.stream();
    std::string line;
    std::size_t lineno = 0, count = 0, outside = 0;
    char buf[160];
    t0 = std::chrono::steady_clock::now();
    while (std::getline(*in, line)) {
      ++lineno;
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      for (char& c : line)
        if (c == ',' || c == '\t' || c == '\r') c = ' ';
      if (line.find_first_not_of(' ') == std::string::npos) continue;
      std::istringstream ls(line);
      Vec3 p;
      std::string extra;
      if (!(ls >> p[0] >> p[1] >> p[2]) || (ls >> extra))
        throw Error("line " + std::to_string(lineno) + ": expected three numbers 'x y z'", points);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw Error("line " + std::to_string(lineno) + ": coordinates must be finite", points);
      ++count;
      if (!f.in_domain(p)) {
        ++outside;
        if (!allow_outside) {
          std::snprintf(buf, sizeof buf, "line %zu: point (%.9g, %.9g, %.9g) is outside the domain of f", lineno,
                        p[0], p[1], p[2]);
          throw Error(std::string(buf) + " (the box of voxel centres; --allow-outside writes nan)", points);
        }
        os << (gradient ? "nan nan nan nan\n" : "nan\n");
        continue;
      }
      if (gradient) {
        Vec3 gr;
        const double v = f.value_gradient(p, gr);
        std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g\n", v, gr[0], gr[1], gr[2]);
      } else {
        std::snprintf(buf, sizeof buf, "%.17g\n", f.value(p));
      }
      os << buf;
    }
    if (in->bad()) throw Error("read error", points);
    out.commit();
    tool.stats["mode"] = "points";
    tool.stats["points"] = count;
    tool.stats["outside"] = outside;
    tool.stats["evaluation_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return cli::kOk;
  });
}
