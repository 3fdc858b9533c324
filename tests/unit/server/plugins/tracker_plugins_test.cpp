// The controllers.dwa and controllers.vfh sections: defaults from the Dashgo within the robot's
// limits, every option read and range-checked with its full key named, unknown keys refused.
#include "server/plugins/tracker_plugins.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "core/control/dwa_tracker.h"
#include "core/control/vfh_tracker.h"

namespace mobot::server {
namespace {

PluginContext context() {
  PluginContext context;
  context.limits.max_linear_mps = 1.0;
  context.limits.max_angular_radps = 1.5;
  context.limits.max_linear_accel_mps2 = 1.0;  // below the Dashgo's 1.5: the cap wins
  context.limits.max_angular_accel_radps2 = 3.0;
  context.navigation.max_linear_mps = 0.6;
  context.navigation.goal_tolerance_m = 0.07;
  context.navigation.goal_tolerance_rad = 0.04;
  return context;
}

template <class Tracker>
control::DynamicLimits limits_of(const control::PathTracker& tracker) {
  const auto* typed = dynamic_cast<const Tracker*>(&tracker);
  EXPECT_NE(typed, nullptr);
  return typed == nullptr ? control::DynamicLimits{} : typed->options().limits;
}

std::string error_of(Registry<control::PathTracker>::Parser parser, const std::string& yaml,
                     const PluginContext& ctx = context()) {
  try {
    parser(YAML::Load(yaml), ctx);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(TrackerPlugins, DwaDefaultsAreTheDashgosWithinTheRobotsLimits) {
  const auto tracker = dwa_plugin(YAML::Node(), context())();
  ASSERT_NE(tracker, nullptr);
  EXPECT_EQ(tracker->name(), "dwa");
  const auto* dwa = dynamic_cast<const control::DwaTracker*>(tracker.get());
  ASSERT_NE(dwa, nullptr);
  const control::DwaOptions& o = dwa->options();
  EXPECT_DOUBLE_EQ(o.limits.max_linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(o.limits.max_angular_radps, 1.0);
  EXPECT_DOUBLE_EQ(o.limits.min_in_place_angular_radps, 0.4);
  EXPECT_DOUBLE_EQ(o.limits.linear_accel_mps2, 1.0);
  EXPECT_DOUBLE_EQ(o.limits.angular_accel_radps2, 2.0);
  EXPECT_DOUBLE_EQ(o.sim_time_s, 1.7);
  EXPECT_EQ(o.angular_samples, 20);
  EXPECT_DOUBLE_EQ(o.goal_tolerance_m, 0.07);
  EXPECT_DOUBLE_EQ(o.goal_tolerance_rad, 0.04);
}

TEST(TrackerPlugins, VfhDefaultsAreTheSameLimits) {
  const auto tracker = vfh_plugin(YAML::Node(), context())();
  ASSERT_NE(tracker, nullptr);
  EXPECT_EQ(tracker->name(), "vfh");
  const auto* vfh = dynamic_cast<const control::VfhTracker*>(tracker.get());
  ASSERT_NE(vfh, nullptr);
  EXPECT_EQ(vfh->options().sector_count, 72);
  EXPECT_DOUBLE_EQ(vfh->options().limits.max_linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(vfh->options().limits.linear_accel_mps2, 1.0);
  EXPECT_DOUBLE_EQ(vfh->options().goal_tolerance_m, 0.07);
}

TEST(TrackerPlugins, ASlowRobotCapsTheDefaults) {
  PluginContext slow = context();
  slow.navigation.max_linear_mps = 0.2;
  slow.limits.max_angular_radps = 0.3;  // below the Dashgo's in-place minimum as well
  const auto tracker = dwa_plugin(YAML::Node(), slow)();
  const control::DynamicLimits limits = limits_of<control::DwaTracker>(*tracker);
  EXPECT_DOUBLE_EQ(limits.max_linear_mps, 0.2);
  EXPECT_DOUBLE_EQ(limits.max_angular_radps, 0.3);
  EXPECT_DOUBLE_EQ(limits.min_in_place_angular_radps, 0.3);
}

TEST(TrackerPlugins, TheControlPeriodIsTheLoopsUnlessTheSectionSetsIt) {
  PluginContext fast = context();
  fast.control_period_s = 0.01;  // robot.control_rate_hz: 100
  EXPECT_DOUBLE_EQ(
      limits_of<control::DwaTracker>(*dwa_plugin(YAML::Node(), fast)()).control_period_s, 0.01);
  EXPECT_DOUBLE_EQ(
      limits_of<control::VfhTracker>(*vfh_plugin(YAML::Node(), fast)()).control_period_s, 0.01);
  EXPECT_DOUBLE_EQ(
      limits_of<control::DwaTracker>(*dwa_plugin(YAML::Load("control_period_s: 0.05"), fast)())
          .control_period_s,
      0.05);
}

TEST(TrackerPlugins, ReadsEveryOption) {
  const auto dwa = dwa_plugin(YAML::Load(R"(
    max_linear_mps: 0.5
    max_angular_radps: 1.2
    min_in_place_angular_radps: 0.3
    linear_accel_mps2: 0.8
    angular_accel_radps2: 2.5
    control_period_s: 0.05
    sim_time_s: 2.0
    sim_granularity_m: 0.05
    angular_sim_granularity_rad: 0.2
    linear_samples: 6
    angular_samples: 10
    path_distance_bias: 20
    goal_distance_bias: 30
    occdist_scale: 0.02
    forward_point_distance_m: 0.2
    local_goal_distance_m: 1.0
    projection_window_m: 3.0
    min_improvement: 0.01
    approach_radius_m: 0.25
    accelerate_in_rollout: true
  )"),
                              context())();
  const auto& o = dynamic_cast<const control::DwaTracker&>(*dwa).options();
  EXPECT_DOUBLE_EQ(o.limits.max_linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(o.limits.control_period_s, 0.05);
  EXPECT_EQ(o.linear_samples, 6);
  EXPECT_DOUBLE_EQ(o.goal_distance_bias, 30.0);
  EXPECT_DOUBLE_EQ(o.min_improvement, 0.01);
  EXPECT_DOUBLE_EQ(o.approach_radius_m, 0.25);
  EXPECT_TRUE(o.accelerate_in_rollout);
  const auto vfh = vfh_plugin(YAML::Load(R"(
    sector_count: 36
    window_radius_m: 2.0
    unknown_certainty: 0.5
    smoothing_half_width: 2
    high_threshold: 3
    low_threshold: 1
    wide_valley_sectors: 8
    min_valley_sectors: 1
    target_weight: 4
    heading_weight: 1
    previous_weight: 1
    lookahead_m: 1.0
    heading_gain: 1.0
    in_place_turn_rad: 1.2
    slowdown_density: 5
    approach_time_s: 2
    projection_window_m: 1.5
  )"),
                              context())();
  const auto& v = dynamic_cast<const control::VfhTracker&>(*vfh).options();
  EXPECT_EQ(v.sector_count, 36);
  EXPECT_DOUBLE_EQ(v.unknown_certainty, 0.5);
  EXPECT_DOUBLE_EQ(v.high_threshold, 3.0);
  EXPECT_DOUBLE_EQ(v.approach_time_s, 2.0);
}

TEST(TrackerPlugins, RefusesOutOfRangeValuesNamingTheKey) {
  EXPECT_EQ(error_of(dwa_plugin, "max_linear_mps: 0.7"),
            "controllers.dwa.max_linear_mps: 0.7 is outside the allowed range [0.01, 0.6]");
  EXPECT_EQ(error_of(dwa_plugin, "linear_accel_mps2: 1.5"),
            "controllers.dwa.linear_accel_mps2: 1.5 is outside the allowed range [0.01, 1]");
  for (const std::string key :
       {"sim_time_s: 0", "sim_granularity_m: 1", "angular_sim_granularity_rad: 0",
        "linear_samples: 0", "angular_samples: 101", "path_distance_bias: -1",
        "goal_distance_bias: 1e6", "occdist_scale: -0.1", "forward_point_distance_m: 3",
        "local_goal_distance_m: 0", "projection_window_m: 0", "min_improvement: -1",
        "approach_radius_m: -1", "accelerate_in_rollout: maybe",
        "control_period_s: 1", "max_angular_radps: 2", "min_in_place_angular_radps: -1",
        "angular_accel_radps2: 4"}) {
    const std::string error = error_of(dwa_plugin, key);
    EXPECT_EQ(error.rfind("controllers.dwa." + key.substr(0, key.find(':')) + ":", 0), 0U)
        << key << " -> " << error;
  }
  for (const std::string key :
       {"sector_count: 4", "window_radius_m: 0.1", "unknown_certainty: 2",
        "smoothing_half_width: 11", "high_threshold: 0", "low_threshold: -1",
        "wide_valley_sectors: 0", "min_valley_sectors: 400", "target_weight: -1",
        "heading_weight: 101", "previous_weight: -2", "lookahead_m: 0", "heading_gain: 0",
        "in_place_turn_rad: 4", "slowdown_density: 0", "approach_time_s: 0",
        "projection_window_m: 20", "max_linear_mps: 0"}) {
    const std::string error = error_of(vfh_plugin, key);
    EXPECT_EQ(error.rfind("controllers.vfh." + key.substr(0, key.find(':')) + ":", 0), 0U)
        << key << " -> " << error;
  }
  EXPECT_EQ(error_of(dwa_plugin, "sim_time_s: fast"),
            "controllers.dwa.sim_time_s: expected a number");
}

TEST(TrackerPlugins, RefusesUnknownKeysAndInconsistentCombinations) {
  EXPECT_EQ(error_of(dwa_plugin, "vx_samples: 8"), "controllers.dwa.vx_samples: unknown key");
  EXPECT_EQ(error_of(vfh_plugin, "sectors: 72"), "controllers.vfh.sectors: unknown key");
  EXPECT_EQ(error_of(dwa_plugin, "[1, 2]"), "controllers.dwa: expected a mapping");
  EXPECT_EQ(error_of(dwa_plugin, "{max_angular_radps: 0.3, min_in_place_angular_radps: 0.4}"),
            "controllers.dwa: DWA tracker options out of range");
  EXPECT_EQ(error_of(vfh_plugin, "{high_threshold: 1, low_threshold: 2}"),
            "controllers.vfh: VFH tracker options out of range");
}

}  // namespace
}  // namespace mobot::server
