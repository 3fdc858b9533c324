#pragma once

#include <memory>
#include <vector>

#include "core/kinematics/kinematic_model.h"
#include "drivers/backend.h"
#include "server/bus.h"
#include "server/config.h"
#include "server/map_listener.h"
#include "server/planning_worker.h"
#include "server/plugins/plugins.h"
#include "server/runtime.h"
#include "server/stages/estimate_stage.h"
#include "server/stages/follow_stage.h"
#include "server/stages/omni_bearing_stage.h"
#include "server/stages/mapping_stage.h"
#include "server/stages/mux_stage.h"
#include "server/stages/navigate_stage.h"
#include "server/stages/publish_stage.h"
#include "server/stages/safety_stage.h"
#include "server/stages/sweep_stage.h"
#include "server/stages/tracking_stage.h"
#include "server/stages/write_base_stage.h"
#include "server/sweep_layer.h"

namespace mobot::server {

// The robot as the config describes it: the backend's drivers, the plugins chosen by name, and the
// control tick built from them as a pipeline of stages (read drivers -> estimate -> perceive ->
// sweep -> navigate -> safety -> mux -> smooth -> write base [-> sim truth] -> publish). Keeps a
// handle on each stage that commands act on.
class RobotAssembly {
 public:
  // `on_sweep` hears every sweep's outcome on the control loop (it must only hand it on).
  RobotAssembly(const Config& config, Bus& bus, std::unique_ptr<drivers::Backend> backend,
                SweepStage::Listener on_sweep);
  // The devices' threads stop first: a laser's scan forwarder calls into the runtime.
  ~RobotAssembly();
  RobotAssembly(const RobotAssembly&) = delete;
  RobotAssembly& operator=(const RobotAssembly&) = delete;

  drivers::Backend& backend() { return *backend_; }
  const ConfiguredPlugins& plugins() const { return plugins_; }
  const kinematics::KinematicModel& kinematics() const { return *kinematics_; }
  PlanningWorker& planning() { return *planning_; }
  SweepLayer& sweep_layer() { return sweep_layer_; }
  Runtime& runtime() { return *runtime_; }

  EstimateStage& estimate() { return *estimate_; }
  MappingStage& mapping() { return *mapping_; }
  NavigateStage& navigate() { return *navigate_; }
  SweepStage& sweep() { return *sweep_; }
  MuxStage& mux() { return *mux_; }
  WriteBaseStage& write_base() { return *write_base_; }
  const SafetyStage& safety() const { return *safety_; }
  // Null on a robot without a camera (tracking) or without a pan/tilt head (follow).
  TrackingStage* tracking() { return tracking_; }
  FollowStage* follow() { return follow_; }

  // Everything that works on the active map, in the order a new map reaches it.
  std::vector<MapListener*> map_listeners();

 private:
  Pipeline build_pipeline(const Config& config, SweepStage::Listener on_sweep);

  std::unique_ptr<drivers::Backend> backend_;
  ConfiguredPlugins plugins_;
  std::unique_ptr<kinematics::KinematicModel> kinematics_;
  std::unique_ptr<PlanningWorker> planning_;
  SweepLayer sweep_layer_;
  EstimateStage* estimate_ = nullptr;
  MappingStage* mapping_ = nullptr;
  NavigateStage* navigate_ = nullptr;
  SweepStage* sweep_ = nullptr;
  SafetyStage* safety_ = nullptr;
  MuxStage* mux_ = nullptr;
  WriteBaseStage* write_base_ = nullptr;
  PublishStage* publish_ = nullptr;
  TrackingStage* tracking_ = nullptr;
  FollowStage* follow_ = nullptr;
  std::unique_ptr<Runtime> runtime_;
};

}  // namespace mobot::server
