// FacetCycle's stages (thesis 8.2; facet_cycle.cpp runs them): the Voronoi
// facet h of a Delaunay edge pq on its bisector plane Pi, rasterised row by
// row into runs of one sign (facet_cycle_raster.cpp), the sign regions that
// never reach h's border, and a point of S on the cycle around one. The
// stages see h on Pi only: what the triangulation gives (pq's ring, the
// cells' circumcentres) is read in facet_cycle.cpp. Private to lib/surface.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/facet_cycle.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

// A half-plane A a + B b <= C on Pi (x = m + a u + b v).
struct FacetHalfPlane {
  double A, B, C;
};
// Samples s..e of row j, all of one sign (sg: inside).
struct FacetRun {
  long j, s, e;
  signed char sg;
};
// An active cube's rows j0..j1 and samples s..e (one sample wider each side).
struct FacetCubeSpan {
  long j0, j1, s, e;
};

// Scratch reused across checks, one per thread (no allocation per edge).
struct FacetScratch {
  std::vector<FacetHalfPlane> hp;                     // h's edges, then the box's six
  std::vector<FacetHalfPlane> hp_hi, hp_lo, hp_flat;  // by the sign of A, for the rows
  std::vector<long> lo, hi;                           // each row's first and last sample
  std::vector<double> alo_row, ahi_row;               // h's exact border on each row
  std::vector<std::array<double, 2>> poly, poly_next;  // h widened, for the rows near it
  std::vector<FacetCubeSpan> cube_spans;
  std::vector<std::pair<long, long>> spans;           // row j's: [row_span[j], row_span[j + 1]), by s
  std::vector<long> row_span, fill_at;
  std::vector<FacetRun> runs, reference;
  std::vector<long> row_run;                          // row j's runs: [row_run[j], row_run[j + 1])
  std::vector<long> parent;                           // the runs' union-find
  std::vector<char> open;                             // a region (at its root) reaches h's border
  std::vector<std::pair<double, std::array<Vec3, 2>>> cands;  // (-distance^2 to p, sample pair)
};

// One facet h on Pi, its samples (a0 + i step, b0 + j step) and their runs.
// The stages in the order facet_cycle() calls them; each reads what the
// ones before it left.
struct FacetRaster {
  FacetRaster(const SurfaceSampler& f, FacetScratch& s) : f(f), grid(f.grid()), s(s) {}
  const SurfaceSampler& f;
  const CubeGrid& grid;
  FacetScratch& s;
  Vec3 pp, m, n, u, v;  // p; Pi through m, normal n, axes u and v
  double a0 = 0, a1 = 0, b0 = 0, b1 = 0;  // h's extent on Pi
  double step = 0, b_last = 0, eps = 0;   // the samples' step, the last row's b, rounding
  long nb = 0;                            // rows
  long rows_used = 0;                     // rows with a sample in h
  long regions = 0;                       // sign regions (join_regions)
  bool no_active = false;                 // no active cube near h: every sample takes one sign
  bool walk_all = true;                   // walk every row cube by cube (no spans)
  bool bounded = true;                    // h's extent is its Voronoi vertices' (else the box's)
  bool any_neg = false, any_pos = false;  // samples of each sign

  // Pi, the bisector plane of pq, and its frame; false if p == q.
  bool frame(const Vec3& p, const Vec3& q);
  // h's half-planes, one per neighbour w in pq's ring (V(p) against V(w));
  // then extent() adds the box's and cuts h's extent (its Voronoi
  // vertices', or the box's when unbounded) to the box's: false if empty.
  // It sets the samples' step and rows.
  void add_neighbour(const Vec3& w);
  bool extent(bool bounded, double va0, double va1, double vb0, double vb1);
  // No active block meets the samples' rectangle (false beyond 64M
  // samples, where the answer must stay kSkipped).
  bool no_active_block() const;
  // Each row's samples in h (lo..hi) and exact border; with `compare`,
  // false unless the rows without the box's loose half-planes agree with all.
  bool find_rows(bool compare);
  long sample_count() const;
  // The stretches of each row near active cubes (unless every row is
  // walked); no_active when Pi meets no active cube among the samples'.
  void find_spans(FacetWalk how);
  // The runs of every row; kCompare: nullptr, else the walk ("full" or
  // "span") whose runs differ from the samples' signs by definition.
  const char* sign_runs(FacetWalk how);
  // The sign regions (4-connected runs of one sign), and those that reach
  // h's border (open); the others are enclosed by a cycle of S. False when
  // every region is open (it stops there: no cycle).
  void join_regions();
  bool open_regions();
  // The enclosed regions' sample pairs across S, farthest from p first;
  // the first that brackets a root of f gives x on S.
  void enclosed_pairs();
  bool cycle_point(Vec3& x);

  // x = m + a u + b v, and sample i of row j. Inlined, as cube_of (called
  // per sample and per cube step).
  __attribute__((always_inline)) Vec3 at(double a, double b) const {
    return Vec3{m[0] + a * u[0] + b * v[0], m[1] + a * u[1] + b * v[1], m[2] + a * u[2] + b * v[2]};
  }
  __attribute__((always_inline)) Vec3 point(long i, long j) const { return at(a0 + i * step, b0 + j * step); }

private:
  double inv_s[3] = {0, 0, 0}, inv_u[3] = {0, 0, 0}, inv_step = 0;
  bool loose(const FacetHalfPlane& h) const;
  void rows(bool all);
  void row_range(long& j0, long& j1) const;
  void collect_cube_spans(const long c0[3], const long c1[3]);
  void deal_spans();
  void build_runs(FacetWalk mode);
  void append(long j, long s0, long e0, bool in);
  void fill(long j, long s0, long e0);
  void decide(long j, long s0, long e0, const Vec3& xs);
  void walk(long j, long s0, long e0);
  // The cube of x. It multiplies by 1/s: a sample within rounding of a
  // face may go to either cube, and takes the same sign in both (f's sign on
  // an inactive cube's faces is its corners', F1).
  __attribute__((always_inline)) void cube_of(const Vec3& x, long c[3]) const {
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(floor_long(x[k] * inv_s[k]), 0L, grid.n[k] - 2);
  }
  bool sign_at(double a, double b) const;
  double column_end(double a, int dir) const;
  bool exits(const FacetRun& x) const;
  long find(long r);
};

} // namespace imgmesh::surface_detail
