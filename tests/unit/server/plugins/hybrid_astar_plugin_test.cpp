// planners.hybrid_astar: the base's turning radius and body reach the planner, every option does,
// and a bad one is refused with its full key before anything is built.
#include <gtest/gtest.h>

#include <string>

#include "core/planning/hybrid_astar_planner.h"
#include "server/plugins/option_reader.h"
#include "server/plugins/planner_plugins.h"

namespace mobot::server {
namespace {

std::string planner_error_of(const std::string& yaml, const PluginContext& context = {}) {
  try {
    hybrid_astar_plugin(YAML::Load(yaml), context);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

planning::HybridAStarOptions options_of(const YAML::Node& section, const PluginContext& context) {
  const auto planner = hybrid_astar_plugin(section, context)();
  return dynamic_cast<const planning::HybridAStarPlanner&>(*planner).options();
}

// R3's tricycle as the runtime describes it (deploy/config/tricycle_t1.yaml).
PluginContext tricycle() {
  PluginContext context;
  context.min_turning_radius_m = 1.844;
  context.geometry.footprint_length_m = 2.64;
  context.geometry.footprint_width_m = 1.2;
  context.geometry.footprint_offset_m = 0.92;
  context.geometry.wheelbase_m = 1.844;
  context.navigation.inscribed_radius_m = 0.8;
  return context;
}

TEST(HybridAStarPlugin, TakesTheTurningRadiusAndBodyFromTheRobot) {
  const auto planner = hybrid_astar_plugin(YAML::Node(), tricycle())();
  ASSERT_NE(planner, nullptr);
  EXPECT_EQ(planner->name(), "hybrid_astar");
  EXPECT_FALSE(planner->route_may_be_smoothed());
  const planning::HybridAStarOptions options = options_of(YAML::Node(), tricycle());
  EXPECT_EQ(options.min_turning_radius_m, 1.844);
  EXPECT_EQ(options.primitive_length_m, 0.5);
  EXPECT_EQ(options.footprint_length_m, 2.64);
  EXPECT_EQ(options.footprint_width_m, 1.2);
  EXPECT_EQ(options.footprint_offset_m, 0.92);
  EXPECT_EQ(options.inscribed_radius_m, 0.8);
  const planning::HybridAStarOptions defaults;
  EXPECT_EQ(options.max_expansions, defaults.max_expansions);
  EXPECT_EQ(options.goal_heading_tolerance_rad, defaults.goal_heading_tolerance_rad);
}

TEST(HybridAStarPlugin, ABaseThatTurnsOnTheSpotGetsAGentleRadius) {
  PluginContext differential;  // min_turning_radius_m 0
  differential.navigation.inscribed_radius_m = 0.42;
  const planning::HybridAStarOptions options = options_of(YAML::Node(), differential);
  EXPECT_EQ(options.min_turning_radius_m, 0.5);
  EXPECT_LT(options.primitive_length_m, 0.5);  // a step turns no more than about 22 degrees
  differential.navigation.inscribed_radius_m = 0.9;
  EXPECT_EQ(options_of(YAML::Node(), differential).min_turning_radius_m, 0.9);
}

TEST(HybridAStarPlugin, EveryOptionReachesThePlanner) {
  const planning::HybridAStarOptions options = options_of(YAML::Load(R"(
    min_turning_radius_m: 2.5
    primitive_length_m: 0.6
    steering_samples_per_side: 2
    heading_bins: 36
    state_cell_m: 0.2
    cost_penalty_weight: 1.5
    steering_penalty: 0.2
    steering_change_penalty: 0.7
    max_expansions: 5000
    collision_step_m: 0.05
    path_step_m: 0.2
    shot_interval: 4
    shot_always_within_m: 6
    max_shot_length_m: 20
    goal_heading_tolerance_rad: 0.3
    max_escape_distance_m: 1.0
  )"),
                                                          tricycle());
  EXPECT_EQ(options.min_turning_radius_m, 2.5);
  EXPECT_EQ(options.primitive_length_m, 0.6);
  EXPECT_EQ(options.steering_samples_per_side, 2);
  EXPECT_EQ(options.heading_bins, 36);
  EXPECT_EQ(options.state_cell_m, 0.2);
  EXPECT_EQ(options.cost_penalty_weight, 1.5);
  EXPECT_EQ(options.steering_penalty, 0.2);
  EXPECT_EQ(options.steering_change_penalty, 0.7);
  EXPECT_EQ(options.max_expansions, 5000u);
  EXPECT_EQ(options.collision_step_m, 0.05);
  EXPECT_EQ(options.path_step_m, 0.2);
  EXPECT_EQ(options.shot_interval, 4);
  EXPECT_EQ(options.shot_always_within_m, 6.0);
  EXPECT_EQ(options.max_shot_length_m, 20.0);
  EXPECT_EQ(options.goal_heading_tolerance_rad, 0.3);
  EXPECT_EQ(options.max_escape_distance_m, 1.0);
}

TEST(HybridAStarPlugin, RefusesBadOptionsByTheirKey) {
  EXPECT_NE(planner_error_of("{heading_bins: 2}").find("planners.hybrid_astar.heading_bins"),
            std::string::npos);
  EXPECT_NE(planner_error_of("{min_turning_radius_m: -1}").find("min_turning_radius_m"),
            std::string::npos);
  EXPECT_NE(
      planner_error_of("{turning_radius: 2}").find("planners.hybrid_astar.turning_radius: unknown"),
      std::string::npos);
  // In range alone, but not together: a state cell as long as a step.
  EXPECT_NE(planner_error_of("{state_cell_m: 1.5}", tricycle()).find("planners.hybrid_astar:"),
            std::string::npos);
  EXPECT_EQ(planner_error_of("{state_cell_m: 0.2}", tricycle()), "");
}

}  // namespace
}  // namespace mobot::server
