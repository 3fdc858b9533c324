#include "drivers/hardware/motion_mind_tilt_laser.h"

#include <cmath>
#include <numbers>
#include <utility>

#include "core/numeric/constants.h"

namespace mobot::drivers::hardware {

namespace {

std::int64_t counts_of(double degrees, double counts_per_degree) {
  return std::llround(degrees * counts_per_degree);
}

}  // namespace

MotionMindBoardConfig motion_mind_tilt_board(std::uint8_t address, double counts_per_degree) {
  MotionMindBoardConfig board;
  board.address = address;
  board.counts_per_rev = 360.0 * counts_per_degree;
  board.setup = protocol::motion_mind::r1_tilt_setup();
  board.setup.timer_periods = 2;
  return board;
}

MotionMindTiltLaser::MotionMindTiltLaser(std::shared_ptr<MotionMindLine> line,
                                         MotionMindLine::BoardId board, LaserScanSource& laser,
                                         MotionMindTiltLaserOptions options)
    : line_(std::move(line)), board_(board), laser_(laser), options_(options) {
  laser_.add_listener([this](const msgs::LaserScan& scan,
                             std::chrono::steady_clock::time_point at) { on_scan(scan, at); });
}

void MotionMindTiltLaser::start(const perception::SweepMode& mode, double /*now_s*/) {
  const std::lock_guard lock(mutex_);
  ready_.clear();
  scans_taken_ = 0;
  limit_failed_ = false;
  if (!(mode.period_s > 0.0) || mode.scans <= 0) {
    phase_ = Phase::kIdle;
    return;
  }
  mode_ = mode;
  phase_ = Phase::kHoming;
  const double span_deg = options_.range.span_rad() / kRadPerDeg;
  MotionMindCommand seek;
  seek.kind = MotionMindCommand::Kind::kSeekNegativeLimit;
  seek.radps = -options_.home_speed_dps * kRadPerDeg;
  seek.then_radps = options_.range.span_rad() / mode.period_s;
  seek.then_travel_counts = counts_of(span_deg, options_.counts_per_degree);
  seek.max_seek_counts = counts_of(span_deg + options_.seek_margin_deg, options_.counts_per_degree);
  seek_generation_ = line_->command(board_, seek);
}

std::optional<msgs::TiltScan> MotionMindTiltLaser::poll(double now_s) {
  const std::lock_guard lock(mutex_);
  update_phase();
  if (ready_.empty()) return std::nullopt;
  msgs::TiltScan scan = std::move(ready_.front());
  ready_.pop_front();
  // The laser's clock is not the robot's; a scan is at most one control period old here.
  scan.stamp_s = now_s;
  return scan;
}

void MotionMindTiltLaser::stop() {
  const std::lock_guard lock(mutex_);
  update_phase();
  phase_ = Phase::kIdle;
  ready_.clear();
  park();
}

void MotionMindTiltLaser::park() {
  if (!limit_counts_) {
    line_->set_velocity(board_, 0.0);
    return;
  }
  const std::int64_t level_counts =
      *limit_counts_ +
      counts_of(-options_.range.min_pitch_rad / kRadPerDeg, options_.counts_per_degree);
  const std::optional<std::int64_t> counts = line_->counts(board_);
  MotionMindCommand park;
  if (!counts || *counts == level_counts) {
    park.kind = MotionMindCommand::Kind::kHoldPosition;
    park.position_counts = level_counts;
  } else {
    // At the homing speed and then held: MOVETO_ABSOLUTE alone would swing the laser at full
    // power.
    park.radps = (*counts < level_counts ? 1.0 : -1.0) * options_.home_speed_dps * kRadPerDeg;
    park.stop_at_counts = level_counts;
  }
  line_->command(board_, park);
}

DeviceStatus MotionMindTiltLaser::status() const {
  DeviceStatus line = line_->health().status();
  if (!line.ok) return line;
  DeviceStatus laser = laser_.status();
  if (!laser.ok) return laser;
  const std::lock_guard lock(mutex_);
  if (limit_failed_) return {false, "limit_switch"};
  return {};
}

std::optional<std::int64_t> MotionMindTiltLaser::limit_counts() {
  const std::lock_guard lock(mutex_);
  update_phase();
  return limit_counts_;
}

void MotionMindTiltLaser::update_phase() {
  if (phase_ != Phase::kHoming) return;
  const MotionMindSeekResult seek = line_->seek_result(board_);
  if (seek.generation != seek_generation_) return;
  if (seek.found) {
    phase_ = Phase::kSweeping;
    sweep_start_ = seek.at;
    limit_counts_ = seek.position_counts;
  } else {
    phase_ = Phase::kIdle;
    limit_failed_ = true;
  }
}

void MotionMindTiltLaser::on_scan(const msgs::LaserScan& scan,
                                  std::chrono::steady_clock::time_point at) {
  const std::lock_guard lock(mutex_);
  update_phase();
  if (phase_ != Phase::kSweeping || at < sweep_start_) return;
  const std::chrono::duration<double> interval(mode_.period_s / mode_.scans);
  if (at < sweep_start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              (scans_taken_ - 0.5) * interval)) {
    return;
  }
  ready_.push_back(tilt_scan(scan, scans_taken_));
  if (++scans_taken_ >= mode_.scans) {
    // The laser is the robot's planar laser as well: back to level for it.
    phase_ = Phase::kDone;
    park();
  }
}

msgs::TiltScan MotionMindTiltLaser::tilt_scan(const msgs::LaserScan& scan, int index) const {
  msgs::TiltScan out;
  out.stamp_s = scan.stamp_s;
  out.pitch_rad = perception::assigned_pitch_rad(index, mode_.scans, options_.range);
  // The laser's 0 is straight ahead, positive to the left; the sweep's 0 is to the right.
  out.bearing_min_rad = static_cast<double>(scan.angle_min_rad) + std::numbers::pi / 2.0;
  out.bearing_step_rad = scan.angle_increment_rad;
  out.range_min_m = scan.range_min_m;
  out.range_max_m = scan.range_max_m;
  out.sensor_in_base = options_.sensor_in_base;
  out.sensor_height_m = options_.sensor_height_m;
  out.ranges_m = scan.ranges_m;
  // The laser's scans carry no intensities: the cloud's points get 0 (append_scan's default).
  return out;
}

}  // namespace mobot::drivers::hardware
