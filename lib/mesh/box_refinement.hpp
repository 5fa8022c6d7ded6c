// --outside (implicit2tet's region 2, seg2tet's region 0): the box B the
// outside fills, its 8 corners in the mesher's triangulation so that the
// convex hull is B, and
// Shewchuk's boundary rule (Tetrahedral mesh generation by Delaunay
// refinement, 1998) for a bad cell whose circumcentre c cannot go in: c
// outside B, or c in the diametral ball of a box subsegment or subfacet (a
// hull edge on an edge of B, a hull triangle) of its conflict zone. Then
//   an encroached subsegment: split at its midpoint;
//   else the encroached subfacet (c outside B: the largest hull triangle
//   in the conflict zone of c's projection onto B): its circumcentre p,
//   unless p encroaches a subsegment or lies off its face, when that
//   subsegment is split instead.
// A template over the CGAL Delaunay triangulation (implicit2tet's and
// seg2tet's: both meshers' TUs include CGAL) and its vertex ids.
//
// Termination (why B is the image extent, half a voxel beyond the samples):
// S lies in the cubes of voxel centres, so every point of the box is at
// least g = min spacing / 2 from S. Box points are inserted without any
// test against the surface Delaunay balls: a box point never makes the
// surface refine near the box (the cascade box split -> facet split ->
// smaller box split ...), and if its Voronoi cell reaches S, the restricted
// facet it makes has a surface ball of radius >= g, whose centre goes in
// (off-surface facets, tet_refinement.cpp) >= g from every vertex: finitely
// many on S. Each box point goes in at least `floor` from every vertex
// (else it is refused and the bad cell stays, reported), so the box points
// are a floor-packing of the box's surface: finitely many. The cells: a
// circumcentre of a cell with radius-edge ratio above R >= 2 is more than
// 2 l_min from every vertex, and l_min >= m, the least insertion radius so
// far, so it never lowers m; size-bad cells' are farther than --cell-size;
// slivers', encroached facets' and box points have floors (1e-3 voxel,
// `floor`). So within a round every point goes in at least min(m, floors)
// > 0 from the others, inside bounded B: finitely many; rounds are capped.
#pragma once
#include <CGAL/Kernel/global_functions.h>
#include <CGAL/iterator.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace imgmesh {

// Tr: a CGAL Delaunay_triangulation_3 of double points; IdOf(Vh): a
// vertex's id (finite vertices).
template <class Tr, class IdOf>
class BoxRefinement {
public:
  using Vec3 = std::array<double, 3>;
  using Point = typename Tr::Point;
  using Vh = typename Tr::Vertex_handle;
  using Ch = typename Tr::Cell_handle;

  // B = [lo, hi] in the triangulation's coordinates; floor: the least
  // distance from a box point to the other vertices when it goes in.
  BoxRefinement(const Vec3& lo, const Vec3& hi, double floor, IdOf id = IdOf())
      : lo_(lo), hi_(hi), floor_(floor), id_(id) {}

  std::array<Vec3, 8> corners() const {
    std::array<Vec3, 8> c;
    for (int k = 0; k < 8; ++k) c[std::size_t(k)] = {k & 1 ? hi_[0] : lo_[0], k & 2 ? hi_[1] : lo_[1], k & 4 ? hi_[2] : lo_[2]};
    return c;
  }
  bool contains(const Point& p) const {  // closed
    const Vec3 q = vec(p);
    for (int i = 0; i < 3; ++i)
      if (!(q[i] >= lo_[i] && q[i] <= hi_[i])) return false;
    return true;
  }
  Point project(const Point& p) const {  // the point of B nearest p
    const Vec3 q = vec(p);
    return Point(std::clamp(q[0], lo_[0], hi_[0]), std::clamp(q[1], lo_[1], hi_[1]), std::clamp(q[2], lo_[2], hi_[2]));
  }
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }
  // On a face of B (exactly: box points carry its coordinates).
  bool on_face(const Vec3& a, const Vec3& b, const Vec3& c) const {
    for (int i = 0; i < 3; ++i)
      for (double x : {lo_[i], hi_[i]})
        if (a[i] == x && b[i] == x && c[i] == x) return true;
    return false;
  }

  enum Kind { kNone, kSegment, kFacet, kRefused };
  struct Split {
    Kind kind = kNone;
    Vec3 x{0, 0, 0};
    Ch near;  // a cell in conflict with x, to start its insertion
  };
  // What to insert instead of circumcentre c, given the conflict zone
  // (finite and infinite cells) of c, or of its projection onto B when c
  // is beyond B: kNone when c is in B and encroaches no box subsegment or
  // subfacet of the zone.
  Split split_for(const Tr& tr, const Point& c, const std::vector<Ch>& zone) const;

