#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "core/control/dynamic_window.h"
#include "core/control/path_progress.h"
#include "core/control/path_tracker.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"
#include "core/planning/path.h"
#include "core/planning/planning_grid.h"

namespace mobot::control {

struct VfhOptions {
  // Speeds and accelerations: the same Dashgo limits as the DWA tracker's.
  DynamicLimits limits;
  // The polar histogram: Borenstein and Koren's 72 sectors of 5 degrees.
  int sector_count = 72;
  // The active window: costmap cells within this radius of the robot (half the 3 x 3 m local
  // costmap). A cell's magnitude is c^2 (a - b d) with a = this radius and b = 1 per metre, so it
  // falls to zero at the window's edge; c is its cost / 253 (certainty 1 at the inscribed cost).
  double window_radius_m = 1.5;
  // Certainty of an unknown cell (VFH: never observed, no evidence of an obstacle).
  double unknown_certainty = 0.0;
  // Smoothing half-width l: h'_k = sum_{|i|<=l} (l + 1 - |i|) h_{k+i} / (2l + 1).
  int smoothing_half_width = 3;
  // Binary histogram with hysteresis (VFH+): a sector above high_threshold is blocked, below
  // low_threshold free, in between it keeps its last state. In units of the magnitude of one
  // 0.1 m cell (Borenstein's grid), so they do not depend on the costmap's resolution.
  double high_threshold = 1.0;
  double low_threshold = 0.5;
  // Valleys wider than this many sectors (80 degrees) are "wide": candidate directions half that
  // far inside each border, and the target when it lies between them; narrower ones, their centre.
  int wide_valley_sectors = 16;
  // Openings narrower than this are ignored (too narrow to be real).
  int min_valley_sectors = 2;
  // VFH+ direction cost: weights of the angle to the target, to the current heading and to the
  // previously chosen direction.
  double target_weight = 5.0;
  double heading_weight = 2.0;
  double previous_weight = 2.0;
  // The target is the path point this far ahead of the robot's projection (the goal near the end).
  double lookahead_m = 0.8;
  // w = heading_gain * (chosen direction - heading), clamped.
  double heading_gain = 2.0;
  // A chosen direction more than this off the heading is turned to on the spot.
  double in_place_turn_rad = 1.0;
  // Speed: v = v_max (1 - min(h'_c, h_m) / h_m)(1 - |w| / w_max), h'_c the smoothed density in the
  // direction of travel (Borenstein and Koren), and at most distance_to_goal / approach_time_s.
  double slowdown_density = 2.0;
  double approach_time_s = 1.0;
  double projection_window_m = 2.0;
  // Final approach (latched, stop_and_rotate) within goal_tolerance_m of the goal.
  double goal_tolerance_m = 0.05;
  double goal_tolerance_rad = 0.05;
};

// Vector Field Histogram (Borenstein and Koren 1991, with VFH+'s hysteresis and direction cost;
// docs/algorithms.md C5) following a path: each tick a polar histogram of the local costmap around
// the robot, smoothed and thresholded; the free valleys give candidate directions (narrow valley:
// its centre; wide valley: near its borders or straight at the target) and the one nearest the
// target (the carrot on the path) wins. It steers toward it, slows with the obstacle density
// ahead, stays inside the dynamic window and, as a last guard, never drives its centre into an
// inscribed cell. Every sector blocked is a clear stop (zero command, blocked()). Near the goal it
// stops and turns to the goal heading (stop_and_rotate). Without a costmap the histogram is empty.
class VfhTracker : public PathTracker {
 public:
  // Throws std::invalid_argument on out-of-range options.
  explicit VfhTracker(const VfhOptions& options = {});

  std::string_view name() const override { return "vfh"; }
  bool set_path(const planning::Path& path, std::optional<double> goal_heading_rad) override;
  void clear() override;
  void set_local_costmap(std::shared_ptr<const planning::PlanningGrid> costmap) override {
    costmap_ = std::move(costmap);
  }
  msgs::Twist compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                      double now_s) override;
  TrackerStatus status() const override { return progress_.status(); }

  const VfhOptions& options() const { return options_; }
  bool blocked() const { return blocked_; }
  // Last tick's smoothed histogram and binary histogram (sector k spans [k, k + 1) * 2 pi / n in
  // the map frame), and the direction chosen (map frame) when there was one.
  const std::vector<double>& smoothed_histogram() const { return smoothed_; }
  const std::vector<bool>& blocked_sectors() const { return binary_; }
  std::optional<double> chosen_direction_rad() const { return chosen_; }

 private:
  void build_histogram(const geometry::Pose2D& pose);
  std::optional<double> choose_direction(double target_rad, double heading_rad) const;
  msgs::Twist track(const geometry::Pose2D& pose, const msgs::Twist& velocity);

  VfhOptions options_;
  std::shared_ptr<const planning::PlanningGrid> costmap_;
  PathProgress progress_;
  bool blocked_ = false;
  std::vector<double> histogram_;
  std::vector<double> smoothed_;
  std::vector<bool> binary_;
  std::optional<double> chosen_;
  std::optional<double> previous_;
};

}  // namespace mobot::control
