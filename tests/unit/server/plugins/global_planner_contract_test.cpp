// What every registered global planner must do alike: the contract's error codes on the
// same bad inputs, in the same order of checks, with nothing in the result but the error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "server/plugins/plugins.h"

namespace mobot::planning {
namespace {

// Every planner with the options of an empty config.
const server::PluginSet<GlobalPlanner>& planners() {
  static const server::Plugins plugins = server::builtin_plugins();
  static const server::PluginSet<GlobalPlanner> configured(plugins.planners, YAML::Node(),
                                                           server::PluginContext{});
  return configured;
}

class GlobalPlannerContract : public ::testing::TestWithParam<std::string> {};

TEST_P(GlobalPlannerContract, ReportsEachError) {
  PlanningGrid grid(20, 20, 0.1, {});                                          // 2 x 2 m
  for (int y = 0; y < 20; ++y) grid.set_cost({10, y}, PlanningGrid::kLethal);  // a full wall
  grid.set_cost({15, 15}, PlanningGrid::kInscribed);
  grid.set_cost({16, 16}, PlanningGrid::kUnknown);
  const auto planner = planners().make(GetParam());
  ASSERT_NE(planner, nullptr);
  EXPECT_EQ(planner->name(), GetParam());
  const geometry::Pose2D start{0.25, 0.25, 0.0};
  const auto error_of = [&](const geometry::Pose2D& s, const geometry::Pose2D& g) {
    const PlanResult r = planner->plan(grid, s, g);
    EXPECT_TRUE(r.cells.empty());
    EXPECT_TRUE(r.points_in_map.empty());
    return r.error;
  };
  EXPECT_EQ(error_of(start, {2.5, 0.5, 0.0}), PlanError::kGoalOutsideMap);
  EXPECT_EQ(error_of(start, {-0.01, 0.5, 0.0}), PlanError::kGoalOutsideMap);
  EXPECT_EQ(error_of({-3.0, 0.0, 0.0}, {0.5, 0.5, 0.0}), PlanError::kStartOutsideMap);
  EXPECT_EQ(error_of(start, {1.05, 0.5, 0.0}), PlanError::kGoalInObstacle);   // lethal
  EXPECT_EQ(error_of(start, {1.55, 1.55, 0.0}), PlanError::kGoalInObstacle);  // inscribed
  EXPECT_EQ(error_of(start, {1.65, 1.65, 0.0}), PlanError::kGoalInObstacle);  // unknown
  EXPECT_EQ(error_of(start, {1.85, 0.5, 0.0}), PlanError::kNoPath);           // behind the wall
  EXPECT_EQ(error_of({std::nan(""), 0.2, 0.0}, {0.5, 0.5, 0.0}), PlanError::kInvalidPose);
  EXPECT_EQ(error_of(start, {0.5, std::numeric_limits<double>::infinity(), 0.0}),
            PlanError::kInvalidPose);
  EXPECT_EQ(error_of(start, {0.5, 0.5, std::nan("")}), PlanError::kInvalidPose);
  EXPECT_EQ(planner->plan(PlanningGrid(), start, {0.5, 0.5, 0.0}).error, PlanError::kNoMap);

  // Deep inside an obstacle: no traversable cell within the escape distance.
  PlanningGrid blocked(20, 20, 0.1, {}, PlanningGrid::kInscribed);
  blocked.set_cost({1, 1}, PlanningGrid::kFree);
  EXPECT_EQ(planner->plan(blocked, {1.55, 1.55, 0.0}, {0.15, 0.15, 0.0}).error,
            PlanError::kStartInObstacle);
}

TEST(GlobalPlannerContract, ErrorCodesAreTheContractsNames) {
  EXPECT_EQ(error_code(PlanError::kGoalOutsideMap), "goal_outside_map");
  EXPECT_EQ(error_code(PlanError::kStartOutsideMap), "start_outside_map");
  EXPECT_EQ(error_code(PlanError::kGoalInObstacle), "goal_in_obstacle");
  EXPECT_EQ(error_code(PlanError::kStartInObstacle), "start_in_obstacle");
  EXPECT_EQ(error_code(PlanError::kNoPath), "no_path");
  EXPECT_EQ(error_code(PlanError::kInvalidPose), "invalid_pose");
  EXPECT_EQ(error_code(PlanError::kNoMap), "no_map");
}

INSTANTIATE_TEST_SUITE_P(EveryPlanner, GlobalPlannerContract,
                         ::testing::ValuesIn([] { return planners().names(); }()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param;
                         });

}  // namespace
}  // namespace mobot::planning
