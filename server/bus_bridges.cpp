#include "server/bus_bridges.h"

#include <memory>

#include "core/timing/rate_schedule.h"

namespace mobot::server {

void connect_stream_hub(Bus& bus, api::StreamHub& hub) {
  bus.pose.subscribe([&hub](const PoseSample& sample) {
    hub.publish_pose(sample.t_s, sample.pose, sample.velocity, sample.covariance,
                     sample.steering_rad);
  });
  bus.odom.subscribe([&hub](const msgs::Odometry& odometry) { hub.publish_odom(odometry); });
  bus.scan.subscribe(
      [&hub](const ScanSample& sample) { hub.publish_scan(sample.scan, sample.sensor_in_map); });
  bus.sonar.subscribe(
      [&hub](const SonarSample& sample) { hub.publish_sonar(sample.ring, sample.base_in_map); });
  bus.ir.subscribe(
      [&hub](const IrSample& sample) { hub.publish_ir(sample.ring, sample.base_in_map); });
  bus.camera.subscribe([&hub](const msgs::Image& image) { hub.publish_camera(image); });
  bus.target.subscribe(
      [&hub](const api::TrackingSnapshot& snapshot) { hub.publish_target(snapshot); });
  bus.costmap.subscribe([&hub](const CostmapSample& sample) {
    hub.publish_costmap(sample.t_s, *sample.costmap, sample.local);
  });
  bus.particles.subscribe([&hub](const ParticlesSample& sample) {
    hub.publish_particles(sample.t_s, sample.particles, sample.total);
  });
  bus.map_tiles.subscribe([&hub](const MapTilesSample& sample) {
    hub.publish_map_tiles(sample.t_s, sample.grid, sample.tiles);
  });
  bus.map.subscribe(
      [&hub](const MapSample& sample) { hub.publish_map(sample.t_s, sample.grid, sample.map_id); });
  bus.status.subscribe(
      [&hub](const api::RobotSnapshot& snapshot) { hub.publish_status(snapshot); });
  bus.events.subscribe(
      [&hub](const EventSample& event) { hub.publish_event(event.t_s, event.kind, event.detail); });
  bus.truth.subscribe([&hub](const api::SimTruth& truth) { hub.publish_truth(truth); });
  bus.cloud.subscribe([&hub](const CloudSample& sample) {
    hub.publish_cloud(sample.t_s, sample.chunk, sample.points);
  });
  bus.goals.subscribe([&hub](const GoalSample& sample) {
    hub.publish_goal(sample.t_s, sample.goal);
    if (sample.path_changed) hub.publish_path(sample.t_s, sample.goal);
  });
  bus.flush.subscribe([&hub](const TickEnd&) { hub.flush(); });
}

void connect_recorder(Bus& bus, Recorder& recorder, double trajectory_rate_hz) {
  bus.events.subscribe([&recorder](const EventSample& event) {
    recorder.record_event(event.t_s, event.kind, event.detail.dump());
  });
  // Only the control loop publishes poses, so the schedule needs no lock.
  auto schedule = std::make_shared<timing::RateSchedule>(1.0 / trajectory_rate_hz);
  bus.pose.subscribe([&recorder, schedule](const PoseSample& sample) {
    if (!schedule->due(sample.t_s)) return;
    schedule->taken(sample.t_s);
    recorder.record_pose(sample.t_s, sample.pose.x, sample.pose.y, sample.pose.theta);
    recorder.set_distance(sample.distance_m);
  });
}

}  // namespace mobot::server
