#include "surface/topo_disk.hpp"

#include "surface/star.hpp"

#include <algorithm>

namespace imgmesh::surface_detail {

void restricted_around(const Tr& tr, Vh v, std::vector<Facet>& facets, std::vector<Ch>& cells) {
  facets.clear();
  cells.clear();
  star_cells(tr, v, cells);
  for (Ch c : cells) {
    const int iv = c->index(v);
    for (int i = 0; i < 4; ++i) {
      if (i == iv || !c->facet.restricted(i)) continue;
      // Also around v: the facet is taken from the side whose opposite
      // vertex has the smaller id (the infinite one: -1), not by address.
      // The side is the insertion's hint, and the hint decides the layout
      // of the new cells, so by address the mesh depended on the allocator.
      Ch n = c->neighbor(i);
      if (c->vertex(i)->info().id < n->vertex(n->index(c))->info().id) facets.emplace_back(c, i);
    }
  }
}

bool TopoDisk::operator()(const Tr& tr, Vh v, Facet* worst) {
  restricted_around(tr, v, facets_, cells_);
  link_.clear();
  double best = -1;
  for (const Facet& f : facets_) {
    const FacetInfo& fi = f.first->facet[f.second];
    if (!(fi.state & kRestricted)) continue;
    int ids[2], k = 0;
    for (int m = 1; m < 4; ++m) {
      Vh w = f.first->vertex((f.second + m) & 3);
      if (w != v) ids[k++] = w->info().id;
    }
    link_.emplace_back(ids[0], ids[1]);
    if (fi.r2 > best) {
      best = fi.r2;
      *worst = f;
    }
  }
  if (link_.empty()) return true;
  return one_cycle(link_);
}

bool TopoDisk::one_cycle(const std::vector<std::pair<int, int>>& link) {
  if (link.empty()) return false;
  ends_.clear();
  for (auto& e : link) {
    ends_.push_back(e.first);
    ends_.push_back(e.second);
  }
  std::sort(ends_.begin(), ends_.end());
  for (std::size_t i = 0; i < ends_.size(); i += 2)
    if (ends_[i] != ends_[i + 1] || (i + 2 < ends_.size() && ends_[i + 2] == ends_[i])) return false;
  // Walk the cycle from the first edge.
  used_.assign(link.size(), 0);
  used_[0] = 1;
  const int start = link[0].first;
  int cur = link[0].second;
  std::size_t steps = 1;
  while (cur != start) {
    std::size_t k = 0;
    for (; k < link.size(); ++k)
      if (!used_[k] && (link[k].first == cur || link[k].second == cur)) break;
    if (k == link.size()) return false;
    used_[k] = 1;
    cur = link[k].first == cur ? link[k].second : link[k].first;
    ++steps;
  }
  return steps == link.size();
}

} // namespace imgmesh::surface_detail
