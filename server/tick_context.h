#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/camera_port.h"
#include "api/ports/control_port.h"
#include "api/ports/sim_control_port.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/compass_reading.h"
#include "core/msgs/contact.h"
#include "core/msgs/head_range.h"
#include "core/msgs/image.h"
#include "core/msgs/ir_ring.h"
#include "core/msgs/landmark_bearing.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/odometry.h"
#include "core/msgs/sonar_ring.h"
#include "core/msgs/twist.h"
#include "core/msgs/wheel_encoders.h"
#include "core/navigation/goal.h"
#include "core/vision/pan_tilt_head.h"
#include "core/planning/planning_grid.h"
#include "server/bus.h"

namespace mobot::server {

// How far the running 3D sweep is.
struct SweepProgress {
  std::int64_t id = 0;
  int scans_done = 0;
  int scans = 0;
  std::size_t points = 0;
};

// A command a stage asks the mux for this tick (the mux stage applies them in order).
struct MuxRequest {
  std::string source;
  std::optional<msgs::Twist> command;  // nothing: the source falls silent at once
};

// How one sensor is doing, as the safety stage judged it this tick.
struct SensorState {
  std::string name;
  bool ok = true;
  double rate_hz = 0.0;
  std::string reason;
};

// What the stages of one control tick hand each other, in pipeline order. The readings and
// requests are this tick's (cleared by begin()); the estimate and the states carry over, so a
// stage that runs before the one that writes a field sees the last tick's value.
struct TickContext {
  explicit TickContext(Bus& bus_) : bus(&bus_) {}

  // Clears this tick's readings and requests and sets the clock.
  void begin(double now, double period) {
    now_s = now;
    period_s = period;
    ++tick;
    encoders.reset();
    scan.reset();
    sonar.reset();
    ir.reset();
    compass.reset();
    bearings.reset();
    image.reset();
    head_range.reset();
    contacts.clear();
    estop_button = false;
    device_faults.clear();
    scan_blocks_path = false;
    mux_requests.clear();
    halt = false;
  }

  // Runs `action` once the state this command or tick produced is published (a reply must never
  // reach a client before what it reports can be read back).
  void then(std::function<void()> action) { after_publish.push_back(std::move(action)); }

  // Publishes an event on the bus, stamped with this tick's time.
  void event(const std::string& kind, nlohmann::json detail) const {
    bus->events.publish({now_s, kind, std::move(detail)});
  }

  Bus* bus;
  double now_s = 0.0;
  double period_s = 0.0;
  std::uint64_t tick = 0;

  // read_drivers
  std::optional<msgs::WheelEncoders> encoders;
  std::optional<msgs::LaserScan> scan;
  std::optional<msgs::SonarRing> sonar;
  std::optional<msgs::IrRing> ir;
  std::optional<msgs::CompassReading> compass;
  std::optional<msgs::LandmarkBearings> bearings;
  std::vector<msgs::Contact> contacts;
  std::optional<msgs::Image> image;  // a camera frame (JPEG)
  std::optional<msgs::HeadRange> head_range;  // the ranger on the camera head
  std::optional<vision::PanTilt> head;        // where the camera head is (a pan/tilt camera)
  // The base's own emergency button is held down.
  bool estop_button = false;
  // Devices whose driver says they are not ok: name -> reason.
  std::vector<std::pair<std::string, std::string>> device_faults;

  // estimate
  geometry::Pose2D pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  msgs::Odometry odometry;
  double distance_m = 0.0;
  std::string localization_method;
  bool localization_converged = false;

  // mapping: a SLAM session is building a map (the estimate is the SLAM's)
  bool mapping = false;

  // perceive: what the sensors see that the map does not have
  std::shared_ptr<const std::vector<geometry::Point2D>> unmapped_points =
      std::make_shared<const std::vector<geometry::Point2D>>();
  bool scan_blocks_path = false;  // this tick's scan saw something on the active path
  std::vector<msgs::RangeReading> avoidance_echoes;  // last sonar ring, echoes off the path removed

  // costmap: the rolling window around the robot the trackers steer on
  std::shared_ptr<const planning::PlanningGrid> local_costmap;

  // 3D sweep
  std::optional<SweepProgress> sweep;

  // navigate
  bool navigating = false;
  std::vector<geometry::Point2D> active_path;  // the active goal's path, empty without one
  std::shared_ptr<const std::vector<navigation::Goal>> goals =
      std::make_shared<const std::vector<navigation::Goal>>();

  // tracking: the camera's target as of its last processed frame
  api::TrackingSnapshot target;
  // The head angles that put the target on the optical axis, from the head's angles when its
  // frame was taken (so the head's own motion since does not feed back); a pan/tilt camera only.
  std::optional<vision::PanTilt> target_head;
  // follow: the base and the head keep the target at a set distance
  bool following = false;

  // safety
  std::vector<SensorState> sensors;
  std::vector<std::string> faults;  // required sensors that are stale or failing

  // Requests to the mux from the stages before it.
  std::vector<MuxRequest> mux_requests;
  // A stage that stops the robot at once (a contact): the mux drops every command and the
  // smoother its ramp.
  bool halt = false;
  // The smoother drops its ramp at its next step: set by whatever dropped the commands (a stage,
  // or a command between ticks: an e-stop, a reset), cleared by the smooth stage.
  bool halt_smoother = false;

  // mux
  bool estop = false;
  bool teleop_active = false;
  std::optional<std::string> mux_source;  // nothing: every source is silent
  msgs::Twist selected;

  // smooth: what the base is told this tick
  msgs::Twist command;
  // A steered base's steering angle as last commanded (WriteBaseStage); nothing on a
  // differential base.
  std::optional<double> steering_rad;

  // publish (simulator only): the ground truth
  std::optional<api::SimTruth> truth;

  // Run by the runtime after the state is published; see then().
  std::vector<std::function<void()>> after_publish;
};

}  // namespace mobot::server
