// quadsmooth's loop (see smooth.hpp) and its result.
#include "quadsmooth/smooth.hpp"

#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>

namespace imgmesh {

Json SmoothStats::to_json() const {
  Json j = Json::object();
  j["before"] = before.to_json();
  j["after"] = after.to_json();
  Json ops = Json::object();
  ops["passes"] = passes;
  ops["moves"] = moves;
  ops["slides"] = slides;
  ops["rejected_moves"] = rejected;
  ops["worst_mu_climbs"] = optimized;
  ops["edge_moves"] = edge_moves;
  ops["mean_mu_climbs"] = mean_climbs;
  ops["max_min_climbs"] = worst_climbs;
  ops["diagonal_swaps"] = swaps;
  ops["valence_swaps"] = valence_swaps;
  ops["pair_splits"] = splits;
  ops["pair_splits_four"] = splits_four;
  ops["doublets_removed"] = doublets;
  ops["sharp_corners_opened"] = sharp_corners;
  ops["wedge_tips_opened"] = wedge_tips;
  ops["quad_collapses"] = collapses;
  ops["valence_collapses"] = valence_collapses;
  ops["grading_moves"] = grading_moves;
  ops["grading_collapses"] = grading_collapses;
  ops["grading_splits"] = grading_splits;
  ops["fixed_vertices"] = fixed_vertices;
  j["operations"] = ops;
  // Checked, not assumed: every quad that came in strictly convex stays so.
  Json g = Json::object();
  g["strictly_convex"] = after.non_convex == 0;
  g["no_quad_made_nonconvex"] = after.non_convex <= before.non_convex;
  g["min_mu_not_decreased"] = after.min_mu >= before.min_mu - 1e-9;
  j["guarantees"] = g;
  return j;
}

std::string SmoothStats::failed_guarantee() const {
  if (after.non_convex == 0) return {};
  if (after.non_convex > before.non_convex)
    return std::to_string(after.non_convex - before.non_convex) + " quad(s) made non-convex";
  return std::to_string(after.non_convex) + " quad(s) are not strictly convex (they came in that way)";
}

void check_quad_mesh(const PlanarMesh& m, const std::string& path) { quadsmooth_detail::conforming_stars(m, path); }

SmoothStats smooth_quad_mesh(PlanarMesh& mesh, const SmoothOptions& opt) {
  using namespace quadsmooth_detail;
  const Stars stars = conforming_stars(mesh, {});
  SmoothStats st;
  st.before = quality_report(mesh);
  QuadMesh qm(mesh, opt, stars);
  st.fixed_vertices = qm.fixed_vertices;
  Colouring colouring;
  const int passes = std::max(0, opt.iterations);
  for (int it = 0; it < passes; ++it) {
    // Clean-up every third pass, once smoothing has done what it can, then
    // smoothing resumes on the new topology.
    if (opt.cleanup && it > 0 && it % 3 == 0) {
      const std::size_t ops = st.swaps + st.splits + st.collapses + st.doublets + st.sharp_corners;
      swap_pass(qm, st);
      collapse_pass(qm, st);
      doublet_pass(qm, st);
      edge_pass(qm, st);
      // New colours only where the topology changed (the operations woke
      // the vertices around them).
      colouring.stale = st.swaps + st.splits + st.collapses + st.doublets + st.sharp_corners != ops;
    }
    smooth_pass(qm, colouring, opt.threads, st);
    qm.climb = true;
    if (opt.slide_boundary) slide_pass(qm, st);
    st.passes = it + 1;
    if (opt.progress) opt.progress(it + 1, passes);
  }
  if (opt.cleanup && passes > 0) {
    swap_pass(qm, st);
    doublet_pass(qm, st);
  }
  if (opt.cleanup && passes > 0) {
    sharp_corner_pass(qm, st);
    final_collapse_pass(qm, st);
    final_split_pass(qm, st);
    tip_pass(qm, st);
  }
  for (int r = 0; passes > 0 && r < 4; ++r) worst_pass(qm, st);
  for (int r = 0; passes > 0 && r < opt.mean_rounds; ++r) mean_pass(qm, st);
  // The grading pass last: the max-min and mean climbs, blind to size,
  // undid most of its gains when they ran after it. Half the mean rounds
  // again, no ratio around a vertex raised past the aim, win back the mean
  // its moves cost.
  if (opt.cleanup && passes > 0 && opt.grading > 0) {
    grading_pass(qm, st, opt.grading);
    for (int r = 0; r < (opt.mean_rounds + 1) / 2; ++r) mean_pass(qm, st, opt.grading);
  }
  qm.compact();
  st.after = quality_report(mesh);
  return st;
}

} // namespace imgmesh
