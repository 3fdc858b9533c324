#include "drivers/sim/moving_target.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace mobot::sim {
namespace {

constexpr double kTolerance_m = 1e-9;

MovingTargetSpec square_path(bool loop) {
  MovingTargetSpec spec;
  spec.path = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}, {0.0, 2.0}};
  spec.speed_mps = 0.5;
  spec.loop = loop;
  return spec;
}

void expect_at(const MovingTarget& target, double time_s, double x_m, double y_m) {
  const geometry::Point2D at = target.position_at(time_s);
  EXPECT_NEAR(at.x, x_m, kTolerance_m) << "t = " << time_s;
  EXPECT_NEAR(at.y, y_m, kTolerance_m) << "t = " << time_s;
}

std::string rejection(const MovingTargetSpec& spec) {
  try {
    const MovingTarget target(spec);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "accepted";
}

TEST(MovingTarget, MovesAlongThePathAtItsSpeed) {
  const MovingTarget target(square_path(false));
  expect_at(target, 0.0, 0.0, 0.0);
  expect_at(target, 1.0, 0.5, 0.0);
  expect_at(target, 4.0, 2.0, 0.0);  // the corner
  expect_at(target, 5.0, 2.0, 0.5);
  expect_at(target, 10.0, 1.0, 2.0);
  EXPECT_NEAR(target.path_length_m(), 6.0, kTolerance_m);
}

TEST(MovingTarget, StopsAtTheEndWithoutLoop) {
  const MovingTarget target(square_path(false));
  expect_at(target, 12.0, 0.0, 2.0);
  expect_at(target, 100.0, 0.0, 2.0);
}

TEST(MovingTarget, LoopsBackToTheFirstPointAndRoundAgain) {
  const MovingTarget target(square_path(true));
  EXPECT_NEAR(target.path_length_m(), 8.0, kTolerance_m);
  expect_at(target, 13.0, 0.0, 1.5);  // on the way back from the last point to the first
  expect_at(target, 16.0, 0.0, 0.0);  // one lap
  expect_at(target, 17.0, 0.5, 0.0);
  expect_at(target, 16.0 * 10 + 5.0, 2.0, 0.5);
}

TEST(MovingTarget, WaitsAtTheFirstPointBeforeItStarts) {
  const MovingTarget target(square_path(true));
  expect_at(target, -3.0, 0.0, 0.0);
}

TEST(MovingTarget, OnePointOrZeroSpeedStandsStill) {
  MovingTargetSpec spec;
  spec.path = {{3.0, 4.0}};
  for (const bool loop : {false, true}) {
    spec.loop = loop;
    expect_at(MovingTarget(spec), 7.0, 3.0, 4.0);
  }
  MovingTargetSpec parked = square_path(true);
  parked.speed_mps = 0.0;
  expect_at(MovingTarget(parked), 7.0, 0.0, 0.0);
}

TEST(MovingTarget, RepeatedPointsDoNotStallIt) {
  MovingTargetSpec spec;
  spec.path = {{0.0, 0.0}, {0.0, 0.0}, {1.0, 0.0}, {1.0, 0.0}};
  spec.speed_mps = 1.0;
  spec.loop = true;
  const MovingTarget target(spec);
  expect_at(target, 0.5, 0.5, 0.0);
  expect_at(target, 1.5, 0.5, 0.0);  // on the way back
}

TEST(MovingTarget, RejectsABadSpecNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto with = [](auto change) {
    MovingTargetSpec spec = square_path(true);
    change(spec);
    return rejection(spec);
  };
  EXPECT_NE(with([](MovingTargetSpec& s) { s.radius_m = 0.0; }).find("radius_m"),
            std::string::npos);
  EXPECT_NE(with([](MovingTargetSpec& s) { s.radius_m = -0.1; }).find("radius_m"),
            std::string::npos);
  EXPECT_NE(with([nan](MovingTargetSpec& s) { s.radius_m = nan; }).find("radius_m"),
            std::string::npos);
  EXPECT_NE(with([inf](MovingTargetSpec& s) { s.height_m = inf; }).find("height_m"),
            std::string::npos);
  EXPECT_NE(with([](MovingTargetSpec& s) { s.speed_mps = -1.0; }).find("speed_mps"),
            std::string::npos);
  EXPECT_NE(with([nan](MovingTargetSpec& s) { s.speed_mps = nan; }).find("speed_mps"),
            std::string::npos);
  EXPECT_NE(with([](MovingTargetSpec& s) { s.path.clear(); }).find("path"), std::string::npos);
  EXPECT_NE(with([nan](MovingTargetSpec& s) { s.path[2].y = nan; }).find("path[2]"),
            std::string::npos);
  EXPECT_EQ(with([](MovingTargetSpec&) {}), "accepted");
}

TEST(MovingTarget, RejectsANonFiniteTime) {
  const MovingTarget target(square_path(true));
  EXPECT_THROW(target.position_at(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
  EXPECT_THROW(target.position_at(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::sim
