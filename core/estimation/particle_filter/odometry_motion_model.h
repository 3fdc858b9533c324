#pragma once

#include <random>

#include "core/geometry/pose2d.h"

namespace mobot::estimation {

struct OdometryMotionModelOptions {
  // Thrun's sample_motion_model_odometry noise (AMCL's odom_alpha1..4; the Dashgo thesis keeps
  // AMCL's 0.2 each): rotation noise from rotation, rotation from translation, translation from
  // translation, translation from rotation.
  double alpha1 = 0.2;
  double alpha2 = 0.2;
  double alpha3 = 0.2;
  double alpha4 = 0.2;
  // Below this translation the direction of travel is noise (a turn on the spot): rot1 is 0 and
  // the whole turn goes to rot2, as AMCL does.
  double min_translation_for_bearing_m = 0.01;
};

// One odometry increment split as Thrun's rot1 - trans - rot2, with the standard deviations the
// samples are drawn with.
struct OdometryStep {
  double rot1_rad = 0.0;
  double trans_m = 0.0;
  double rot2_rad = 0.0;
  double rot1_sigma_rad = 0.0;
  double trans_sigma_m = 0.0;
  double rot2_sigma_rad = 0.0;
};

// docs/algorithms.md E4: Probabilistic Robotics' sample_motion_model_odometry as AMCL's
// "diff-corrected" model: alphas multiply variances (sigma = sqrt(alpha1 rot^2 + alpha2
// trans^2), ...), and a rotation's noise is measured from the nearer of forward and backward
// travel, so driving backwards is not treated as two half-turns.
class OdometryMotionModel {
 public:
  // Throws std::invalid_argument for a negative or non-finite option.
  explicit OdometryMotionModel(const OdometryMotionModelOptions& options = {});

  const OdometryMotionModelOptions& options() const { return options_; }

  // The step between two odometry poses (odom frame). Non-finite poses give a non-finite step.
  OdometryStep step(const geometry::Pose2D& odom_before, const geometry::Pose2D& odom_after) const;
  // A pose drawn from p(x' | x, step); the heading is wrapped.
  geometry::Pose2D sample(const OdometryStep& step, const geometry::Pose2D& pose,
                          std::mt19937_64& rng) const;

 private:
  OdometryMotionModelOptions options_;
};

}  // namespace mobot::estimation
