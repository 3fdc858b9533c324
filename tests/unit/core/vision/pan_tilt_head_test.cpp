// R4's pan/tilt head: the DH chain against its closed form, the camera pose in the map, limits and
// rate-limited slewing, the two column-to-bearing formulas, and target positions from pixel +
// range.
#include "core/vision/pan_tilt_head.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

namespace mobot::vision {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

using Mat4 = std::array<std::array<double, 4>, 4>;
using Vec3 = std::array<double, 3>;

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) c[i][j] += a[i][k] * b[k][j];
    }
  }
  return c;
}

// The standard DH transform: Rot_z(theta) Trans_z(d) Trans_x(a) Rot_x(alpha).
Mat4 dh(double theta, double alpha, double a, double d) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  return {{{ct, -st * ca, st * sa, a * ct},
           {st, ct * ca, -ct * sa, a * st},
           {0.0, sa, ca, d},
           {0.0, 0.0, 0.0, 1.0}}};
}

Mat4 base_column(double l0) { return {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, l0}, {0, 0, 0, 1}}}; }

// A point in the base frame seen by the head's camera: its pixel and its range from the lens.
struct Seen {
  double u_px;
  double v_px;
  double range_m;
};

Seen look_at(const PanTiltHead& head, PanTilt joints, const Vec3& point,
             const PinholeCamera& camera) {
  const LensPosition lens = head.lens_in_base(joints);
  const Vec3 d{point[0] - lens.x_m, point[1] - lens.y_m, point[2] - lens.z_m};
  const double cp = std::cos(joints.pan_rad), sp = std::sin(joints.pan_rad);
  const double ct = std::cos(joints.tilt_rad), st = std::sin(joints.tilt_rad);
  const double forward = d[0] * cp * ct + d[1] * sp * ct + d[2] * st;
  const double left = -d[0] * sp + d[1] * cp;
  const double up = -d[0] * cp * st - d[1] * sp * st + d[2] * ct;
  const double f = camera.focal_px();
  return {0.5 * camera.width_px - f * left / forward, 0.5 * camera.height_px - f * up / forward,
          std::hypot(d[0], d[1], d[2])};
}

TEST(PanTiltHead, LensPositionMatchesTheDenavitHartenbergChain) {
  PanTiltHeadOptions options;
  options.l0_m = 0.42;
  options.l1_m = 0.13;
  options.l2_m = 0.07;
  const PanTiltHead head(options);
  for (const double pan : {-2.5, -1.0, 0.0, 0.4, 1.6, 2.9}) {
    for (const double tilt : {-0.5, -0.1, 0.0, 0.3, 0.78}) {
      const Mat4 chain =
          multiply(multiply(base_column(options.l0_m), dh(pan, kPi / 2, 0.0, options.l1_m)),
                   dh(tilt, 0.0, options.l2_m, 0.0));
      const LensPosition lens = head.lens_in_base({pan, tilt});
      EXPECT_NEAR(lens.x_m, chain[0][3], 1e-12);
      EXPECT_NEAR(lens.y_m, chain[1][3], 1e-12);
      EXPECT_NEAR(lens.z_m, chain[2][3], 1e-12);
      // The optical axis is the chain's last x axis: the camera pose's yaw and pitch.
      EXPECT_NEAR(std::atan2(chain[1][0], chain[0][0]), std::atan2(std::sin(pan), std::cos(pan)),
                  1e-12);
      EXPECT_NEAR(std::asin(chain[2][0]), tilt, 1e-12);
    }
  }
}

