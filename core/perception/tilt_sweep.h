#pragma once

#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/tilt_scan.h"
#include "core/perception/point_cloud.h"

namespace mobot::perception {

// A scan mode of the tilting laser (docs/algorithms.md R1, Table 2.1): one up-sweep of the pitch
// range takes period_s, the laser's angular step is step_deg, and that many scans fit in the sweep.
struct SweepMode {
  double period_s = 0.0;
  double step_deg = 0.0;
  int scans = 0;
};

// The Table 2.1 mode for a sweep period (10 or 42 s) and step (1, 0.5 or 0.25 deg), or nullopt.
std::optional<SweepMode> find_sweep_mode(double period_s, double step_deg);
std::vector<SweepMode> sweep_modes();

// The nodding range of R1: pitch -5 .. +20 deg.
struct TiltRange {
  double min_pitch_rad = -0.087266462599716474;  // -5 deg
  double max_pitch_rad = 0.34906585039886590;    // +20 deg
  double span_rad() const { return max_pitch_rad - min_pitch_rad; }
};

// R1: the pitch is not measured. Scan `index` (0 at the limit switch that starts the up-sweep) of a
// sweep with `scans` scans is assigned min + index * delta_alpha, delta_alpha = span / scans.
double assigned_pitch_rad(int index, int scans, const TiltRange& range = {});

// P1: the point of beam (range_m, pitch_rad, bearing_rad) in the sensor frame, x to the right,
// y forward, z up from the floor: x = R cos a cos b, y = R cos a sin b, z = R sin a + height.
struct SensorPoint {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
};
SensorPoint beam_point(double range_m, double pitch_rad, double bearing_rad,
                       double sensor_height_m);

// Appends every return of `scan` to `cloud` in the map frame, the base being at `base_in_map` when
// the scan was taken. Beams without a return are skipped.
void append_scan(const msgs::TiltScan& scan, const geometry::Pose2D& base_in_map,
                 PointCloud& cloud);

}  // namespace mobot::perception
