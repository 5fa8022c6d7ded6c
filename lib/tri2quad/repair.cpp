// The repair of Fig. 3.23 (thesis 3.3): a point a component puts on the
// constraint edge it shares with its parent component splits the parent's
// triangle there, and the constraint segment with it.
#include "tri2quad/conversion.hpp"


namespace imgmesh::tri2quad_detail {

void Conversion::split_segment(int a, int b, int m) {
  auto it = segments.find(edge_key(a, b));
  if (it == segments.end()) return;
  const int marker = it->second;
  segments.erase(it);
  segments[edge_key(a, m)] = marker;
  segments[edge_key(m, b)] = marker;
}

// Fig. 3.23: the triangle across (a, b) from `from` gets the point m.
void Conversion::repair(int from, int a, int b, int m) {
  int N = -1, sN = -1;
  for (int j = 0; j < 3; ++j) {
    const int w = neighbours[from][j];
    if (w >= 0 && ((triangles[from][j] == a && triangles[from][(j + 1) % 3] == b))) N = w;
  }
  if (N < 0) return;
  for (int j = 0; j < 3; ++j)
    if (triangles[N][j] == b && triangles[N][(j + 1) % 3] == a) sN = j;
  if (sN < 0) return;
  const int z = triangles[N][(sN + 2) % 3];
  const int oldnb = neighbours[N][(sN + 1) % 3];
  const int oldbit = constrained[N] >> ((sN + 1) % 3) & 1;
  const int N2 = int(triangles.size());
  triangles.push_back({m, a, z});
  neighbours.push_back({from, oldnb, N});
  constrained.push_back(std::uint8_t(1u | (oldbit << 1)));
  attribute.push_back(attribute[N]);
  component.push_back(component[N]);
  parent.push_back(-1);
  parent_slot.push_back(0);
  leftover.push_back({});
  triangles[N][(sN + 1) % 3] = m;
  neighbours[N][(sN + 1) % 3] = N2;
  constrained[N] = std::uint8_t((constrained[N] & ~(1u << ((sN + 1) % 3))) | (1u << sN));
  if (oldnb >= 0)
    for (int j = 0; j < 3; ++j)
      if (neighbours[oldnb][j] == N && triangles[oldnb][j] == z && triangles[oldnb][(j + 1) % 3] == a) neighbours[oldnb][j] = N2;
  ++case_counts[kRepair];
  ++result.repairs;
}

} // namespace imgmesh::tri2quad_detail
