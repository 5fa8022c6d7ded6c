// The quad-mesh state quadsmooth works on, and the rooms that work on it
// (thesis 3.2.3; the loop that calls them is in smooth.hpp). Internal to
// lib/quadsmooth (and its tests).
//
// QuadMesh holds the quads, the stars (vertex -> incident quads), which
// vertices are fixed, the feature edges and the cached sin(mu) of every
// quad. Every operation that may be undone works on a Patch (as tri2quad's
// constructions on a LocalPatch with mark/rollback): save_patch saves the
// stars of some core vertices and of their neighbours, rollback puts them
// back exactly and drops the vertices and quads added since. compact()
// writes the result back into the PlanarMesh, removed vertices and quads
// compacted away.
#pragma once
#include "quad/predicates.hpp"
#include "quadsmooth/smooth.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <unordered_set>
#include <vector>

namespace imgmesh::quadsmooth_detail {

using Quad = std::array<int, 4>;  // corners, counter-clockwise

// sin of the smallest angle of a triangle from its squared edge lengths
// and twice its area. The smallest angle is at most 60 degrees, where sin
// is monotone: comparing sines compares angles without any trigonometry
// (the guard runs millions of times). It is opposite the shortest edge:
// sin = 2A / (product of the other two).
inline double sin_min_angle(double l1, double l2, double l3, double area2) {
  double den;
  if (l1 <= l2 && l1 <= l3) den = l2 * l3;
  else if (l2 <= l3) den = l1 * l3;
  else den = l1 * l2;
  if (!(den > 0)) return 0;
  return std::fabs(area2) / std::sqrt(den);
}

// sin(Joe's mu); mu <= 45 degrees so the sine orders quads like mu does.
// The four triangles share the four sides and two diagonals.
inline double sin_mu(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  auto sq = [](const Point2& p, const Point2& q) {
    return (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]);
  };
  auto cross = [](const Point2& o, const Point2& p, const Point2& q) {
    return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
  };
  const double ab = sq(a, b), bc = sq(b, c), cd = sq(c, d), da = sq(d, a), ac = sq(a, c), bd = sq(b, d);
  // Diagonal bd: [a,b,d], [c,d,b]; diagonal ac: [a,b,c], [d,a,c].
  return std::min(std::min(sin_min_angle(ab, bd, da, cross(a, b, d)), sin_min_angle(cd, bd, bc, cross(c, d, b))),
                  std::min(sin_min_angle(ab, bc, ac, cross(a, b, c)), sin_min_angle(da, ac, cd, cross(d, a, c))));
}

// ---- smooth_mesh.cpp: the state ------------------------------------------

// The directed edges a -> b of all elements grouped by a (a counting sort,
// in element order): for each vertex, the elements around it and the next
// vertex in each. The conformity check and the smoother's adjacency both
// read it; no sort and no hashing, so 10^6 quads take a fraction of a second.
struct Stars {
  std::vector<int> start, next, elem;
  // The element holding the directed edge b -> a, or -1.
  int twin(int a, int b) const {
    for (int i = start[b]; i < start[b + 1]; ++i)
      if (next[i] == a) return elem[i];
    return -1;
  }
};

// Checks the input contract (see check_quad_mesh) and returns the stars.
Stars conforming_stars(const PlanarMesh& m, const std::string& path);

// A sliding vertex v: the fixed ends A, B of its straight chain and the two
// feature neighbours u, w bounding the slide.
struct Slide { int v, A, B, u, w; };

// The stars of some core vertices and of their neighbours, saved so that a
// topological operation plus relaxation can be undone. Vertices and quads
// an operation adds are appended to verts and quads (after the saved ones).
struct Patch {
  std::vector<int> quads, verts;  // verts: the core first, then the ring, then new ones
  std::size_t ncore = 0;
  std::vector<Quad> q;
  std::vector<char> qdead, vdead;
  std::vector<std::vector<int>> vq;
  std::vector<Point2> p;
};

// Valence (Canann et al.): the quads around v in the fan holding q, bounded
// by feature edges, and the number the fan's angle wants, one a 90 degrees
// (4 around a closed star).
struct Fan { int count, ideal; bool closed; };

struct QuadMesh {
  // The quads of `mesh` (its 4-node elements), which vertices are fixed and
  // which slide (SmoothOptions::slide_boundary), from its conforming stars.
  QuadMesh(PlanarMesh& mesh, const SmoothOptions& opt, const Stars& stars);

