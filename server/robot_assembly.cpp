#include "server/robot_assembly.h"
#include "server/scan_forwarder.h"

#include <algorithm>

#include "server/plugins/costmap_options.h"
#include "server/plugins/safety_options.h"
#include "server/plugins/slam_options.h"
#include "server/stages/advance_stage.h"
#include "server/stages/costmap_stage.h"
#include "server/stages/ir_safety_stage.h"
#include "server/stages/mapping_stage.h"
#include "server/stages/perceive_stage.h"
#include "server/stages/publish_stage.h"
#include "server/stages/read_drivers_stage.h"
#include "server/stages/sim_truth_stage.h"
#include "server/stages/smooth_stage.h"
#include "server/stages/sonar_safety_stage.h"

namespace mobot::server {
namespace {

// The robot's nominal geometry, unless the config holds calibrated values: systematic wheel
// errors stay in the odometry until a UMBmark calibration measures them.
estimation::OdometryParams odometry_params(const OdometrySection& calibrated,
                                           const kinematics::RobotGeometry& geometry) {
  const auto or_nominal = [](double value, double nominal) {
    return value > 0.0 ? value : nominal;
  };
  return {or_nominal(calibrated.left_wheel_radius_m, geometry.wheel_radius_m),
          or_nominal(calibrated.right_wheel_radius_m, geometry.wheel_radius_m),
          or_nominal(calibrated.track_m, geometry.track_m), geometry.ticks_per_wheel_rev};
}

template <class Msg>
void watch(std::vector<WatchedSensor>& out, const drivers::SensorDriver<Msg>* driver,
           const RobotSection& robot) {
  if (!driver) return;
  const std::string name(driver->name());
  // A sensor slower than the control rate gets 2.5 of its own periods before it counts as silent.
  const double timeout_s = std::max(robot.sensor_timeout_s, 2.5 / driver->nominal_rate_hz());
  const bool required = std::find(robot.required_sensors.begin(), robot.required_sensors.end(),
                                  name) != robot.required_sensors.end();
  out.push_back({name, timeout_s, required});
}

std::vector<WatchedSensor> watched_sensors(const drivers::DriverSet& drivers,
                                           const RobotSection& robot) {
  const bool encoders_required =
      std::find(robot.required_sensors.begin(), robot.required_sensors.end(), "encoders") !=
      robot.required_sensors.end();
  std::vector<WatchedSensor> sensors{{"encoders", robot.sensor_timeout_s, encoders_required}};
  watch(sensors, drivers.laser.get(), robot);
  watch(sensors, drivers.sonar.get(), robot);
  watch(sensors, drivers.ir.get(), robot);
  watch(sensors, drivers.compass.get(), robot);
  watch(sensors, drivers.head_range.get(), robot);
  return sensors;
}

navigation::GoalNavigatorOptions navigator_options(const Config& config) {
  navigation::GoalNavigatorOptions options;
  options.avoidance.influence_distance_m = config.navigation.avoidance_distance_m;
  options.avoidance.max_angular_radps = config.robot.limits.max_angular_radps;
  return options;
}

CostmapOptions costmap_options(const Config& config) {
  return read_costmap_options(config.document, config.navigation.inscribed_radius_m);
}

}  // namespace

RobotAssembly::RobotAssembly(const Config& config, Bus& bus,
                             std::unique_ptr<drivers::Backend> backend,
                             SweepStage::Listener on_sweep)
    : backend_(std::move(backend)),
      plugins_(configure_plugins(builtin_plugins(), config, backend_->geometry())),
      kinematics_(plugins_.kinematics.make(config.robot.kinematics)),
      planning_(std::make_unique<PlanningWorker>(costmap_options(config).global, plugins_.planners,
                                                 kinematics_->min_turning_radius_m())),
      // IPaBD's cell (docs/algorithms.md P2): a third of the robot's width.
      sweep_layer_(backend_->geometry().footprint_width_m / 3.0) {
  runtime_ = std::make_unique<Runtime>(bus, build_pipeline(config, std::move(on_sweep)),
                                       1.0 / config.robot.control_rate_hz,
                                       RobotDescription{config.robot.kinematics, backend_->geometry()},
                                       config.robot.realtime_priority);
  drivers::DriverSet& drivers = backend_->drivers();
  if (drivers.laser && drivers.laser->set_arrival_listener(ScanForwarder(bus, *runtime_))) {
    publish_->leave_scans_to_forwarder();
  }
}

RobotAssembly::~RobotAssembly() { backend_->stop_devices(); }

Pipeline RobotAssembly::build_pipeline(const Config& config, SweepStage::Listener on_sweep) {
  drivers::DriverSet& drivers = backend_->drivers();
  drivers::SimControl* sim = backend_->sim_control();
  const geometry::Pose2D start = sim ? sim->true_pose() : geometry::Pose2D{};
  Pipeline pipeline;
  pipeline.add(std::make_unique<AdvanceStage>(*backend_));
  pipeline.add(std::make_unique<ReadDriversStage>(drivers));
  if (drivers.camera_info && drivers.camera_info->omni) {
    pipeline.add(std::make_unique<OmniBearingStage>(*drivers.camera_info->omni,
                                                    drivers.camera_info->landmarks,
                                                    drivers.camera_info->landmark_range_m));
  }
  estimate_ = &pipeline.add(std::make_unique<EstimateStage>(
      odometry_params(config.odometry, backend_->geometry()),
      [this](std::string_view name) { return plugins_.estimators.make(name); },
      config.localization.method, start));
  mapping_ = &pipeline.add(std::make_unique<MappingStage>(read_slam_options(config.document)));
  pipeline.add(std::make_unique<PerceiveStage>([this] { return planning_->static_grid(); },
                                               config.navigation.inscribed_radius_m));
  pipeline.add(std::make_unique<CostmapStage>(costmap_options(config).local,
                                              [this] { return planning_->static_grid(); }));
  if (drivers.tilt) {
    sweep_ = &pipeline.add(std::make_unique<SweepStage>(*drivers.tilt, std::move(on_sweep)));
  }
  navigate_ = &pipeline.add(
      std::make_unique<NavigateStage>(*planning_, plugins_.trackers, navigator_options(config)));
  if (drivers.camera && drivers.camera_info) {
    tracking_ = &pipeline.add(
        std::make_unique<TrackingStage>(*drivers.camera_info, drivers.pan_tilt.get()));
    if (drivers.pan_tilt) {
      FollowOptions follow;
      follow.base.max_linear_mps = config.robot.limits.max_linear_mps;
      follow.base.max_angular_radps =
          std::min(follow.base.max_angular_radps, config.robot.limits.max_angular_radps);
      follow_ = &pipeline.add(
          std::make_unique<FollowStage>(*drivers.camera_info, drivers.pan_tilt.get(), follow));
    }
  }
  if (auto ir = read_ir_safety_options(config.document); ir && drivers.ir) {
    pipeline.add(std::make_unique<IrSafetyStage>(*ir));
  }
  if (auto sonar = read_sonar_emergency_options(config.document); sonar && drivers.sonar) {
    pipeline.add(std::make_unique<SonarSafetyStage>(*sonar));
  }
  safety_ = &pipeline.add(std::make_unique<SafetyStage>(
      watched_sensors(drivers, config.robot),
      [this](const std::string& reason, TickContext& context) {
        navigate_->end_active(navigation::GoalStatus::kFailed, reason, context);
      }));
  mux_ = &pipeline.add(std::make_unique<MuxStage>(config.robot.mux_sources));
  pipeline.add(std::make_unique<SmoothStage>(config.robot.limits));
  write_base_ = &pipeline.add(std::make_unique<WriteBaseStage>(*drivers.base, *kinematics_));
  if (sim) pipeline.add(std::make_unique<SimTruthStage>(*sim));
  publish_ = &pipeline.add(std::make_unique<PublishStage>(
      RobotDescription{config.robot.kinematics, backend_->geometry()}));
  return pipeline;
}

std::vector<MapListener*> RobotAssembly::map_listeners() {
  std::vector<MapListener*> listeners{&sweep_layer_, navigate_, estimate_};
  if (sweep_) listeners.push_back(sweep_);
  return listeners;
}

}  // namespace mobot::server
