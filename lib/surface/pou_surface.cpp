// The adapter lives in its own file: it is built only when the implicit
// module (chapter 6) is part of the build.
#include "implicit/partition_of_unity.hpp"
#include "surface/implicit_surface.hpp"

namespace imgmesh {

PartitionOfUnitySurface::PartitionOfUnitySurface(const PartitionOfUnity& pu) : pu_(pu) {}

double PartitionOfUnitySurface::value(const Vec3& q) const { return pu_.value(to_world(q)); }

double PartitionOfUnitySurface::value_gradient(const Vec3& q, Vec3& gradient) const {
  Vec3 gw;
  const double v = pu_.value_gradient(to_world(q), gw);
  gradient = vector_to_local(gw);
  return v;
}

const FloatImage& PartitionOfUnitySurface::samples() const { return pu_.samples(); }

} // namespace imgmesh
