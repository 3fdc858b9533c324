#include "core/perception/tilt_sweep.h"

#include <array>
#include <cmath>

namespace mobot::perception {
namespace {

// docs/algorithms.md R1, Table 2.1.
constexpr std::array<SweepMode, 6> kTable21{{
    {10.0, 1.0, 81},
    {10.0, 0.5, 40},
    {10.0, 0.25, 24},
    {42.0, 1.0, 320},
    {42.0, 0.5, 160},
    {42.0, 0.25, 100},
}};

}  // namespace

std::optional<SweepMode> find_sweep_mode(double period_s, double step_deg) {
  for (const SweepMode& mode : kTable21) {
    if (mode.period_s == period_s && mode.step_deg == step_deg) return mode;
  }
  return std::nullopt;
}

std::vector<SweepMode> sweep_modes() { return {kTable21.begin(), kTable21.end()}; }

double assigned_pitch_rad(int index, int scans, const TiltRange& range) {
  return range.min_pitch_rad + index * range.span_rad() / scans;
}

SensorPoint beam_point(double range_m, double pitch_rad, double bearing_rad,
                       double sensor_height_m) {
  const double horizontal_m = range_m * std::cos(pitch_rad);
  return {horizontal_m * std::cos(bearing_rad), horizontal_m * std::sin(bearing_rad),
          range_m * std::sin(pitch_rad) + sensor_height_m};
}

void append_scan(const msgs::TiltScan& scan, const geometry::Pose2D& base_in_map,
                 PointCloud& cloud) {
  const geometry::Pose2D sensor = geometry::compose(base_in_map, scan.sensor_in_base);
  const double c = std::cos(sensor.theta);
  const double s = std::sin(sensor.theta);
  for (std::size_t k = 0; k < scan.ranges_m.size(); ++k) {
    const float range_m = scan.ranges_m[k];
    if (!(range_m >= scan.range_min_m && range_m <= scan.range_max_m)) continue;
    const double bearing_rad =
        scan.bearing_min_rad + static_cast<double>(k) * scan.bearing_step_rad;
    const SensorPoint p = beam_point(range_m, scan.pitch_rad, bearing_rad, scan.sensor_height_m);
    // The sensor's forward (y) is the base's x and its right (x) the base's -y.
    const double forward_m = p.y_m;
    const double left_m = -p.x_m;
    cloud.push_back({static_cast<float>(sensor.x + c * forward_m - s * left_m),
                     static_cast<float>(sensor.y + s * forward_m + c * left_m),
                     static_cast<float>(p.z_m),
                     k < scan.intensities.size() ? scan.intensities[k] : 0.0F});
  }
}

}  // namespace mobot::perception
