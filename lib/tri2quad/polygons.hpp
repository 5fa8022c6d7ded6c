// Quadrangulations of the small polygons of the thesis's appendix B and the
// triangle splits of section 3.2 (de Berg's 3-quad split, Joe's 5-quad
// split), as used by tri2quad. Internal to lib/tri2quad (and its tests).
//
// Every construction works on a LocalPatch: known vertices (with their ids in
// the output mesh) and new Steiner points (id -1). Steiner points are placed
// in floating point by the placement rule of doc/tri2quad.md (each output
// quad turn in which the point is the only unknown is an open half-plane;
// clip a bounding polygon by them and take the centroid, then other points
// of the region), and every output quad is then checked with exact
// predicates (CGAL orientation) plus a relative margin. A construction that
// fails its checks returns false and leaves the patch as it was, so the
// caller can fall back to another one.
#pragma once
#include "planar/triangle_io.hpp"
#include "quad/half_plane_clip.hpp"
#include "quad/predicates.hpp"

#include <array>
#include <vector>

namespace imgmesh::tri2quad_detail {

using P2 = Point2;
using Quad = std::array<int, 4>;  // local indices, counter-clockwise

struct LocalPatch {
  std::vector<P2> p;
  std::vector<int> gid;  // output id, or -1 for a new Steiner point
  std::vector<Quad> quads;
  int add_known(const P2& x, int id) { p.push_back(x); gid.push_back(id); return int(p.size()) - 1; }
  int add_new(const P2& x = {0, 0}) { p.push_back(x); gid.push_back(-1); return int(p.size()) - 1; }
  struct Mark { std::size_t np, nq; };
  Mark mark() const { return {p.size(), quads.size()}; }
  void rollback(Mark m) { p.resize(m.np); gid.resize(m.np); quads.resize(m.nq); }
};

// A polygon as local indices, counter-clockwise.
using Ring = std::vector<int>;

// Lemma B.1.1: hexagon H fully quadrangulated with at most `budget` interior
// Steiner points (templates T0, T1, then peeling, doc/tri2quad.md 3.2).
bool hexagon(LocalPatch& lp, const Ring& h, int budget = 3);

// Lemma B.1.2: quadrilateral c with the interior point q: 5 quads, 3 new
// points (nested template; convex closed form, pushed homothety, search).
bool quad_with_point(LocalPatch& lp, const Ring& c, int q);
// Step 5(c): a quadrilateral that is not strictly convex, with a free
// interior point at the centre of its kernel: 5 quads, 4 new points.
bool quad_nested_free(LocalPatch& lp, const Ring& c);

// Lemma B.2.1 for a pentagon v (v[0]v[1] the outgoing edge): quads plus a
// leftover triangle on the outgoing edge; returns the apex of that triangle
// (a local index) or -1. kind: 0 ear (no point), 1 type 1, 2 type 2, 3 in
// place of type 3 (which would put a point on the outgoing edge): a new apex
// and B.1.1 on the hexagon left, with at most `hexagon_budget` points (1
// keeps the lemma's 3 quads and 2 points).
int pentagon(LocalPatch& lp, const Ring& v, int* kind = nullptr, int hexagon_budget = 3);

// Lemma B.3.1 for a heptagon v (v[0]v[1] the outgoing edge): a leftover
// triangle on the outgoing edge (an ear, or with a new apex and the path of
// doc/tri2quad.md 3.6), hexagons for the rest. Returns the apex or -1.
int heptagon(LocalPatch& lp, const Ring& v, int* kind = nullptr);
// An octagon o closed with at most `budget` interior points (at most
// budget + 3 quads): a diagonal and B.1.1, or a path through one new point
// between opposite vertices and two hexagons (doc/tri2quad.md 3.6).
bool octagon(LocalPatch& lp, const Ring& o, int budget);
// The heptagon v with the point mpt on its outgoing edge v0v1, closed as
// the octagon (mpt, v1, ..., v6, v0) with at most 4 interior points: 7
// quads and 5 points for its 5 triangles, no leftover.
bool heptagon_closed(LocalPatch& lp, const Ring& v, int mpt);

// Joe's split of triangle (a, b, c) with the point m on edge bc (section
// 3.8 of doc/tri2quad.md): 5 quads, 4 new interior points.
bool joe_split(LocalPatch& lp, int a, int b, int m, int c);
// de Berg's split: m_ab, m_bc, m_ca on the edges, one new centre point.
bool deberg_split(LocalPatch& lp, int a, int b, int c, int mab, int mbc, int mca);

} // namespace imgmesh::tri2quad_detail
