#pragma once

#include <Eigen/Core>

#include "core/geometry/pose2d.h"
#include "core/perception/line_segment.h"

namespace mobot::estimation {

// A map line as the robot at `pose` should see it, z = (r_m, psi_rad) in the base frame, and the
// Jacobian H = dz / d(x, y, theta).
struct LineMeasurementPrediction {
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> h = Eigen::Matrix<double, 2, 3>::Zero();
};

// docs/algorithms.md E2: C = rho - x cos(beta) - y sin(beta), r = |C|, psi = beta - theta (+ pi
// when C < 0), wrapped; H = [[-sign(C) cos(beta), -sign(C) sin(beta), 0], [0, 0, -1]].
LineMeasurementPrediction predict_line_measurement(const geometry::Pose2D& pose,
                                                   const perception::LineSegment& map_line);

// The same line in whichever of its two equivalent forms, (r, psi) or (-r, psi + pi), has the
// angle nearer to the observed one. Away from the line this is exactly E2's form; when the robot
// (or its estimate) is close to the line, r may come out negative, which keeps the innovation
// continuous instead of jumping by pi as the sign of C flips.
LineMeasurementPrediction predict_line_measurement(const geometry::Pose2D& pose,
                                                   const perception::LineSegment& map_line,
                                                   double observed_alpha_rad);

// Observed (rho, alpha) minus predicted, angle wrapped into (-pi, pi].
Eigen::Vector2d line_innovation(const perception::LineSegment& observed,
                                const LineMeasurementPrediction& prediction);

}  // namespace mobot::estimation