TEST(PanTiltHead, LensPositionAtTheHomeAndTurnedPoses) {
  PanTiltHeadOptions options;
  options.mount_x_m = 0.1;
  const PanTiltHead head(options);
  const LensPosition home = head.lens_in_base({0.0, 0.0});
  EXPECT_NEAR(home.x_m, 0.1 + options.l2_m, 1e-12);
  EXPECT_NEAR(home.y_m, 0.0, 1e-12);
  EXPECT_NEAR(home.z_m, options.l0_m + options.l1_m, 1e-12);
  const LensPosition left = head.lens_in_base({kPi / 2, 0.0});
  EXPECT_NEAR(left.x_m, 0.1, 1e-12);
  EXPECT_NEAR(left.y_m, options.l2_m, 1e-12);
  const LensPosition up = head.lens_in_base({0.0, kPi / 2});
  EXPECT_NEAR(up.x_m, 0.1, 1e-12);
  EXPECT_NEAR(up.z_m, options.l0_m + options.l1_m + options.l2_m, 1e-12);
}

TEST(PanTiltHead, CameraPoseInTheMap) {
  PanTiltHeadOptions options;
  options.mount_x_m = 0.2;
  const PanTiltHead head(options);
  const geometry::Pose2D base{1.0, 2.0, kPi / 2};
  const CameraPose pose = head.camera_pose(base, {0.0, 0.25});
  // Facing +y in the map: the lens is ahead of the base along +y.
  EXPECT_NEAR(pose.x_m, 1.0, 1e-12);
  EXPECT_NEAR(pose.y_m, 2.0 + 0.2 + options.l2_m * std::cos(0.25), 1e-12);
  EXPECT_NEAR(pose.z_m, options.l0_m + options.l1_m + options.l2_m * std::sin(0.25), 1e-12);
  EXPECT_NEAR(pose.yaw_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(pose.pitch_rad, 0.25, 1e-12);
  // Yaw is base heading plus pan, wrapped.
  const CameraPose behind = head.camera_pose({0.0, 0.0, 3.0}, {2.5, 0.0});
  EXPECT_NEAR(behind.yaw_rad, 5.5 - 2 * kPi, 1e-12);
}

TEST(PanTiltHead, ClampKeepsJointsInsideTheLimitsAndDropsNan) {
  const PanTiltHead head;
  EXPECT_EQ(head.clamp({0.3, 0.2}), (PanTilt{0.3, 0.2}));
  const PanTilt high = head.clamp({4.0, 1.0});
  EXPECT_NEAR(high.pan_rad, 170 * kDeg, 1e-12);
  EXPECT_NEAR(high.tilt_rad, 45 * kDeg, 1e-12);
  const PanTilt low = head.clamp({-4.0, -1.0});
  EXPECT_NEAR(low.pan_rad, -170 * kDeg, 1e-12);
  EXPECT_NEAR(low.tilt_rad, -30 * kDeg, 1e-12);
  EXPECT_EQ(head.clamp({std::nan(""), std::numeric_limits<double>::infinity()}),
            (PanTilt{0.0, 0.0}));
}

TEST(PanTiltHead, StepTowardsIsRateLimitedPerAxis) {
  const PanTiltHead head;  // 2.0 rad/s pan, 1.5 rad/s tilt
  const PanTilt step = head.step_towards({0.0, 0.0}, {1.0, -0.5}, 0.1);
  EXPECT_NEAR(step.pan_rad, 0.2, 1e-12);
  EXPECT_NEAR(step.tilt_rad, -0.15, 1e-12);
  // Close enough: lands exactly on the target.
  EXPECT_EQ(head.step_towards({0.95, -0.45}, {1.0, -0.5}, 0.1), (PanTilt{1.0, -0.5}));
  // Slewing a whole way takes target / rate.
  PanTilt joints{};
  int steps = 0;
  while (!(joints == PanTilt{1.0, 0.6}) && steps < 1000) {
    joints = head.step_towards(joints, {1.0, 0.6}, 0.02);
    ++steps;
  }
  EXPECT_EQ(steps, 25);  // pan is the slower axis here: 1.0 rad at 2 rad/s
}

TEST(PanTiltHead, StepTowardsClampsTheTargetAndNeverWrapsThroughTheStop) {
  const PanTiltHead head;
  // 200 deg is -160 deg as a heading, but the head gets there by stopping at +170.
  PanTilt joints{3.0, 0.0};
  for (int i = 0; i < 100; ++i) joints = head.step_towards(joints, {200 * kDeg, 2.0}, 0.05);
  EXPECT_NEAR(joints.pan_rad, 170 * kDeg, 1e-12);
  EXPECT_NEAR(joints.tilt_rad, 45 * kDeg, 1e-12);
}

TEST(PanTiltHead, StepTowardsIgnoresBadTimeSteps) {
  const PanTiltHead head;
  for (const double dt : {0.0, -0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(head.step_towards({0.1, 0.1}, {1.0, 0.5}, dt), (PanTilt{0.1, 0.1}));
  }
}

TEST(PanTiltHead, RejectsBadOptions) {
  PanTiltHeadOptions negative;
  negative.l2_m = -0.1;
  EXPECT_THROW(PanTiltHead{negative}, std::invalid_argument);
  PanTiltHeadOptions crossed;
  crossed.min_tilt_rad = 0.5;
  crossed.max_tilt_rad = 0.1;
  EXPECT_THROW(PanTiltHead{crossed}, std::invalid_argument);
  PanTiltHeadOptions still;
  still.max_pan_rate_rad_s = 0.0;
  EXPECT_THROW(PanTiltHead{still}, std::invalid_argument);
  PanTiltHeadOptions nan_mount;
  nan_mount.mount_x_m = std::nan("");
  EXPECT_THROW(PanTiltHead{nan_mount}, std::invalid_argument);
}

TEST(ColumnBearing, LinearAndExactAgreeAtTheCentreAndTheEdgesOnly) {
  const PinholeCamera camera;  // 640 px, 60 deg
  EXPECT_NEAR(bearing_from_column_linear_rad(320.0, camera), 0.0, 1e-15);
  EXPECT_NEAR(bearing_from_column_rad(320.0, camera), 0.0, 1e-15);
  // f is defined by the edges, so both give +-FOV/2 there.
  EXPECT_NEAR(bearing_from_column_linear_rad(0.0, camera), 30 * kDeg, 1e-12);
  EXPECT_NEAR(bearing_from_column_rad(0.0, camera), 30 * kDeg, 1e-12);
  EXPECT_NEAR(bearing_from_column_rad(640.0, camera), -30 * kDeg, 1e-12);
  // In between the linear form is off by up to 0.0195 rad (1.1 deg), 55 % of the way out.
  double worst = 0.0;
  double worst_column = 0.0;
  for (double j = 0.0; j <= 640.0; j += 0.5) {
    const double error =
        std::abs(bearing_from_column_linear_rad(j, camera) - bearing_from_column_rad(j, camera));
    if (error > worst) {
      worst = error;
      worst_column = j;
    }
  }
  EXPECT_NEAR(worst, 0.0195, 0.0002);
  EXPECT_NEAR(std::abs(worst_column - 320.0), 0.555 * 320.0, 2.0);
  // Left of the centre is CCW positive.
  EXPECT_GT(bearing_from_column_rad(100.0, camera), 0.0);
  EXPECT_GT(elevation_from_row_rad(100.0, camera), 0.0);
}

TEST(ColumnBearing, ExactBearingIsWhereAPinholeProjectsAPoint) {
  const PinholeCamera camera{800, 600, 70 * kDeg};
  for (const double bearing : {-0.6, -0.2, 0.0, 0.1, 0.55}) {
    const double u = 0.5 * camera.width_px - camera.focal_px() * std::tan(bearing);
    EXPECT_NEAR(bearing_from_column_rad(u, camera), bearing, 1e-12);
  }
}

TEST(PanTiltHead, TargetInBaseAlongTheOpticalAxis) {
  PanTiltHeadOptions options;
  options.mount_x_m = 0.1;
  const PanTiltHead head(options);
  const PinholeCamera camera;
  const auto ahead = head.target_in_base({0.0, 0.0}, 320.0, 240.0, 2.0, camera);
  ASSERT_TRUE(ahead.has_value());
  EXPECT_NEAR(ahead->x, 0.1 + options.l2_m + 2.0, 1e-12);
  EXPECT_NEAR(ahead->y, 0.0, 1e-12);
  const auto left = head.target_in_base({kPi / 2, 0.0}, 320.0, 240.0, 2.0, camera);
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(left->x, 0.1, 1e-12);
  EXPECT_NEAR(left->y, options.l2_m + 2.0, 1e-12);
  // Tilted down 0.3 rad: the horizontal distance shrinks by cos(0.3).
  const auto down = head.target_in_base({0.0, -0.3}, 320.0, 240.0, 2.0, camera);
  ASSERT_TRUE(down.has_value());
  EXPECT_NEAR(down->x, 0.1 + (options.l2_m + 2.0) * std::cos(0.3), 1e-12);
}

TEST(PanTiltHead, TargetInBaseInvertsTheProjection) {
  const PanTiltHead head;
  const PinholeCamera camera;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pan(-2.5, 2.5), tilt(-0.4, 0.6), offset(-0.4, 0.4);
  std::uniform_real_distribution<double> distance(0.8, 5.0), height(0.0, 1.5);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    const PanTilt joints{pan(rng), tilt(rng)};
    // A point roughly in front of the camera, not on the axis.
    const double heading = joints.pan_rad + offset(rng);
    const double d = distance(rng);
    const Vec3 point{d * std::cos(heading), d * std::sin(heading), height(rng)};
    const Seen seen = look_at(head, joints, point, camera);
    if (seen.u_px < 0 || seen.u_px > camera.width_px || seen.v_px < 0 ||
        seen.v_px > camera.height_px) {
      continue;
    }
    const auto target = head.target_in_base(joints, seen.u_px, seen.v_px, seen.range_m, camera);
    ASSERT_TRUE(target.has_value());
    EXPECT_NEAR(target->x, point[0], 1e-9);
    EXPECT_NEAR(target->y, point[1], 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(PanTiltHead, TargetInBaseRejectsBadInput) {
  const PanTiltHead head;
  const PinholeCamera camera;
  EXPECT_FALSE(head.target_in_base({0.0, 0.0}, 320.0, 240.0, 0.0, camera).has_value());
  EXPECT_FALSE(head.target_in_base({0.0, 0.0}, 320.0, 240.0, -1.0, camera).has_value());
  EXPECT_FALSE(head.target_in_base({0.0, 0.0}, std::nan(""), 240.0, 1.0, camera).has_value());
  EXPECT_FALSE(
      head.target_in_base({0.0, 0.0}, 320.0, 240.0, std::numeric_limits<double>::infinity(), camera)
          .has_value());
  EXPECT_FALSE(head.target_in_base({std::nan(""), 0.0}, 320.0, 240.0, 1.0, camera).has_value());
}

TEST(PanTiltHead, CentringTargetPutsThePixelOnTheAxis) {
  PanTiltHeadOptions options;
  options.l2_m = 0.0;  // no parallax: the centring is exact
  const PanTiltHead head(options);
  const PinholeCamera camera;
  const PanTilt current{0.4, 0.1};
  const Vec3 point{2.0 * std::cos(0.6), 2.0 * std::sin(0.6), 0.2};
  const Seen before = look_at(head, current, point, camera);
  const PanTilt centred = head.centring_target(current, before.u_px, before.v_px, camera);
  const Seen after = look_at(head, centred, point, camera);
  EXPECT_NEAR(after.u_px, 320.0, 1e-9);
  EXPECT_NEAR(after.v_px, 240.0, 1e-9);
  EXPECT_NEAR(centred.pan_rad, 0.6, 1e-12);
  // NaN pixels keep the current joints.
  EXPECT_EQ(head.centring_target(current, std::nan(""), 1.0, camera), current);
}

}  // namespace
}  // namespace mobot::vision