  PlanarMesh& mesh;
  std::vector<Point2>& points;               // mesh.points, moved in place
  const double split_below;                  // sin of SmoothOptions::split_below
  std::vector<Quad> quads;                   // copies of the 4-node elements
  std::vector<int> quad_element;             // element index of each quad
  std::vector<char> quad_dead;
  std::vector<double> quad_sin_mu;           // cached sin(mu)
  std::vector<std::vector<int>> vertex_quads;  // the stars
  std::vector<char> fixed;                   // never moves (and never merges away)
  std::vector<char> vertex_dead;
  std::unordered_set<std::uint64_t> features;  // boundary, segment and region-boundary edges
  std::vector<Slide> slides;
  std::vector<char> active;                  // smoothing work list (see smooth_pass)
  // Poor quads whose pair splits all failed: a later try rarely succeeds
  // and costs a relaxation each, so they are tried again only once changed.
  std::vector<char> tried;
  // The compass search waits for the first angle-based pass: most poor
  // quads of a distorted mesh are fixed by it, at a fraction of the cost.
  bool climb = false;
  std::size_t fixed_vertices = 0;            // fixed vertices with a quad around

  // Feature edges join two fixed vertices: test that first, hash rarely.
  bool is_feature(int a, int b) const { return fixed[a] && fixed[b] && features.count(edge_key(a, b)) != 0; }
  double sin_mu_of(const Quad& q) const { return sin_mu(points[q[0]], points[q[1]], points[q[2]], points[q[3]]); }
  bool convex(const Quad& q) const {
    return is_strictly_convex(points[q[0]], points[q[1]], points[q[2]], points[q[3]]);
  }
  int quad_with_edge(int a, int b) const;  // the quad holding the directed edge a -> b, or -1
  Fan fan(int v, int q) const {
    return fixed[v] ? fixed_fan(v, q) : Fan{int(vertex_quads[v].size()), 4, true};  // a free vertex's star is closed
  }
  Fan fixed_fan(int v, int q) const;
  // New corners for quad q (its stars and cached sine follow).
  void set_quad(int q, const Quad& nq);
  void remove_from(int v, int q) {
    auto& l = vertex_quads[v];
    l.erase(std::remove(l.begin(), l.end(), q), l.end());
  }
  // Puts the vertices of the quads around v back on the smoothing work list
  // (after a topological operation near v).
  void wake(int v) {
    for (int q : vertex_quads[v])
      for (int w : quads[q]) active[w] = 1;
  }

  void save_patch(std::initializer_list<int> core, Patch& pt);
  void save_patch(const std::vector<int>& core, Patch& pt);
  // Puts the patch back as saved; the vertices and quads appended to it
  // since must be the latest added (they are dropped).
  void rollback(Patch& pt);
  double patch_worst(const Patch& pt) const;
  // The sines of the patch's live quads, ascending: operations compare
  // these lexicographically, so one bad quad elsewhere in the patch does not
  // hide an improvement of the next worst.
  std::vector<double> patch_sines(const Patch& pt) const;

  // A new free vertex at p (point attributes and marker zero), and a new quad
  // element of q's region (its corners set by set_quad); the drop_* undo the
  // latest one.
  int add_vertex(const Point2& p);
  void drop_vertex();
  int add_quad(int like);
  void drop_quad();

  // Writes quads and points back into mesh, dead ones removed (segment ids
  // renumbered).
  void compact();

private:
  void save_patch(const int* core, std::size_t ncore, Patch& pt);
  std::vector<int> vertex_stamp, quad_stamp;  // save_patch's marks
  int stamp_id = 0;
};

// Moves x to the centroid of the region where every quad around it is
// strictly convex, the others standing (the placement rule of
// doc/tri2quad.md section 1), the sines of its quads updated; false, x not
// moved, if it is empty.
bool place_in_star(QuadMesh& qm, int x);

// True if `now` comes after `before` in lexicographic order, each entry
// compared with a relative margin (patch_sines of after and before).
bool lex_better(const std::vector<double>& now, const std::vector<double>& before);

// ---- smooth_angle.cpp: angle-based smoothing, compass search, colouring ---

