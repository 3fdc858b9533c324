#include "server/sweep_scanner.h"

#include <numbers>
#include <random>

namespace mobot::server {

std::optional<SweepProgress> SweepScanner::progress() const {
  if (!sweep_) return std::nullopt;
  return SweepProgress{sweep_->id, sweep_->scans_done, sweep_->mode.scans, sweep_->cloud.size()};
}

void SweepScanner::start(std::int64_t id, const perception::SweepMode& mode, double now_s,
                         const sim::RobotProfile& profile, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double phase_rad = std::uniform_real_distribution<double>(0.0, 2.0 * std::numbers::pi)(rng);
  sweep_.emplace(Active{id, mode, profile.tilt_range,
                        sim::TiltMotion(profile.tilt_range, mode.period_s,
                                        profile.tilt_speed_ripple_fraction,
                                        profile.tilt_ripple_period_s, phase_rad),
                        now_s, 0, {}, {}});
  // A 42 s sweep at 0.25 deg holds 100 scans of 721 beams.
  sweep_->cloud.reserve(static_cast<std::size_t>(mode.scans) *
                        (static_cast<std::size_t>(180.0 / mode.step_deg) + 1));
}

std::optional<SweepOutcome> SweepScanner::tick(sim::Simulator& sim,
                                               const geometry::Pose2D& base_in_map, double now_s,
                                               api::StreamHub& hub) {
  if (!sweep_) return std::nullopt;
  Active& sweep = *sweep_;
  const double interval_s = sweep.mode.period_s / sweep.mode.scans;
  const double step_rad = sweep.mode.step_deg * std::numbers::pi / 180.0;
  // Scan i is due i intervals after the limit switch; the epsilon keeps float sums from
  // postponing a scan by a whole tick.
  while (sweep.scans_done < sweep.mode.scans &&
         now_s - sweep.started_s >= sweep.scans_done * interval_s - 1e-9) {
    msgs::TiltScan scan = sim.read_tilt_laser(sweep.motion.pitch_rad(now_s - sweep.started_s),
                                              step_rad);
    scan.stamp_s = now_s;
    scan.pitch_rad = perception::assigned_pitch_rad(sweep.scans_done, sweep.mode.scans, sweep.range);
    if (sweep.scans_done == 0) {
      const geometry::Pose2D sensor = geometry::compose(base_in_map, scan.sensor_in_base);
      sweep.origin_in_map = {sensor.x, sensor.y};
    }
    const std::size_t first = sweep.cloud.size();
    perception::append_scan(scan, base_in_map, sweep.cloud);
    ++sweep.scans_done;
    hub.publish_cloud(now_s, {static_cast<std::uint32_t>(sweep.id),
                              static_cast<std::uint32_t>(first),
                              sweep.scans_done == sweep.mode.scans,
                              static_cast<std::uint32_t>(sweep.scans_done),
                              static_cast<std::uint32_t>(sweep.mode.scans)},
                      std::span<const perception::CloudPoint>(sweep.cloud).subspan(first));
  }
  if (sweep.scans_done < sweep.mode.scans) return std::nullopt;
  SweepOutcome outcome{sweep.id, std::nullopt, std::move(sweep.cloud), sweep.origin_in_map,
                       sweep.started_s, now_s};
  sweep_.reset();
  return outcome;
}

std::optional<SweepOutcome> SweepScanner::abort(const std::string& reason, double now_s) {
  if (!sweep_) return std::nullopt;
  SweepOutcome outcome{sweep_->id, reason, {}, sweep_->origin_in_map, sweep_->started_s, now_s};
  sweep_.reset();
  return outcome;
}

}  // namespace mobot::server
