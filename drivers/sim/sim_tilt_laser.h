#pragma once

#include <optional>
#include <random>

#include "drivers/sim/tilt_motion.h"
#include "drivers/tilt_laser_driver.h"

namespace mobot::sim {

class SimBackend;

// The simulated nodding laser of R1: the tilt unit moves at constant speed with its speed loop's
// ripple (TiltMotion); each scan of the mode is cast at the unit's true pitch and assigned the
// pitch its count implies, as the real system assigns it.
class SimTiltLaser final : public drivers::TiltLaserDriver {
 public:
  SimTiltLaser(SimBackend& backend, std::uint64_t seed);

  perception::TiltRange range() const override;
  void start(const perception::SweepMode& mode, double now_s) override;
  std::optional<msgs::TiltScan> poll(double now_s) override;
  void stop() override { sweep_.reset(); }
  drivers::DeviceStatus status() const override { return {}; }

 private:
  struct Sweep {
    perception::SweepMode mode;
    TiltMotion motion;
    double started_s = 0.0;
    int scans_done = 0;
  };

  SimBackend& backend_;
  // The ripple's phase differs from sweep to sweep, as the unit's does.
  std::mt19937_64 phase_rng_;
  std::optional<Sweep> sweep_;
};

}  // namespace mobot::sim
