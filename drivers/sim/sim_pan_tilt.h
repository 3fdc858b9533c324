#pragma once

#include "drivers/pan_tilt_driver.h"

namespace mobot::sim {

// The simulated head: the joints slew toward the target at the head's rates as simulated time
// passes (SimBackend::advance), as the real servos do between two commands.
class SimPanTilt final : public drivers::PanTiltDriver {
 public:
  explicit SimPanTilt(const vision::PanTiltHeadOptions& options) : head_(options) {}

  const vision::PanTiltHeadOptions& head() const override { return head_.options(); }
  void set_target(const vision::PanTilt& joints) override;
  vision::PanTilt target() const override { return target_; }
  vision::PanTilt current() const override { return current_; }
  drivers::DeviceStatus status() const override { return {}; }

  void advance(double dt_s) { current_ = head_.step_towards(current_, target_, dt_s); }
  // Back to looking straight ahead (a simulator reset).
  void reset() { current_ = target_ = {}; }

 private:
  vision::PanTiltHead head_;
  vision::PanTilt current_;
  vision::PanTilt target_;
};

}  // namespace mobot::sim