// Zhou and Shimada's angle-based position for the interior vertex v; false
// for an open or too large star.
bool angle_based_target(const QuadMesh& qm, int v, Point2& out);
// Moves v to p (with back-off toward the current position) only if no quad
// around it becomes non-convex or drops below the worst sin(mu) around v;
// slide_line: p is projected on the line of the slide s first.
bool try_move(QuadMesh& qm, int v, Point2 p, bool slide_line, const Slide* s);
// Compass search on the energy sum 1/sin(mu) around v (a soft minimum), the
// worst mu never dropping; h2: a squared edge length around v.
bool optimize_star(QuadMesh& qm, int v, double h2);
// Beyond the thesis: a compass search on the sum of sin(mu) around v (the
// mean quality), no quad around becoming non-convex or worse than the worst
// mu around v before; with grading > 0, nor the largest size ratio between
// v's quads and their neighbours (grading_ratio) past grading or its value
// before, whichever is larger; true if v moved.
bool raise_mean(QuadMesh& qm, int v, double h2, double grading = 0);
// raise_mean on every free vertex next to a quad of mu below 40 degrees.
void mean_pass(QuadMesh& qm, SmoothStats& st, double grading = 0);
// A compass search on the smallest, then the second smallest, sin(mu)
// around v, no quad around becoming non-convex; true if v moved.
bool raise_worst(QuadMesh& qm, int v, double h2);
// The same moving two free vertices u, v (together, apart or one alone),
// first step h; on the union of their stars.
bool raise_worst_pair(QuadMesh& qm, int u, int v, double h);
// raise_worst on every free vertex next to a quad of mu below 12 degrees,
// then raise_worst_pair on the free ends of each edge of such a quad.
void worst_pass(QuadMesh& qm, SmoothStats& st);
// The same moving the two free ends u, v of an edge together, step h.
bool optimize_edge(QuadMesh& qm, int u, int v, double h);
// One guarded angle-based move then (once qm.climb) the compass search;
// kMoved, kRejected, kOptimized bits, and kFar: moved by over
// sqrt(kWakeFar) of an edge.
enum { kMoved = 1, kRejected = 2, kOptimized = 4, kFar = 8 };
int smooth_vertex(QuadMesh& qm, int v);
// A compass search on the largest size ratio between the quads around v
// and their neighbours (grading_ratio), stopping once within target; no
// quad around becoming non-convex or going under its own sin(mu) or floor,
// whichever is lower; true if v moved.
bool raise_grading(QuadMesh& qm, int v, double h2, double target, double floor);
// Smooths the vertices of a patch after a topological operation.
void relax(QuadMesh& qm, const Patch& pt);

// Colour classes of the smoothing vertices: two that share a quad differ.
struct Colouring {
  std::vector<std::vector<int>> classes;
  bool stale = true;  // recompute: the topology changed
};
void colour(const QuadMesh& qm, Colouring& colouring);
// One pass over the active vertices, colour by colour, over `threads`.
void smooth_pass(QuadMesh& qm, Colouring& colouring, int threads, SmoothStats& st);
// Sliding vertices to the midpoint of their neighbours along their segment.
void slide_pass(QuadMesh& qm, SmoothStats& st);
// Edge moves for slivers along a segment.
void edge_pass(QuadMesh& qm, SmoothStats& st);

// ---- smooth_swap.cpp -------------------------------------------------------

// The diagonal swap (or, for a poor pair, the pair split) across edge i of
// quad q1; true if q1 changed. Counted in st.
bool swap_diagonal(QuadMesh& qm, int q1, int i, SmoothStats& st);
void swap_pass(QuadMesh& qm, SmoothStats& st);

// ---- smooth_split.cpp ------------------------------------------------------

// A re-meshed, settled patch is taken when accept(patch, its sorted sines
// before) says so; empty: when its sorted sines rose (lex_better).
using Accept = std::function<bool(const Patch&, const std::vector<double>&)>;

// The pair across edge i of quad q1 (u = its corner i, w = corner i + 1):
// q2, the quad holding w -> u, and their union H = u, c, d, w, a, b
// (counter-clockwise). False where the edge is a feature, has no quad
// beyond it, or the six corners are not distinct.
bool pair_hexagon(const QuadMesh& qm, int q1, int i, int& q2, int (&H)[6]);

// Splits the pair q1, q2 (their union the hexagon H, counter-clockwise) into
// three quads around a new point or four around two; returns 3 or 4, or 0
// with the quads, stars and points exactly as they were (tried marks of q1
// and q2 cleared).
int split_pair(QuadMesh& qm, int q1, int q2, const int (&H)[6], const Accept& accept = {});
// Beyond the thesis, after the clean-up, the sharp corners and the final
// collapse: split_pair on each pair of a quad under 10 degrees, which the
// passes' swaps no longer reach (counted with the splits).
void final_split_pass(QuadMesh& qm, SmoothStats& st);

// ---- smooth_doublet.cpp ----------------------------------------------------

