// The surface S = f^-1(0) that implicit2mesh samples (thesis ch. 7-8), seen
// through a small interface so the mesher can be developed and tested on
// analytic shapes as well as on chapter 6's partition of unity.
//
// Everything is expressed in the grid's local frame q = diag(spacing) * index
// (voxel centre (i,j,k) at q = (i sx, j sy, k sz)): the cubes C_k between
// voxel centres are axis aligned there, and world = origin + direction * q is
// a rigid motion, so Delaunay triangulations and distances are preserved.
#pragma once
#include "image/grid.hpp"
#include "image/sample_grid.hpp"

#include <functional>

namespace imgmesh {

class PartitionOfUnity;

class ImplicitSurface {
public:
  virtual ~ImplicitSurface() = default;
  // f at a local point inside the box of voxel centres; negative inside.
  virtual double value(const Vec3& q) const = 0;
  // f and its gradient with respect to q.
  virtual double value_gradient(const Vec3& q, Vec3& gradient) const = 0;
  // g at the voxel centres with the world geometry: f has g's sign there,
  // and f has no zero in a cube whose 8 corners share one sign (thesis F1).
  virtual const SampleGrid& samples() const = 0;
  // An enclosure [lo, hi] of f on the local box [a, b] (a <= b), when the
  // surface can give one (false: none; the default). until_zero, for
  // callers that only ask whether it excludes 0: it may stop as soon as
  // [lo, hi] holds 0 (lo < 0 < hi, no longer an enclosure of f); an
  // enclosure that excludes 0 is the same as without it.
  virtual bool range(const Vec3& a, const Vec3& b, double& lo, double& hi, bool until_zero = false) const;
  // An enclosure [lo, hi] of the derivative of f along the unit vector v
  // on the local box [a, b], when the surface can give one (false: none);
  // until_zero as in range().
  virtual bool slope_range(const Vec3& a, const Vec3& b, const Vec3& v, double& lo, double& hi, bool until_zero = false) const;

  // Local frame <-> world coordinates.
  Vec3 to_world(const Vec3& q) const;
  Vec3 to_local(const Vec3& world) const;
  Vec3 vector_to_world(const Vec3& v) const;  // directions (gradients)
  Vec3 vector_to_local(const Vec3& v) const;
  // det(direction) < 0: the world map reflects, flip facet orientation.
  bool reflects() const;
};

// f given in world coordinates by a function (analytic test shapes); the
// samples are f at the voxel centres of `grid`; gradient by central
// differences.
class FunctionSurface : public ImplicitSurface {
public:
  using Function = std::function<double(const Vec3& world)>;
  FunctionSurface(const Geometry& grid, Function f);
  double value(const Vec3& q) const override;
  double value_gradient(const Vec3& q, Vec3& gradient) const override;
  const SampleGrid& samples() const override { return samples_; }

private:
  Function f_;
  SampleGrid samples_;
};

// Chapter 6's partition of unity (world coordinates) seen in the local frame.
// Holds a reference: `pu` must outlive the adapter.
class PartitionOfUnitySurface : public ImplicitSurface {
public:
  explicit PartitionOfUnitySurface(const PartitionOfUnity& pu);
  double value(const Vec3& q) const override;
  double value_gradient(const Vec3& q, Vec3& gradient) const override;
  const SampleGrid& samples() const override;
  // f = sum_j w_j f_j with weights w_j >= 0 summing to 1, w_j = 0 beyond
  // cell j dilated by d, and each f_j multilinear (the trilinear
  // interpolant of g on cell j, extended): on a box, f lies within the
  // range of the f_j of the cells whose dilated box meets it, each at the
  // box's 8 corners.
  bool range(const Vec3& a, const Vec3& b, double& lo, double& hi, bool until_zero = false) const override;
  // grad f = sum_j w_j grad f_j + sum_j f_j grad w_j. The first sum lies in
  // the range of the d f_j / d x_i of those cells (bilinear in the other two
  // coordinates: their values at the box's corners). The second is nonzero
  // on axis i only within d_i of an inner grid plane, where two cells blend
  // with (1 - eta, eta): there it is eta' (f_up - f_lo), and f_up - f_lo =
  // x (s_up - s_lo) (the two agree on the plane; x is the offset, |x| < d_i,
  // s their slopes along i), so |it| <= kBlendSlope |s_up - s_lo| with
  // kBlendSlope >= max_u |d eta / du| |1/2 - u| (u = (d - x) / 2d).
  bool slope_range(const Vec3& a, const Vec3& b, const Vec3& v, double& lo, double& hi, bool until_zero = false) const override;
  // max_u |d eta/du| |1/2 - u| is 0.32718 (at u = 0.2435); the unit test
  // checks the bound on a dense sample.
  static constexpr double kBlendSlope = 0.33;

private:
  const PartitionOfUnity& pu_;
};

} // namespace imgmesh
