#include "drivers/sim/sim_tilt_laser.h"

#include <numbers>

#include "drivers/sim/sim_backend.h"

namespace mobot::sim {

SimTiltLaser::SimTiltLaser(SimBackend& backend, std::uint64_t seed)
    : backend_(backend), phase_rng_(seed) {}

perception::TiltRange SimTiltLaser::range() const { return backend_.profile().tilt_range; }

void SimTiltLaser::start(const perception::SweepMode& mode, double now_s) {
  const RobotProfile& profile = backend_.profile();
  const double phase_rad =
      std::uniform_real_distribution<double>(0.0, 2.0 * std::numbers::pi)(phase_rng_);
  sweep_.emplace(
      Sweep{mode,
            TiltMotion(profile.tilt_range, mode.period_s, profile.tilt_speed_ripple_fraction,
                       profile.tilt_ripple_period_s, phase_rad),
            now_s, 0});
}

std::optional<msgs::TiltScan> SimTiltLaser::poll(double now_s) {
  if (!sweep_ || sweep_->scans_done >= sweep_->mode.scans) return std::nullopt;
  Sweep& sweep = *sweep_;
  const double interval_s = sweep.mode.period_s / sweep.mode.scans;
  // Scan i is due i intervals after the limit switch; the epsilon keeps float sums from
  // postponing a scan by a whole tick.
  if (now_s - sweep.started_s < sweep.scans_done * interval_s - 1e-9) return std::nullopt;
  const double step_rad = sweep.mode.step_deg * std::numbers::pi / 180.0;
  msgs::TiltScan scan = backend_.simulator().read_tilt_laser(
      sweep.motion.pitch_rad(now_s - sweep.started_s), step_rad);
  scan.stamp_s = now_s;
  scan.pitch_rad = perception::assigned_pitch_rad(sweep.scans_done, sweep.mode.scans, range());
  ++sweep.scans_done;
  return scan;
}

}  // namespace mobot::sim
