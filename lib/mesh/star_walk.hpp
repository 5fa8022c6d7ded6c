// The cells around a vertex v of a CGAL 3D triangulation (dimension 3), as
// its incident_cells lists them: depth first from v->cell(), each cell
// marked in its TDS data while the walk runs, in the same order, without
// the call's heap work (a stack and a vector a call). The surface mesher's
// stars (surface/star.hpp) and the conforming mesher's (Mesher::star).
#pragma once
#include <cstddef>
#include <vector>

namespace imgmesh {

// Appends v's cells to `out` (stack: scratch); found(c) is called on each
// cell as it is listed, and the walk stops at the first cell for which it
// returns true, which is returned (else a null handle). The marks are
// cleared.
template <class Vh, class Ch, class Found>
Ch star_walk(Vh v, std::vector<Ch>& out, std::vector<Ch>& stack, Found&& found) {
  const std::size_t first = out.size();
  const Ch d = v->cell();
  d->tds_data().mark_in_conflict();
  out.push_back(d);
  stack.assign(1, d);
  Ch stopped = found(d) ? d : Ch();
  while (stopped == Ch() && !stack.empty()) {
    const Ch c = stack.back();
    stack.pop_back();
    for (int i = 0; i < 4; ++i) {
      if (c->vertex(i) == v) continue;
      const Ch n = c->neighbor(i);
      if (!n->tds_data().is_clear()) continue;
      n->tds_data().mark_in_conflict();
      stack.push_back(n);
      out.push_back(n);
      if (found(n)) {
        stopped = n;
        break;
      }
    }
  }
  for (std::size_t k = first; k < out.size(); ++k) out[k]->tds_data().clear();
  return stopped;
}

} // namespace imgmesh
