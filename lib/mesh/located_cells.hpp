// The cells of a CGAL 3D triangulation that hold a point locate() placed
// at (c, lt, li, lj): c alone, or every cell around the facet, edge or
// vertex the point lies on (VoxelSides, seg2mesh --conforming and seg2tet
// check each voxel centre's side against all of them).
#pragma once
#include <iterator>
#include <vector>

namespace imgmesh {

template <class Tr>
void located_cells(const Tr& tr, typename Tr::Cell_handle c, typename Tr::Locate_type lt, int li, int lj,
                   std::vector<typename Tr::Cell_handle>& out) {
  out.assign(1, c);
  if (lt == Tr::FACET) {
    out.push_back(c->neighbor(li));
  } else if (lt == Tr::EDGE) {
    out.clear();
    auto cc = tr.incident_cells(c, li, lj), done = cc;
    do out.push_back(cc); while (++cc != done);
  } else if (lt == Tr::VERTEX) {
    out.clear();
    tr.incident_cells(c->vertex(li), std::back_inserter(out));
  }
}

} // namespace imgmesh
