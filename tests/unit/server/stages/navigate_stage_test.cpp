// The navigate and perceive stages together, without a world, a hub or a store: planning around
// what the laser sees, the contract's error codes, goal ids and the navigation mux source.
#include "server/stages/navigate_stage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/geometry/polyline.h"
#include "server/plugins/plugins.h"
#include "server/stages/perceive_stage.h"

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

class NavigateStageTest : public ::testing::Test {
 protected:
  NavigateStageTest()
      : plugins_(configure_plugins(builtin_plugins(), Config{}, {})),
        worker_(planning::PlanningGridOptions{}, plugins_.planners),
        navigate_(worker_, plugins_.trackers, {}),
        perceive_([this] { return worker_.static_grid(); }, 0.42),
        context_(bus_) {
    context_.pose = {1.0, 2.0, 0.0};
  }

  void set_room() {
    const auto grid = std::make_shared<const mapping::OccupancyGrid>(room());
    const ActiveMap map{1, 1, grid};
    navigate_.prepare_map(map);
    navigate_.apply_map(map, context_);
  }

  PlanningWorker::Outcome plan(const api::GoalRequest& request) {
    std::promise<PlanningWorker::Outcome> promise;
    auto future = promise.get_future();
    navigate_.plan(request, context_,
                   [&promise](PlanningWorker::Outcome outcome) { promise.set_value(outcome); });
    return future.get();
  }

  void see(const msgs::LaserScan& scan) {
    context_.begin(context_.now_s + 0.02, 0.02);
    context_.scan = scan;
    perceive_.step(context_);
  }

  Bus bus_;
  ConfiguredPlugins plugins_;
  PlanningWorker worker_;
  NavigateStage navigate_;
  PerceiveStage perceive_;
  TickContext context_;
};

TEST_F(NavigateStageTest, PlansAroundWhatTheLaserSeesButTheMapDoesNotHave) {
  set_room();
  api::GoalRequest request;
  request.target = {8.0, 2.0, 0.0};

  see(scan_with_obstacle_at(9.95));  // only walls
  const auto clear = plan(request);
  ASSERT_FALSE(clear.error);
  EXPECT_LT(geometry::distance_to_polyline(clear.path.points(), {5.0, 2.0}), 0.05)
      << "a straight corridor path";

  see(scan_with_obstacle_at(5.0));  // something at (5, 2)
  const auto around = plan(request);
  ASSERT_FALSE(around.error);
  EXPECT_GT(geometry::distance_to_polyline(around.path.points(), {5.0, 2.0}), 0.3)
      << "the path keeps the robot clear";
}

TEST_F(NavigateStageTest, ImpossibleGoalsReportTheContractCodes) {
  api::GoalRequest request;
  request.target = {5.0, 2.0, 0.0};
  EXPECT_EQ(plan(request).error, planning::PlanError::kNoMap);
  set_room();
  request.target = {50.0, 2.0, 0.0};
  EXPECT_EQ(plan(request).error, planning::PlanError::kGoalOutsideMap);
  request.target = {5.0, 0.1, 0.0};
  EXPECT_EQ(plan(request).error, planning::PlanError::kGoalInObstacle);
}

TEST_F(NavigateStageTest, GoalsGetIncreasingIdsAndTheNavigationCommandStopsWithThem) {
  set_room();
  api::GoalRequest request;
  request.target = {3.0, 2.0, 0.0};
  const auto outcome = plan(request);
  ASSERT_FALSE(outcome.error);
  const auto first = navigate_.start(request, outcome.path, context_)->id;
  const auto second = navigate_.start(request, outcome.path, context_)->id;
  EXPECT_GT(second, first);
  EXPECT_TRUE(context_.navigating);
  context_.begin(1.02, 0.02);
  navigate_.step(context_);
  ASSERT_EQ(context_.mux_requests.size(), 1U);
  EXPECT_EQ(context_.mux_requests[0].source, "navigation");
  EXPECT_TRUE(context_.mux_requests[0].command.has_value());
  navigate_.end_active(navigation::GoalStatus::kCanceled, "estop", context_);
  EXPECT_FALSE(context_.navigating);
  context_.begin(1.04, 0.02);
  navigate_.step(context_);
  // The ended goal's last command must not live on until its mux time-out.
  ASSERT_EQ(context_.mux_requests.size(), 1U);
  EXPECT_FALSE(context_.mux_requests[0].command.has_value());
}

TEST_F(NavigateStageTest, AnUnknownControllerStartsNothingAndTheActiveGoalRunsOn) {
  set_room();
  api::GoalRequest request;
  request.target = {3.0, 2.0, 0.0};
  const auto outcome = plan(request);
  ASSERT_FALSE(outcome.error);
  const auto active = navigate_.start(request, outcome.path, context_);
  ASSERT_TRUE(active);
  request.controller = "teleportation";
  EXPECT_FALSE(navigate_.start(request, outcome.path, context_).has_value());
  EXPECT_TRUE(context_.navigating);
  EXPECT_EQ(navigate_.find(active->id)->status, navigation::GoalStatus::kActive);
}

TEST_F(NavigateStageTest, EveryGoalChangeIsPublishedOnceAsAGoalAndAnEvent) {
  std::vector<std::string> goal_statuses;
  std::vector<std::string> events;
  bus_.goals.subscribe([&](const GoalSample& sample) {
    goal_statuses.emplace_back(navigation::to_string(sample.goal.status));
  });
  bus_.events.subscribe([&](const EventSample& event) { events.push_back(event.kind); });
  set_room();
  api::GoalRequest request;
  request.target = {3.0, 2.0, 0.0};
  const auto outcome = plan(request);
  navigate_.start(request, outcome.path, context_);
  navigate_.start(request, outcome.path, context_);  // preempts the first
  EXPECT_EQ(goal_statuses, (std::vector<std::string>{"active", "canceled", "active"}));
  EXPECT_EQ(events, (std::vector<std::string>{"goal", "goal", "goal"}));
}

}  // namespace
}  // namespace mobot::server
