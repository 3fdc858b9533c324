#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/tilt_scan.h"
#include "core/perception/tilt_sweep.h"
#include "drivers/hardware/laser_scan_source.h"
#include "drivers/hardware/motion_mind_line.h"
#include "drivers/tilt_laser_driver.h"

namespace mobot::drivers::hardware {

struct MotionMindTiltLaserOptions {
  // Quadrature counts per degree of pitch; positive counts pitch the laser up.
  double counts_per_degree = 0.0;
  perception::TiltRange range;  // the lower end is where NEG_LIM closes
  // Towards the limit switch; the board stops itself at the switch, after its debounce (TIMER x
  // 5 ms: 0.5 deg at 10 deg/s).
  double home_speed_dps = 10.0;
  // A seek that travels the range and this much more without the switch gives up ("limit_switch")
  // rather than drive the axis into its mechanical stop.
  double seek_margin_deg = 10.0;
  // The tilt axis on the base and above the floor (the laser's mount).
  geometry::Pose2D sensor_in_base;
  double sensor_height_m = 0.0;
};

// The tilt axis' board: R1's tilt set-up, with the limit switch debounced over 2 PID periods
// (10 ms) instead of the board's 10: the axis overshoots the switch by the debounce time at the
// homing speed (0.5 deg at 10 deg/s with 50 ms), and the sweep's first scan is assigned the
// switch's pitch.
MotionMindBoardConfig motion_mind_tilt_board(std::uint8_t address, double counts_per_degree);

// R1's nodding laser on real hardware: the tilt axis is a Motion Mind 3 board on a line (usually
// the wheels'), the laser rides on it and hands over each scan through LaserScanSource.
//
// start() sends the axis down to its lower limit switch, then up at span / period; the line turns
// it round on the STATUS read that shows the switch closed and holds it at the top of the span
// (should the scans stop coming). Scans
// that arrive during the up-sweep become TiltScans: scan i gets the pitch lower limit + i x
// span / scans (the hardware does not measure the pitch, as in SimTiltLaser), its bearings move
// from the laser's convention (-pi/2..pi/2, 0 ahead) to the sweep's (0 right, pi/2 ahead). Scan i
// is the mode's i-th scan time, within half an interval: a scan that comes earlier (a laser
// faster than the mode) is skipped, so the count keeps following the pitch. poll() hands them on
// in order, stamped with the robot clock when taken. After the mode's last scan, and on stop(),
// the axis goes back level at the homing speed and holds there (the laser is the robot's planar
// laser too); level is defined by where a sweep found the switch (before that, stop() only stops
// the axis).
class MotionMindTiltLaser final : public TiltLaserDriver {
 public:
  // Sets the laser's listener (before the devices start). The laser source must outlive this
  // driver's use by its thread: the backend stops the devices before the drivers go.
  MotionMindTiltLaser(std::shared_ptr<MotionMindLine> line, MotionMindLine::BoardId board,
                      LaserScanSource& laser, MotionMindTiltLaserOptions options);

  perception::TiltRange range() const override { return options_.range; }
  void start(const perception::SweepMode& mode, double now_s) override;
  std::optional<msgs::TiltScan> poll(double now_s) override;
  void stop() override;
  // The worse of the line's and the laser's; "limit_switch" after a seek that never found it.
  DeviceStatus status() const override;

  // Where the switch was last found, in the line's counts: the sweep's pitch reference.
  std::optional<std::int64_t> limit_counts();

 private:
  enum class Phase { kIdle, kHoming, kSweeping, kDone };

  void on_scan(const msgs::LaserScan& scan, std::chrono::steady_clock::time_point at);
  // Follows the line's seek (mutex_ held).
  void update_phase();
  // Sends the axis level and holds it there (mutex_ held).
  void park();
  msgs::TiltScan tilt_scan(const msgs::LaserScan& scan, int index) const;

  std::shared_ptr<MotionMindLine> line_;
  MotionMindLine::BoardId board_;
  LaserScanSource& laser_;
  MotionMindTiltLaserOptions options_;

  mutable std::mutex mutex_;
  Phase phase_ = Phase::kIdle;
  perception::SweepMode mode_;
  std::uint64_t seek_generation_ = 0;  // the line's number for this sweep's seek
  std::chrono::steady_clock::time_point sweep_start_;
  int scans_taken_ = 0;
  std::deque<msgs::TiltScan> ready_;
  std::optional<std::int64_t> limit_counts_;
  bool limit_failed_ = false;
};

}  // namespace mobot::drivers::hardware