private:
  struct Sub {
    Vh a, b, d;  // d null for a subsegment
    Vec3 centre;
    double r2;
  };
  static Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
  static double dist2(const Vec3& a, const Vec3& b) {
    const Vec3 d{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  }
  int bound(const Point& p, int axis) const;  // -1 on lo, 1 on hi, 0 between
  bool segment(Vh a, Vh b, Sub& s) const;
  bool facet(Vh a, Vh b, Vh d, Sub& s) const;
  void subs(const Tr& tr, const std::vector<Ch>& zone, std::vector<Sub>& segs, std::vector<Sub>& facets) const;
  Split checked(const Tr& tr, Kind kind, const Vec3& x, Ch near) const;
  Vec3 lo_, hi_;
  double floor_;
  IdOf id_;
};

// Box points carry their fixed coordinates exactly (corners, and the
// coordinates copied into every split point), so equality decides.
template <class Tr, class IdOf>
int BoxRefinement<Tr, IdOf>::bound(const Point& p, int axis) const {
  const double x = axis == 0 ? p.x() : axis == 1 ? p.y() : p.z();
  return x == lo_[axis] ? -1 : x == hi_[axis] ? 1 : 0;
}

// A hull edge on an edge of B: both ends on the same two faces.
template <class Tr, class IdOf>
bool BoxRefinement<Tr, IdOf>::segment(Vh a, Vh b, Sub& s) const {
  int fixed = 0;
  for (int i = 0; i < 3; ++i) {
    const int ba = bound(a->point(), i);
    fixed += ba != 0 && ba == bound(b->point(), i);
  }
  if (fixed < 2) return false;
  const Vec3 pa = vec(a->point()), pb = vec(b->point());
  s = {a, b, Vh(), {}, 0};
  for (int i = 0; i < 3; ++i) s.centre[i] = pa[i] == pb[i] ? pa[i] : (pa[i] + pb[i]) / 2;
  s.r2 = dist2(pa, pb) / 4;
  return true;
}

// A hull triangle: on one face of B (a hull facet always is); its
// circumcentre in that face's plane, the face's coordinate exact.
template <class Tr, class IdOf>
bool BoxRefinement<Tr, IdOf>::facet(Vh a, Vh b, Vh d, Sub& s) const {
  int axis = -1;
  for (int i = 0; i < 3 && axis < 0; ++i) {
    const int ba = bound(a->point(), i);
    if (ba != 0 && ba == bound(b->point(), i) && ba == bound(d->point(), i)) axis = i;
  }
  if (axis < 0) return false;
  const Point c = CGAL::circumcenter(a->point(), b->point(), d->point());
  s = {a, b, d, vec(c), 0};
  s.centre[axis] = bound(a->point(), axis) < 0 ? lo_[axis] : hi_[axis];
  s.r2 = dist2(s.centre, vec(a->point()));
  return true;
}

