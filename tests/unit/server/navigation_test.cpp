#include "server/navigation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mobot::server {
namespace {

// A 10 x 4 m room at 0.05 m with walls all round.
mapping::OccupancyGrid room() {
  mapping::OccupancyGrid grid(200, 80, 0.05, {0, 0, 0}, mapping::OccupancyGrid::kFree);
  for (int x = 0; x < 200; ++x) {
    grid.set({x, 0}, mapping::OccupancyGrid::kOccupied);
    grid.set({x, 79}, mapping::OccupancyGrid::kOccupied);
  }
  for (int y = 0; y < 80; ++y) {
    grid.set({0, y}, mapping::OccupancyGrid::kOccupied);
    grid.set({199, y}, mapping::OccupancyGrid::kOccupied);
  }
  return grid;
}

// A scan from (1, 2) looking along +x whose centre beams end at `hit_x_m`.
msgs::LaserScan scan_with_obstacle_at(double hit_x_m) {
  msgs::LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-std::numbers::pi / 2);
  scan.angle_increment_rad = static_cast<float>(std::numbers::pi / 180);
  scan.range_min_m = 0.4F;
  scan.range_max_m = 80.0F;
  for (int i = 0; i <= 180; ++i) {
    const double angle = -std::numbers::pi / 2 + i * std::numbers::pi / 180;
    // Walls at y = 0.05 and y = 3.95 (cell faces), far wall at x = 9.95.
    double range = 80.0;
    if (std::sin(angle) > 1e-6) range = std::min(range, (3.95 - 2.0) / std::sin(angle));
    if (std::sin(angle) < -1e-6) range = std::min(range, (0.05 - 2.0) / std::sin(angle));
    if (std::cos(angle) > 1e-6) range = std::min(range, (9.95 - 1.0) / std::cos(angle));
    if (std::abs(angle) < 0.06) range = std::min(range, (hit_x_m - 1.0) / std::cos(angle));
    scan.ranges_m.push_back(static_cast<float>(range));
  }
  return scan;
}

// Distance from `point` to the path polyline.
double min_distance_to(const planning::Path& path, geometry::Point2D point) {
  double best = 1e9;
  const auto& p = path.points();
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const double dx = p[i + 1].x - p[i].x;
    const double dy = p[i + 1].y - p[i].y;
    const double length2 = dx * dx + dy * dy;
    double f = length2 > 0 ? ((point.x - p[i].x) * dx + (point.y - p[i].y) * dy) / length2 : 0.0;
    f = std::clamp(f, 0.0, 1.0);
    best = std::min(best, std::hypot(p[i].x + f * dx - point.x, p[i].y + f * dy - point.y));
  }
  return best;
}

TEST(Navigation, PlansAroundWhatTheLaserSeesButTheMapDoesNotHave) {
  Navigation navigation(Config{});
  navigation.set_map(room());
  const geometry::Pose2D start{1.0, 2.0, 0.0};
  api::GoalRequest request;
  request.target = {8.0, 2.0, 0.0};

  navigation.observe_scan(scan_with_obstacle_at(9.95), start, start, 0.0);  // only walls
  const auto clear = navigation.plan(start, request).get();
  ASSERT_FALSE(clear.error);
  EXPECT_LT(min_distance_to(clear.path, {5.0, 2.0}), 0.05) << "a straight corridor path";

  navigation.observe_scan(scan_with_obstacle_at(5.0), start, start, 0.0);  // something at (5, 2)
  const auto around = navigation.plan(start, request).get();
  ASSERT_FALSE(around.error);
  EXPECT_GT(min_distance_to(around.path, {5.0, 2.0}), 0.3) << "the path keeps the robot clear";
}

TEST(Navigation, ImpossibleGoalsReportTheContractCodes) {
  Navigation navigation(Config{});
  api::GoalRequest request;
  request.target = {5.0, 2.0, 0.0};
  EXPECT_EQ(navigation.plan({1, 2, 0}, request).get().error, planning::PlanError::kNoMap);
  navigation.set_map(room());
  request.target = {50.0, 2.0, 0.0};
  EXPECT_EQ(navigation.plan({1, 2, 0}, request).get().error, planning::PlanError::kGoalOutsideMap);
  request.target = {5.0, 0.1, 0.0};
  EXPECT_EQ(navigation.plan({1, 2, 0}, request).get().error, planning::PlanError::kGoalInObstacle);
}

TEST(Navigation, GoalsGetIncreasingIdsAndTheNavigationCommandStopsWithThem) {
  Navigation navigation(Config{});
  navigation.set_map(room());
  api::GoalRequest request;
  request.target = {3.0, 2.0, 0.0};
  const auto outcome = navigation.plan({1, 2, 0}, request).get();
  ASSERT_FALSE(outcome.error);
  const auto first = navigation.start(request, outcome.path, 0.0).id;
  const auto second = navigation.start(request, outcome.path, 1.0).id;
  EXPECT_GT(second, first);
  EXPECT_TRUE(navigation.active());
  EXPECT_TRUE(navigation.tick(1.02, {1, 2, 0}, {}).has_value());
  navigation.end_active(navigation::GoalStatus::kCanceled, "estop", 1.04);
  EXPECT_FALSE(navigation.active());
  EXPECT_FALSE(navigation.tick(1.06, {1, 2, 0}, {}).has_value());
}

}  // namespace
}  // namespace mobot::server
