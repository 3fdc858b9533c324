#include "core/estimation/particle_filter/pose_moments.h"

#include <cmath>

namespace mobot::estimation {

PoseMoments weighted_pose_moments(std::span<const WeightedPose> poses) {
  PoseMoments moments;
  double sum_x = 0.0;
  double sum_y = 0.0;
  double sum_cos = 0.0;
  double sum_sin = 0.0;
  for (const WeightedPose& p : poses) {
    moments.weight += p.weight;
    sum_x += p.weight * p.pose.x;
    sum_y += p.weight * p.pose.y;
    sum_cos += p.weight * std::cos(p.pose.theta);
    sum_sin += p.weight * std::sin(p.pose.theta);
  }
  if (!(moments.weight > 0.0) || !std::isfinite(moments.weight)) return {};
  moments.mean = {sum_x / moments.weight, sum_y / moments.weight, std::atan2(sum_sin, sum_cos)};
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const WeightedPose& p : poses) {
    const Eigen::Vector3d d(p.pose.x - moments.mean.x, p.pose.y - moments.mean.y,
                            geometry::wrap_angle(p.pose.theta - moments.mean.theta));
    covariance += p.weight * d * d.transpose();
  }
  moments.covariance = covariance / moments.weight;
  return moments;
}

}  // namespace mobot::estimation
