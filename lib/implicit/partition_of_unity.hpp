// The smooth implicit function f of thesis chapter 6: a partition of unity
// over the cells C_k between voxel centres, shape functions f_k = trilinear
// interpolants of the signed distance g (negative inside), weights built from
// the C-infinity step eta (6.7, 6.8; see errata). Evaluation in world
// coordinates, O(1), thread safe, no allocation per call.
#pragma once
#include "image/grid.hpp"

namespace imgmesh {

class PartitionOfUnity {
public:
  // g: signed distance to bdCA(X) at the voxel centres, physical units,
  // negative inside, with the image's world geometry. d: the weight-function
  // constant per axis; computed from g (thesis 6.3.2, Prop. 6.4.1) when all
  // components are <= 0.
  explicit PartitionOfUnity(FloatImage g, Vec3 d = {0, 0, 0});

  // f at a world point inside the domain (the box of voxel centres).
  double value(const Vec3& p) const;
  // f and its analytic gradient (world coordinates).
  double value_gradient(const Vec3& p, Vec3& gradient) const;
  // Inside the domain (the box spanned by the voxel centres).
  bool in_domain(const Vec3& p) const;

  const FloatImage& samples() const { return g_; }
  const Vec3& d() const { return d_; }

private:
  FloatImage g_;
  Vec3 d_;
  // implementation data (per-axis delta, alpha_1, alpha_2, beta, ...) here
};

} // namespace imgmesh