// The box subsegments and subfacets among the hull facets of a conflict
// zone, each once.
template <class Tr, class IdOf>
void BoxRefinement<Tr, IdOf>::subs(const Tr& tr, const std::vector<Ch>& zone, std::vector<Sub>& segs, std::vector<Sub>& facets) const {
  segs.clear();
  facets.clear();
  // Each once: keyed by sorted vertex ids (a zone sees a hull facet from
  // both sides and an edge from several facets).
  std::vector<std::array<int, 3>> seen_f, seen_s;
  auto first = [](std::vector<std::array<int, 3>>& seen, std::array<int, 3> k) {
    std::sort(k.begin(), k.end());
    if (std::find(seen.begin(), seen.end(), k) != seen.end()) return false;
    seen.push_back(k);
    return true;
  };
  for (Ch c : zone)
    for (int i = 0; i < 4; ++i) {
      // A hull facet: opposite the infinite vertex of an infinite cell, or
      // the facet of a finite cell towards an infinite one.
      const bool hull = tr.is_infinite(c) ? tr.is_infinite(c->vertex(i)) : tr.is_infinite(c->neighbor(i));
      if (!hull) continue;
      const Vh v[3] = {c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
      Sub s;
      if (facet(v[0], v[1], v[2], s) && first(seen_f, {id_(v[0]), id_(v[1]), id_(v[2])})) facets.push_back(s);
      for (int k = 0; k < 3; ++k)
        if (segment(v[k], v[(k + 1) % 3], s) && first(seen_s, {-1, id_(v[k]), id_(v[(k + 1) % 3])}))
          segs.push_back(s);
    }
}

template <class Tr, class IdOf>
typename BoxRefinement<Tr, IdOf>::Split BoxRefinement<Tr, IdOf>::checked(const Tr& tr, Kind kind, const Vec3& x, Ch near) const {
  const Point p(x[0], x[1], x[2]);
  const Vh nv = tr.nearest_vertex(p, near);
  if (dist2(vec(nv->point()), x) < floor_ * floor_) return {kRefused, x, near};
  return {kind, x, near};
}

template <class Tr, class IdOf>
typename BoxRefinement<Tr, IdOf>::Split BoxRefinement<Tr, IdOf>::split_for(const Tr& tr, const Point& c, const std::vector<Ch>& zone) const {
  std::vector<Sub> segs, facets;
  subs(tr, zone, segs, facets);
  const Vec3 x = vec(c);
  const Sub* worst = nullptr;
  // The largest piece of v whose diametral ball holds y (any: the largest).
  auto largest_encroached = [](const std::vector<Sub>& v, const Vec3& y, bool any) {
    const Sub* w = nullptr;
    for (const Sub& s : v)
      if ((any || dist2(y, s.centre) < s.r2) && (!w || s.r2 > w->r2)) w = &s;
    return w;
  };
  // Subsegments before subfacets.
  if ((worst = largest_encroached(segs, x, false))) return checked(tr, kSegment, worst->centre, zone.front());
  worst = largest_encroached(facets, x, false);
  if (!worst && !contains(c)) worst = largest_encroached(facets, x, true);
  if (!worst) return {contains(c) ? kNone : kRefused, x, zone.front()};  // c stays in B
  // The subfacet's circumcentre p, unless it encroaches a subsegment of its
  // own conflict zone or falls off its face (then the nearest subsegment).
  const Vec3 p = worst->centre;
  const Point pp(p[0], p[1], p[2]);
  typename Tr::Locate_type lt;
  int li, lj;
  const Ch at = tr.locate(pp, lt, li, lj, zone.front());
  if (lt == Tr::VERTEX) return {kRefused, p, at};
  std::vector<Ch> pz;
  tr.find_conflicts(pp, at, CGAL::Emptyset_iterator(), std::back_inserter(pz));
  std::vector<Sub> psegs, pfacets;
  subs(tr, pz, psegs, pfacets);
  const Sub* seg = largest_encroached(psegs, p, false);
  if (!seg && !contains(pp))
    for (const Sub& s : psegs)
      if (!seg || dist2(p, s.centre) - s.r2 < dist2(p, seg->centre) - seg->r2) seg = &s;
  if (seg) return checked(tr, kSegment, seg->centre, pz.front());
  if (!contains(pp)) return {kRefused, p, at};
  return checked(tr, kFacet, p, pz.front());
}


} // namespace imgmesh
