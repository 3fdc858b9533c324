#include "server/stages/publish_stage.h"

namespace mobot::server {
namespace {

std::array<double, 9> to_array(const Eigen::Matrix3d& m) {
  std::array<double, 9> out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      out[static_cast<std::size_t>(r) * 3 + static_cast<std::size_t>(c)] = m(r, c);
  }
  return out;
}

std::string mode_of(const TickContext& context) {
  if (context.estop) return "estop";
  if (context.mapping) return "mapping";
  if (context.teleop_active) return "teleop";
  if (context.navigating) return "navigating";
  if (context.following) return "following";
  return "idle";
}

}  // namespace

api::RobotSnapshot robot_snapshot(const TickContext& context, const RobotDescription& robot) {
  api::RobotSnapshot snapshot;
  snapshot.t_s = context.now_s;
  snapshot.mode = mode_of(context);
  snapshot.pose = context.pose;
  snapshot.velocity = context.odometry.twist;
  snapshot.localization_method = context.localization_method;
  snapshot.localization_converged = context.localization_converged;
  snapshot.covariance = to_array(context.covariance);
  snapshot.kinematics = robot.kinematics;
  snapshot.steering_rad = context.steering_rad;
  snapshot.geometry = robot.geometry;
  snapshot.estop = context.estop;
  for (const auto& sensor : context.sensors) {
    snapshot.sensors[sensor.name] = {sensor.ok, sensor.rate_hz, sensor.reason};
  }
  return snapshot;
}

void PublishStage::step(TickContext& context) {
  Bus& bus = *context.bus;
  bus.pose.publish({context.now_s, context.pose, context.odometry.twist,
                    to_array(context.covariance), context.distance_m, context.steering_rad});
  bus.odom.publish(context.odometry);
  if (context.image) bus.camera.publish(*context.image);
  if (context.scan && !scans_forwarded_) {
    bus.scan.publish(
        {*context.scan, geometry::compose(context.pose, context.scan->sensor_in_base)});
  }
  if (context.sonar) bus.sonar.publish({*context.sonar, context.pose});
  if (context.ir) bus.ir.publish({*context.ir, context.pose});
  if (status_schedule_.due(context.now_s)) {
    bus.status.publish(robot_snapshot(context, robot_));
    status_schedule_.taken(context.now_s);
  }
  // The batch goes out from Runtime::tick, after the state is published: a client that reads
  // /robot or /goals on a frame sees the state the frame came from.
}

}  // namespace mobot::server
