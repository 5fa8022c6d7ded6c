#include "implicit/evaluate.hpp"

#include "util/cpu_time.hpp"
#include "util/error.hpp"
#include "util/hash.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <istream>
#include <ostream>
#include <sstream>
#include <thread>
#include <vector>

namespace imgmesh {

PointEvaluation evaluate_points(const PartitionOfUnity& f, std::istream& in, std::ostream& out, bool gradient,
                                bool allow_outside, const std::string& source) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string line;
  std::size_t lineno = 0, count = 0, outside = 0;
  char buf[160];
  while (std::getline(in, line)) {
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
      throw Error("line " + std::to_string(lineno) + ": expected three numbers 'x y z'", source);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw Error("line " + std::to_string(lineno) + ": coordinates must be finite", source);
    ++count;
    if (!f.in_domain(p)) {
      ++outside;
      if (!allow_outside) {
        std::snprintf(buf, sizeof buf, "line %zu: point (%.9g, %.9g, %.9g) is outside the domain of f", lineno,
                      p[0], p[1], p[2]);
        throw Error(std::string(buf) + " (the box of voxel centres; --allow-outside writes nan)", source);
      }
      out << (gradient ? "nan nan nan nan\n" : "nan\n");
      continue;
    }
    if (gradient) {
      Vec3 gr;
      const double v = f.value_gradient(p, gr);
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g\n", v, gr[0], gr[1], gr[2]);
    } else {
      std::snprintf(buf, sizeof buf, "%.17g\n", f.value(p));
    }
    out << buf;
  }
  if (in.bad()) throw Error("read error", source);
  PointEvaluation r;
  r.size = f.samples().size;
  r.d = f.d();
  r.points = count;
  r.outside = outside;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

Json PointEvaluation::to_json() const {
  Json j = Json::object();
  j["size"] = std::vector<std::size_t>{size[0], size[1], size[2]};
  j["d"] = std::vector<double>{d[0], d[1], d[2]};
  j["mode"] = "points";
  j["points"] = points;
  j["outside"] = outside;
  j["evaluation_seconds"] = seconds;
  return j;
}

// Threads take the next block as they finish one: on a shared machine a
// thread that gets less CPU does fewer blocks instead of holding up the end.
RandomEvaluation evaluate_random(const PartitionOfUnity& f, std::uint64_t n, std::uint64_t seed, bool gradient,
                                 unsigned threads) {
  const Geometry& g = f.samples();
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
          p[j] = g.world(unit01(h) * ext[0], unit01(splitmix64(h + 1)) * ext[1], unit01(splitmix64(h + 2)) * ext[2]);
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
  const double c0 = process_cpu_seconds();
  if (threads <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);
    for (auto& th : pool) th.join();
  }
  RandomEvaluation r;
  r.size = g.size;
  r.d = f.d();
  r.evaluations = n;
  r.seed = seed;
  r.gradient = gradient;
  r.threads = threads;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_seconds = process_cpu_seconds() - c0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    r.checksum += sum[b];
    r.gradient_checksum += gsum[b];
  }
  return r;
}

Json RandomEvaluation::to_json() const {
  Json j = Json::object();
  j["size"] = std::vector<std::size_t>{size[0], size[1], size[2]};
  j["d"] = std::vector<double>{d[0], d[1], d[2]};
  j["mode"] = "random";
  j["evaluations"] = evaluations;
  j["gradient"] = gradient;
  j["threads"] = threads;
  j["seed"] = seed;
  j["evaluation_seconds"] = seconds;
  j["evaluation_cpu_seconds"] = cpu_seconds;
  j["evaluations_per_second"] = seconds > 0 ? double(evaluations) / seconds : 0.0;
  j["checksum"] = checksum;
  if (gradient) j["gradient_checksum"] = gradient_checksum;
  return j;
}

} // namespace imgmesh
