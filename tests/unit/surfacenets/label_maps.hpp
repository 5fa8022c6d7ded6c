// Hand-built label maps of known topology for the surface-nets tests (the
// mesh, test_surface_nets.cpp; its certificate, test_interface_certificate.cpp).
#pragma once
#include "wellcomposed/label_images.hpp"

#include <random>

namespace imgmesh::test {

inline LabelImage nested_shells() {
  LabelImage img = label_grid(12, 12, 12);
  paint(img, {2, 2, 2}, {9, 9, 9}, 1);
  paint(img, {4, 4, 4}, {7, 7, 7}, 2);
  paint(img, {5, 5, 5}, {6, 6, 6}, 0);  // a cavity of background inside 2
  return img;
}
// Labels 1 and 2 side by side under a slab of 3: triple curves 1|2|3,
// 1|2|0, 1|3|0, 2|3|0 and junctions where they meet.
inline LabelImage three_labels() {
  LabelImage img = label_grid(12, 10, 10);
  paint(img, {2, 2, 2}, {5, 7, 6}, 1);
  paint(img, {6, 2, 2}, {9, 7, 6}, 2);
  paint(img, {2, 2, 7}, {9, 7, 8}, 3);
  return img;
}
// Label 1 on the grid's side x = 0 and z = 0, label 2 one voxel inside it.
inline LabelImage side_and_one_voxel() {
  LabelImage img = label_grid(8, 8, 8);
  paint(img, {0, 1, 0}, {4, 6, 4}, 1);
  paint(img, {2, 3, 2}, {2, 3, 2}, 2);
  return img;
}
// Four labels around the edge line x = 5, y = 5 (corners), z 2..6: four
// patches meeting along one curve, 1|2 and 3|4 on one plane.
inline LabelImage four_labels_around_an_edge() {
  LabelImage img = label_grid(10, 10, 8);
  paint(img, {2, 2, 2}, {4, 4, 5}, 1);
  paint(img, {5, 2, 2}, {7, 4, 5}, 2);
  paint(img, {5, 5, 2}, {7, 7, 5}, 3);
  paint(img, {2, 5, 2}, {4, 7, 5}, 4);
  return img;
}
// The well-composed 2x2x2 block 0 0 0 1 2 0 3 3 (voxel k at (k & 1,
// k >> 1 & 1, k >> 2 & 1)) whose patch 3|0 is two fans at the centre corner
// (interface_complex.hpp).
inline LabelImage pinched_block() {
  LabelImage img = label_grid(2, 2, 2);
  const std::int32_t labels[8] = {0, 0, 0, 1, 2, 0, 3, 3};
  for (std::size_t k = 0; k < 8; ++k) img.data[k] = labels[k];
  return img;
}
// Voronoi cells of `labels` seeds labelled 1..labels and as many of label
// 0, on a cube of `side` voxels (not well-composed: repair it).
inline LabelImage voronoi_map(std::mt19937_64& rng, std::size_t side, int labels) {
  LabelImage img = label_grid(side, side, side);
  std::uniform_real_distribution<double> u(0, double(side));
  std::vector<std::array<double, 4>> seeds(2 * std::size_t(labels));
  for (std::size_t s = 0; s < seeds.size(); ++s)
    seeds[s] = {u(rng), u(rng), u(rng), s < std::size_t(labels) ? double(s + 1) : 0.0};
  for (std::size_t z = 0; z < side; ++z)
    for (std::size_t y = 0; y < side; ++y)
      for (std::size_t x = 0; x < side; ++x) {
        double best = 1e30;
        for (const auto& s : seeds) {
          const double d = (s[0] - double(x)) * (s[0] - double(x)) + (s[1] - double(y)) * (s[1] - double(y)) +
                           (s[2] - double(z)) * (s[2] - double(z));
          if (d < best) best = d, img(x, y, z) = std::int32_t(s[3]);
        }
      }
  return img;
}

} // namespace imgmesh::test
