// The publish stage emits each topic once per tick (scan and sonar only when new, the status at
// 1 Hz); the runtime flushes the batch after it has published the state.
#include "server/stages/publish_stage.h"

#include <gtest/gtest.h>

#include <map>

namespace mobot::server {
namespace {

const RobotDescription kDifferential{"differential", {}};

TEST(PublishStage, EmitsEachTopicOncePerTickAndLeavesTheFlushToTheRuntime) {
  Bus bus;
  std::vector<std::string> order;
  bus.pose.subscribe([&](const PoseSample&) { order.emplace_back("pose"); });
  bus.odom.subscribe([&](const msgs::Odometry&) { order.emplace_back("odom"); });
  bus.scan.subscribe([&](const ScanSample&) { order.emplace_back("scan"); });
  bus.sonar.subscribe([&](const SonarSample&) { order.emplace_back("sonar"); });
  bus.status.subscribe([&](const api::RobotSnapshot&) { order.emplace_back("status"); });
  bus.flush.subscribe([&](const TickEnd&) { order.emplace_back("flush"); });
  PublishStage publish(RobotDescription{"differential", {}});
  TickContext context(bus);

  std::map<std::string, int> counts;
  for (int tick = 1; tick <= 100; ++tick) {  // 2 s at 50 Hz
    context.begin(tick * 0.02, 0.02);
    if (tick % 5 == 0) context.scan = msgs::LaserScan{};
    if (tick % 10 == 0) context.sonar = msgs::SonarRing{};
    order.clear();
    publish.step(context);
    for (const auto& topic : order) ++counts[topic];
    EXPECT_EQ(std::count(order.begin(), order.end(), "pose"), 1);
  }
  EXPECT_EQ(counts["pose"], 100);
  EXPECT_EQ(counts["odom"], 100);
  EXPECT_EQ(counts["scan"], 20);
  EXPECT_EQ(counts["sonar"], 10);
  EXPECT_EQ(counts["status"], 2);
  EXPECT_EQ(counts["flush"], 0);
}

TEST(PublishStage, TheSnapshotsModeFollowsEstopTeleopAndNavigation) {
  Bus bus;
  TickContext context(bus);
  EXPECT_EQ(robot_snapshot(context, kDifferential).mode, "idle");
  context.navigating = true;
  EXPECT_EQ(robot_snapshot(context, kDifferential).mode, "navigating");
  context.teleop_active = true;
  EXPECT_EQ(robot_snapshot(context, kDifferential).mode, "teleop");
  context.estop = true;
  EXPECT_EQ(robot_snapshot(context, kDifferential).mode, "estop");
  EXPECT_EQ(robot_snapshot(context, kDifferential).kinematics, "differential");
}

}  // namespace
}  // namespace mobot::server
