#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/frame_codec.h"
#include "api/ports/camera_port.h"
#include "api/ports/control_port.h"
#include "api/ports/sim_control_port.h"
#include "core/estimation/weighted_pose.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/map_tiles.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/image.h"
#include "core/msgs/ir_ring.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/odometry.h"
#include "core/msgs/sonar_ring.h"
#include "core/navigation/goal.h"
#include "core/perception/point_cloud.h"
#include "core/planning/planning_grid.h"

namespace mobot::server {

// One named stream of messages inside the server. Subscribers are attached while the server is
// wired, before anything publishes; publish() hands the message to each of them synchronously,
// so a subscriber must be quick and must not publish back (the stream hub encodes and queues,
// the recorder appends to a buffer). Publishing never blocks on a client or the disk.
template <class Msg>
class Topic {
 public:
  using Handler = std::function<void(const Msg&)>;

  void subscribe(Handler handler) { handlers_.push_back(std::move(handler)); }
  void publish(const Msg& message) const {
    for (const auto& handler : handlers_) handler(message);
  }
  std::size_t subscribers() const { return handlers_.size(); }

 private:
  std::vector<Handler> handlers_;
};

struct PoseSample {
  double t_s = 0.0;
  geometry::Pose2D pose;
  msgs::Twist velocity;
  std::array<double, 9> covariance{};
  double distance_m = 0.0;  // travelled in this run, resets included
  std::optional<double> steering_rad;  // a steered base's
};

struct ScanSample {
  msgs::LaserScan scan;
  geometry::Pose2D sensor_in_map;
};

struct SonarSample {
  msgs::SonarRing ring;
  geometry::Pose2D base_in_map;
};

struct IrSample {
  msgs::IrRing ring;
  geometry::Pose2D base_in_map;
};

// A costmap as planning (global) or the local controller (the rolling window) sees it.
struct CostmapSample {
  double t_s = 0.0;
  std::shared_ptr<const planning::PlanningGrid> costmap;
  bool local = false;
};

// A sample of the particle filter's belief.
struct ParticlesSample {
  double t_s = 0.0;
  std::vector<estimation::WeightedPose> particles;
  std::size_t total = 0;
};

struct MapSample {
  double t_s = 0.0;
  std::shared_ptr<const mapping::OccupancyGrid> grid;
  std::int64_t map_id = 0;
};

// The map being built while mapping: the whole of it (for viewers that subscribe now) and the
// tiles that changed since the last sample (for those that have the rest).
struct MapTilesSample {
  double t_s = 0.0;
  std::shared_ptr<const mapping::OccupancyGrid> grid;
  mapping::MapTileUpdate tiles;
};

struct EventSample {
  double t_s = 0.0;
  std::string kind;
  nlohmann::json detail;
};

struct CloudSample {
  double t_s = 0.0;
  api::CloudChunk chunk;
  std::span<const perception::CloudPoint> points;  // valid only during publish()
};

struct GoalSample {
  double t_s = 0.0;
  navigation::Goal goal;
  bool path_changed = false;  // planned or replanned: the path topic gets it too
};

struct TickEnd {
  double t_s = 0.0;
};

// The server's topics. Stages and commands publish; the stream hub and the recorder subscribe, so
// an event is published once and both record and stream it. A new topic is one member here.
struct Bus {
  Topic<PoseSample> pose;
  Topic<msgs::Odometry> odom;
  Topic<ScanSample> scan;
  Topic<SonarSample> sonar;
  Topic<IrSample> ir;
  Topic<msgs::Image> camera;  // JPEG frames
  Topic<api::TrackingSnapshot> target;
  Topic<CostmapSample> costmap;
  Topic<ParticlesSample> particles;
  Topic<MapSample> map;
  Topic<MapTilesSample> map_tiles;
  Topic<api::RobotSnapshot> status;
  Topic<EventSample> events;
  Topic<api::SimTruth> truth;
  Topic<CloudSample> cloud;
  Topic<GoalSample> goals;
  // The end of a batch of publications (a tick, a command): subscribers send what they hold.
  Topic<TickEnd> flush;
};

}  // namespace mobot::server
