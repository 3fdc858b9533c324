// mobot-carmen-noise: turns a corrected CARMEN log into one a SLAM run can consume, as the noisy
// Intel log of the benchmark was made (docs/algorithms.md E5): each FLASER line's two pose fields
// become odometry integrated from the reference trajectory's increments, corrupted by a 1 % scale
// error, 0.004 rad/m heading drift and Gaussian noise of 3 % of the step: 3 % of the step length
// along the heading, 1 % of it sideways, and 3 % of the turn combined with 1 % of the length (rad
// per metre) in heading. These fractions reproduce the increment statistics of the benchmark's
// noisy log (straight 1 m steps: 3.1 cm / 0.9 cm / 0.009 rad; turns on the spot: 3 % of the turn).
// The first pose is the reference's; only FLASER lines are written.

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/geometry/pose2d.h"
#include "core/slam/carmen_log.h"
#include "tools/slam/text_input.h"

namespace {

using mobot::geometry::Pose2D;

std::vector<std::string> fields_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> fields;
  std::string field;
  while (in >> field) fields.push_back(field);
  return fields;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Seeded odometry noise for a corrected CARMEN log"};
  std::string in_path, out_path;
  unsigned long long seed = 1;
  double scale_error = 0.01, drift_rad_per_m = 0.004, noise_fraction = 0.03;
  double lateral_fraction = 0.01;
  app.add_option("--in", in_path, "corrected CARMEN log (FLASER poses = reference), plain or .gz")
      ->required();
  app.add_option("--out", out_path, "noisy log to write")->required();
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  app.add_option("--scale-error", scale_error, "odometry scale error (fraction)")
      ->capture_default_str();
  app.add_option("--drift", drift_rad_per_m, "heading drift, rad per metre")->capture_default_str();
  app.add_option("--noise", noise_fraction, "Gaussian std-dev as a fraction of the step")
      ->capture_default_str();
  app.add_option("--lateral-noise", lateral_fraction,
                 "sideways (and heading, rad per metre) std-dev as a fraction of the step length")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    const std::vector<std::string> lines = mobot::tools::read_text_lines(in_path);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::ostringstream out;
    out << std::setprecision(6) << std::fixed;
    bool first = true;
    Pose2D previous_reference;
    Pose2D odometry;
    std::size_t written = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const mobot::slam::CarmenLine parsed = mobot::slam::parse_carmen_line(lines[i]);
      if (parsed.kind == mobot::slam::CarmenLine::Kind::kMalformed) {
        std::cerr << in_path << ":" << i + 1 << ": " << parsed.error << ", skipped\n";
        continue;
      }
      if (parsed.kind != mobot::slam::CarmenLine::Kind::kLaser) continue;
      const std::vector<std::string> fields = fields_of(lines[i]);
      if (fields.empty() || fields[0] != "FLASER") continue;
      const Pose2D& reference = parsed.laser->laser_pose;
      if (first) {
        odometry = reference;
        first = false;
      } else {
        const Pose2D step =
            mobot::geometry::compose(mobot::geometry::inverse(previous_reference), reference);
        const double length_m = std::hypot(step.x, step.y);
        Pose2D noisy;
        const double turn_sigma =
            std::hypot(noise_fraction * step.theta, lateral_fraction * length_m);
        noisy.x = step.x * (1.0 + scale_error) + noise_fraction * length_m * normal(rng);
        noisy.y = step.y * (1.0 + scale_error) + lateral_fraction * length_m * normal(rng);
        noisy.theta = step.theta + drift_rad_per_m * length_m + turn_sigma * normal(rng);
        odometry = mobot::geometry::compose(odometry, noisy);
      }
      previous_reference = reference;
      const std::size_t n = parsed.laser->ranges_m.size();
      out << "FLASER";
      for (std::size_t k = 1; k < 2 + n; ++k) out << ' ' << fields[k];
      for (int twice = 0; twice < 2; ++twice) {
        out << ' ' << odometry.x << ' ' << odometry.y << ' ' << odometry.theta;
      }
      for (std::size_t k = 2 + n + 6; k < fields.size(); ++k) out << ' ' << fields[k];
      out << '\n';
      ++written;
    }
    std::ofstream file(out_path, std::ios::binary);
    file << out.str();
    if (!file) throw std::runtime_error("cannot write " + out_path);
    std::printf("%zu FLASER lines written to %s (seed %llu)\n", written, out_path.c_str(), seed);
  } catch (const std::exception& e) {
    std::cerr << "mobot-carmen-noise: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
