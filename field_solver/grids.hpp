// Regular sampling grids for post-processing (mm): the sensing plane (2-D)
// and a box around it (3-D). Point order: x fastest, then y, then z (VTK).
#pragma once
#include <Eigen/Core>

namespace magenc::fem {

struct GridSpec {
  Eigen::Vector3d origin_mm{0, 0, 0};  // first point (x_min, y_min, z_min)
  Eigen::Vector3d step_mm{0.05, 0.05, 0.05};
  Eigen::Vector3i dims{1, 1, 1};       // points per axis (dims.z() == 1: a plane)

  long num_points() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
  Eigen::Matrix3Xd points() const;
  // Grid from [min, max] per axis and a step (mm); max is rounded to a whole number of steps.
  static GridSpec from_range(const Eigen::Vector3d& min_mm, const Eigen::Vector3d& max_mm, const Eigen::Vector3d& step_mm);
};

}  // namespace magenc::fem
