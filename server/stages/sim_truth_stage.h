#pragma once

#include "drivers/sim_control.h"
#include "server/stage.h"

namespace mobot::server {

// The simulator's ground truth, for the `truth` topic and /sim/truth: only with the sim backend.
class SimTruthStage final : public Stage {
 public:
  explicit SimTruthStage(drivers::SimControl& sim) : sim_(sim) {}

  std::string_view name() const override { return "sim_truth"; }
  void step(TickContext& context) override {
    context.truth = api::SimTruth{context.now_s, sim_.true_pose(), sim_.collision_count(),
                                  sim_.true_steering_rad()};
    context.bus->truth.publish(*context.truth);
  }

 private:
  drivers::SimControl& sim_;
};

}  // namespace mobot::server
