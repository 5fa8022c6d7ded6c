// triangulate_pslg where double precision ends (issue 35): features a few
// units in the last place of their coordinates made CGAL's refinement
// dereference a null face or hand inf to GMP (SIGSEGV, SIGFPE). Each such
// input is an Error saying so; one just above the limit is meshed with every
// guarantee; the coordinate range is checked for PSLGs no reader made.
#include "planar/triangulate.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace imgmesh;

namespace {

// The unit square with a triangular hole of side s at (0.5, 0.5).
PlanarMesh square_with_speck(double s) {
  PlanarMesh p;
  p.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.5 + s, 0.5}, {0.5, 0.5 + s}};
  p.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 4}};
  p.holes = {{0.5 + s / 4, 0.5 + s / 4}};
  return p;
}

std::string error_of(const PlanarMesh& p) {
  try {
    triangulate_pslg(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST_CASE("features below double precision are refused, not a crash") {
  // A speck 1e-15 or 1e-16 wide at 0.5: a few units in the last place.
  for (double s : {1e-15, 1e-16}) {
    INFO(s);
    CHECK(error_of(square_with_speck(s)).find("beyond double precision") != std::string::npos);
  }
  // A needle: a vertex 1e15 away from three within 1e-15 of the origin.
  PlanarMesh needle;
  needle.points = {{1e15, 1e15}, {1e-15, 0}, {1e-15, 1e-15}, {0, 1e-15}};
  needle.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  CHECK(error_of(needle).find("beyond double precision") != std::string::npos);
}

TEST_CASE("a speck of 1e-12 at 0.5 is meshed with every guarantee") {
  // Its split points are rounded midpoints, off their segment by 1e-4 of its
  // length: the walk along the segments allows for that.
  const TriangulateResult r = triangulate_pslg(square_with_speck(1e-12));
  CHECK(r.failed_guarantee().empty());
  CHECK(r.min_angle_away_from_small_input_angles >= 20.7);
  CHECK(r.mesh.segments.size() >= 7);
}

TEST_CASE("a PSLG made by no reader is held to the coordinate range too") {
  PlanarMesh p = square_with_speck(0.1);
  p.points[1][0] = 1e31;
  CHECK(error_of(p).find("a vertex's coordinate '9.9999999999999996e+30' is out of range") != std::string::npos);
  for (auto& q : p.points) q = {q[0] * 1e-32, q[1] * 1e-32};
  p.points[1][0] = 1e-32;
  CHECK(error_of(p).find("the coordinates span only") != std::string::npos);
}

TEST_CASE("a rectangle 1 by 1e-300 is refused, not refined for ever") {
  // Its extent is 1, in the range; refinement placed no vertex after 84
  // and went on (the default angle bound, with or without the lattice).
  PlanarMesh flat;
  flat.points = {{0, 0}, {1, 0}, {1, 1e-300}, {0, 1e-300}};
  flat.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  CHECK(error_of(flat).find("beyond double precision") != std::string::npos);
}
