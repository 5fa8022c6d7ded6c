// implicit-eval's library calls: the text protocol against f itself, the
// random benchmark's checksums against the number of threads and a direct
// sum; the construction's refusal of a non-well-composed image.
#include "helpers.hpp"
#include "implicit/evaluate.hpp"
#include "implicit/implicit_file.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {
std::string g17(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
} // namespace

TEST_CASE("evaluate_points: one line per point, f as value() gives it", "[evaluate]") {
  const PartitionOfUnity f = implicit_from_well_composed(random_wc(9, 8, 10, 3));
  const Vec3 p = f.samples().world(3.25, 4.5, 2.75), q = f.samples().world(1.5, 1.0, 6.125);
  std::ostringstream text;
  text << "# header\n" << g17(p[0]) << ", " << g17(p[1]) << "\t" << g17(p[2]) << "\n\n"
       << g17(q[0]) << ' ' << g17(q[1]) << ' ' << g17(q[2]) << "  # comment\n";
  std::istringstream in(text.str());
  std::ostringstream out;
  const PointEvaluation r = evaluate_points(f, in, out, false, false, "pts");
  CHECK(r.points == 2);
  CHECK(r.outside == 0);
  CHECK(out.str() == g17(f.value(p)) + "\n" + g17(f.value(q)) + "\n");
  CHECK(r.to_json().at("mode").string() == "points");

  std::istringstream in2(text.str());
  std::ostringstream out2;
  evaluate_points(f, in2, out2, true, false, "pts");
  Vec3 gr;
  const double v = f.value_gradient(p, gr);
  CHECK(out2.str().substr(0, out2.str().find('\n')) ==
        g17(v) + " " + g17(gr[0]) + " " + g17(gr[1]) + " " + g17(gr[2]));
}

TEST_CASE("evaluate_points: outside the domain and bad lines", "[evaluate]") {
  const PartitionOfUnity f = implicit_from_well_composed(random_wc(6, 6, 6, 1));
  const Vec3 far = f.samples().world(-3, 2, 2);
  const std::string line = g17(far[0]) + " " + g17(far[1]) + " " + g17(far[2]) + "\n";
  std::istringstream in(line);
  std::ostringstream out;
  CHECK_THROWS_AS(evaluate_points(f, in, out, false, false, "pts"), Error);
  std::istringstream in2(line);
  std::ostringstream out2;
  const PointEvaluation r = evaluate_points(f, in2, out2, true, true, "pts");
  CHECK(r.outside == 1);
  CHECK(out2.str() == "nan nan nan nan\n");
  std::istringstream bad("1 2\n");
  CHECK_THROWS_AS(evaluate_points(f, bad, out, false, true, "pts"), Error);
  std::istringstream extra("1 2 3 4\n");
  CHECK_THROWS_AS(evaluate_points(f, extra, out, false, true, "pts"), Error);
}

TEST_CASE("evaluate_random: the checksums do not depend on the threads", "[evaluate]") {
  const PartitionOfUnity f = implicit_from_well_composed(random_wc(8, 9, 7, 5));
  const std::uint64_t n = 3 * 65536 + 123;  // several blocks, one of them partial
  const RandomEvaluation one = evaluate_random(f, n, 11, true, 1), three = evaluate_random(f, n, 11, true, 3);
  CHECK(one.checksum == three.checksum);
  CHECK(one.gradient_checksum == three.gradient_checksum);
  CHECK(one.evaluations == n);
  CHECK(evaluate_random(f, n, 12, false, 1).checksum != one.checksum);
  CHECK(std::isfinite(one.checksum));  // every point inside the domain
  CHECK(one.to_json().contains("gradient_checksum"));
  CHECK_FALSE(evaluate_random(f, 1000, 11, false, 2).to_json().contains("gradient_checksum"));
}

TEST_CASE("implicit_from_well_composed refuses a critical configuration and reports f", "[file]") {
  BinaryImage im(grid(6, 6, 6), 0);
  im(2, 2, 2) = 1;
  im(3, 3, 2) = 1;  // C1: two voxels sharing only an edge
  CHECK_THROWS_AS(implicit_from_well_composed(im), Error);
  im(3, 3, 2) = 0;
  ImplicitReport rep;
  const PartitionOfUnity f = implicit_from_well_composed(im, &rep);
  CHECK(rep.foreground == 1);
  CHECK(rep.size == f.samples().size);
  CHECK(rep.g_min == f.g_min());
  CHECK(rep.to_json().at("cells").integer() == 5 * 5 * 5);
}
