// The registries: every registered plugin is constructible from its defaults under its own name,
// unknown names and misspelt options are refused with the key named, and names come from one place.
#include "server/plugins/registry.h"

#include <gtest/gtest.h>

#include "server/plugins/plugins.h"

namespace mobot::server {
namespace {

template <class Interface>
void expect_every_plugin_constructible(const Registry<Interface>& registry) {
  ASSERT_FALSE(registry.names().empty()) << registry.kind();
  const PluginSet<Interface> plugins(registry, YAML::Node(),
                                     PluginContext{{0.1, 0.5, 1000, 0.6, 0.6, 1.2}, {}, {}});
  for (const auto& name : registry.names()) {
    const auto instance = plugins.make(name);
    ASSERT_NE(instance, nullptr) << registry.kind() << " " << name;
    EXPECT_EQ(instance->name(), name);
  }
  EXPECT_EQ(plugins.make("no_such_plugin"), nullptr);
}

TEST(Registry, EveryRegisteredPluginIsConstructibleFromItsDefaults) {
  const Plugins plugins = builtin_plugins();
  expect_every_plugin_constructible(plugins.planners);
  expect_every_plugin_constructible(plugins.trackers);
  expect_every_plugin_constructible(plugins.estimators);
  expect_every_plugin_constructible(plugins.kinematics);
}

TEST(Registry, KnowsTheBuiltInNames) {
  const Plugins plugins = builtin_plugins();
  EXPECT_EQ(plugins.planners.names(), (std::vector<std::string>{"astar", "hybrid_astar", "voronoi"}));
  EXPECT_EQ(plugins.trackers.names(), (std::vector<std::string>{"dwa", "lyapunov", "pure_pursuit", "vfh"}));
  EXPECT_EQ(plugins.estimators.names(),
            (std::vector<std::string>{"ekf", "landmark_ekf", "odometry", "particle_filter"}));
  EXPECT_EQ(plugins.kinematics.names(), (std::vector<std::string>{"differential", "tricycle_t1", "tricycle_t2"}));
  EXPECT_FALSE(plugins.planners.contains("dijkstra"));
  EXPECT_FALSE(plugins.trackers.contains("teb"));
}

TEST(Registry, ANameRegisteredTwiceIsAProgrammingError) {
  Plugins plugins = builtin_plugins();
  const Registry<planning::GlobalPlanner>::Parser parser = [](const YAML::Node&,
                                                              const PluginContext&) {
    return Registry<planning::GlobalPlanner>::Maker{};
  };
  EXPECT_THROW(plugins.planners.add("astar", parser), std::logic_error);
  EXPECT_NO_THROW(plugins.planners.add("astar_copy", parser));
}

std::string config_error(const std::string& yaml) {
  const YAML::Node root = YAML::Load(yaml);
  try {
    const Plugins plugins = builtin_plugins();
    PluginSet<planning::GlobalPlanner>(plugins.planners, root, {});
    PluginSet<control::PathTracker>(plugins.trackers, root, {});
    PluginSet<estimation::PoseEstimator>(plugins.estimators, root, {});
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(Registry, EachPluginReadsItsOwnSectionAndRefusesWhatItDoesNotKnow) {
  EXPECT_EQ(config_error("planners: {astar: {cost_penalty_weight: 1.5}}"), "");
  EXPECT_NE(
      config_error("planners: {astar: {cost_penalty: 1.5}}").find("planners.astar.cost_penalty"),
      std::string::npos);
  EXPECT_NE(config_error("planners: {astar: {cost_penalty_weight: -1}}")
                .find("planners.astar.cost_penalty_weight"),
            std::string::npos);
  EXPECT_NE(config_error("planners: {dijkstra: {}}").find("'dijkstra'"), std::string::npos);
  EXPECT_NE(config_error("controllers: {lyapunov: {lookahead_m: fast}}")
                .find("controllers.lyapunov.lookahead_m"),
            std::string::npos);
  EXPECT_NE(config_error("estimators: {ekf: {fuse: [gps]}}").find("'gps'"), std::string::npos);
  EXPECT_NE(config_error("planners: [astar]").find("planners"), std::string::npos);
}

TEST(Registry, AnUnknownSelectedNameNamesTheKeyAndTheKnownNames) {
  Config config;
  config.localization.method = "magic";
  try {
    configure_plugins(builtin_plugins(), config, {});
    FAIL() << "accepted an unknown estimator";
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("localization.method"), std::string::npos) << message;
    EXPECT_NE(message.find("ekf, odometry"), std::string::npos) << message;
  }
  config = {};
  config.robot.kinematics = "hovercraft";
  EXPECT_THROW(configure_plugins(builtin_plugins(), config, {}), ConfigError);
}

TEST(Registry, OptionsReachTheInstance) {
  const Plugins plugins = builtin_plugins();
  const PluginSet<estimation::PoseEstimator> estimators(
      plugins.estimators, YAML::Load("estimators: {ekf: {fuse: [lines, bearing]}}"), {});
  EXPECT_EQ(estimators.make("ekf")->method(), "ekf(odometry+lines+bearing)");
  EXPECT_EQ(estimators.make("odometry")->method(), "odometry");
}

}  // namespace
}  // namespace mobot::server