// Removes the free valence-2 vertex v by merging its two quads, if the
// merged quad is strictly convex and no worse; true if done.
bool remove_doublet(QuadMesh& qm, int v);
// Beyond the thesis: removes the free valence-3 vertex m when two of its
// quads share a fixed corner c whose angle wants one quad (a sharp input
// corner split in two, each quad's mu then at most a quarter of c's angle):
// its three quads become two, c in one, by the hexagon's diagonal beside c.
// Taken if, once the patch is relaxed, its worst mu rose; true if done.
// respoke_too: else, m joined to the hexagon's other three corners instead
// (doublets left by it merged), c then in one quad; else the split keeping
// c whole even where its quads are not strictly convex as the corners
// stand, the free hexagon corners it leaves in two quads merged away in
// turn and the patch's free vertices placed, relaxed and climbed on the
// worst mu (taken if the patch's sorted sines rose).
bool open_sharp_corner(QuadMesh& qm, int m, bool respoke_too);
// Beyond the thesis: collapses quad q along its diagonal from corner diag
// (0 or 1), the free end merged into the other (at their midpoint if both
// are free), where the ends it leaves in two quads would stop collapse_quad:
// those doublets merge too; the patch's free vertices are then placed where
// every quad is strictly convex, relaxed and climbed on the worst mu. Taken
// if the patch's sorted sines rose; true if done.
bool collapse_and_merge(QuadMesh& qm, int q, int diag, const Accept& accept = {});
// collapse_and_merge on every quad under 12 degrees.
void final_collapse_pass(QuadMesh& qm, SmoothStats& st);
// After a re-meshing of the patch pt (its sorted sines were `before`):
// the free corners of each quad not strictly convex placed where their
// quads are, the patch relaxed, its free vertices climbed on the worst mu.
// True, the patch's vertices woken, if every quad of the patch is strictly
// convex and its sorted sines rose (lex_better); the caller rolls back
// otherwise.
bool settle(QuadMesh& qm, const Patch& pt, const std::vector<double>& before, const Accept& accept = {});
// remove_doublet, else open_sharp_corner, on every vertex.
void doublet_pass(QuadMesh& qm, SmoothStats& st);
// open_sharp_corner with its re-joining way on every vertex.
void sharp_corner_pass(QuadMesh& qm, SmoothStats& st);

// ---- smooth_tip.cpp ---------------------------------------------------------

// Beyond the thesis: the fixed vertex c whose fan holding quad q is two or
// three quads where its angle wants one (a wedge tip of the curve split in
// two, each quad's mu then at most a quarter of the tip's angle): the quads
// of that fan and those around their vertices within the region (1 to
// max_rings times over) make patches, topological disks; a patch's free
// inner vertices go and it is re-quadded around new inner points (a fan
// around one; a chain of two to four, the strip that follows a wedge's two
// sides to its tip; a ring of four around a quad), every layout of every
// patch placed, relaxed and climbed (settle). Of those whose quads are all
// strictly convex and whose sorted sines beat their patch's (lex), the best
// (lex, on the quads around the largest patch) is taken; true if one was.
bool open_wedge_tip(QuadMesh& qm, int c, int q, int max_rings);
// open_wedge_tip, up to three rings, on each fixed vertex with such a fan
// holding a quad under 12 degrees (counted in st.wedge_tips).
void tip_pass(QuadMesh& qm, SmoothStats& st);

// ---- smooth_grade.cpp --------------------------------------------------------

// The size of quad q over that of its neighbour across an edge, or the
// inverse, whichever is larger (sizes: the square roots of the areas); the
// largest over q's edges, 1 with no neighbour.
double grading_ratio(const QuadMesh& qm, int q);
// Beyond the thesis: the pairs of neighbouring quads whose sizes differ by
// more than `target` (a small quad of tri2quad's Steiner constructions
// beside a large one, which the passes aiming at mu leave as they are):
// rounds of raise_grading on the free corners of their quads, collapse_and_
// merge of the smaller quad, split_pair of the larger with a neighbour; no
// quad going under 10 degrees (or its own mu if lower), an operation taken
// if every quad of its patch ends under the pair's ratio.
void grading_pass(QuadMesh& qm, SmoothStats& st, double target);

// ---- smooth_collapse.cpp ---------------------------------------------------

// Collapses quad q along its diagonal from corner `diag` (0 or 1): the two
// ends merge (at the fixed one, else at the midpoint); true if done.
bool collapse_quad(QuadMesh& qm, int q, int diag, SmoothStats& st);
void collapse_pass(QuadMesh& qm, SmoothStats& st);

} // namespace imgmesh::quadsmooth_detail
