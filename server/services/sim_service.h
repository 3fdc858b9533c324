#pragma once

#include "api/ports/sim_control_port.h"
#include "drivers/sim_control.h"
#include "server/recorder.h"
#include "server/runtime.h"
#include "server/services/map_catalog.h"
#include "server/stages/estimate_stage.h"
#include "server/stages/mux_stage.h"
#include "server/stages/navigate_stage.h"
#include "server/stages/sweep_stage.h"

namespace mobot::server {

// The stages a simulator reset restarts.
struct ResetStages {
  MuxStage& mux;
  NavigateStage& navigate;
  EstimateStage& estimate;
  SweepStage* sweep;  // null without a tilting laser
};

// The SimControlPort on the sim backend's SimControl: resets restart the stages that hold state
// about where the robot is; obstacles are dropped and removed on the control loop.
class SimService final : public api::SimControlPort {
 public:
  SimService(drivers::SimControl& sim, Runtime& runtime, Recorder& recorder, MapCatalog& maps,
             ResetStages stages);

  std::vector<api::WorldInfo> list_worlds() const override;
  api::SimTruth sim_truth() const override;
  void sim_reset(const api::SimResetRequest& request, api::Completion<api::Done> done) override;
  void set_time_scale(double time_scale) override { runtime_.set_time_scale(time_scale); }
  void add_sim_obstacle(const api::SimObstacleRequest& request, api::Completion<int> done) override;
  void remove_sim_obstacle(int id, api::Completion<api::Done> done) override;
  void add_sim_target(const api::SimTargetRequest& request, api::Completion<int> done) override;
  void remove_sim_target(int id, api::Completion<api::Done> done) override;
  void kidnap(const geometry::Pose2D& pose, api::Completion<api::Done> done) override;

 private:
  void reset_on_loop(const std::shared_ptr<const drivers::SimWorldChoice>& world,
                     const api::SimResetRequest& request, TickContext& context);

  drivers::SimControl& sim_;
  Runtime& runtime_;
  Recorder& recorder_;
  MapCatalog& maps_;
  ResetStages stages_;
};

}  // namespace mobot::server
