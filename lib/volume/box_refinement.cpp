#include "volume/box_refinement.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

std::array<Vec3, 8> BoxRefinement::corners() const {
  std::array<Vec3, 8> c;
  for (int k = 0; k < 8; ++k) c[std::size_t(k)] = {k & 1 ? hi_[0] : lo_[0], k & 2 ? hi_[1] : lo_[1], k & 4 ? hi_[2] : lo_[2]};
  return c;
}

bool BoxRefinement::contains(const Point& p) const {
  const Vec3 q = vec(p);
  for (int i = 0; i < 3; ++i)
    if (!(q[i] >= lo_[i] && q[i] <= hi_[i])) return false;
  return true;
}

Point BoxRefinement::project(const Point& p) const {
  const Vec3 q = vec(p);
  return Point(std::clamp(q[0], lo_[0], hi_[0]), std::clamp(q[1], lo_[1], hi_[1]), std::clamp(q[2], lo_[2], hi_[2]));
}

// Box points carry their fixed coordinates exactly (corners, and the
// coordinates copied into every split point), so equality decides.
int BoxRefinement::bound(const Point& p, int axis) const {
  const double x = axis == 0 ? p.x() : axis == 1 ? p.y() : p.z();
  return x == lo_[axis] ? -1 : x == hi_[axis] ? 1 : 0;
}

// A hull edge on an edge of B: both ends on the same two faces.
bool BoxRefinement::segment(Vh a, Vh b, Sub& s) const {
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
bool BoxRefinement::facet(Vh a, Vh b, Vh d, Sub& s) const {
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
void BoxRefinement::subs(const Tr& tr, const std::vector<Ch>& zone, std::vector<Sub>& segs, std::vector<Sub>& facets) const {
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
      if (facet(v[0], v[1], v[2], s) && first(seen_f, {v[0]->info().id, v[1]->info().id, v[2]->info().id})) facets.push_back(s);
      for (int k = 0; k < 3; ++k)
        if (segment(v[k], v[(k + 1) % 3], s) && first(seen_s, {-1, v[k]->info().id, v[(k + 1) % 3]->info().id}))
          segs.push_back(s);
    }
}

BoxRefinement::Split BoxRefinement::checked(const Tr& tr, Kind kind, const Vec3& x, Ch near) const {
  const Point p(x[0], x[1], x[2]);
  const Vh nv = tr.nearest_vertex(p, near);
  if (dist2(vec(nv->point()), x) < floor_ * floor_) return {kRefused, x, near};
  return {kind, x, near};
}

BoxRefinement::Split BoxRefinement::split_for(const Tr& tr, const Point& c, const std::vector<Ch>& zone) const {
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
  Tr::Locate_type lt;
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

} // namespace imgmesh::surface_detail
