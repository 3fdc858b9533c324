#include "core/estimation/line_matcher.h"

#include <Eigen/Dense>
#include <cmath>
#include <optional>

namespace mobot::estimation {
namespace {

// How far outside map segment a-b a point lies, measured as E2's endpoint distance sum.
double endpoint_excess_m(const geometry::Point2D& point, const perception::LineSegment& map_line) {
  return distance_m(point, map_line.start) + distance_m(point, map_line.end) -
         distance_m(map_line.start, map_line.end);
}

bool endpoints_fit(const geometry::Pose2D& pose, const perception::LineSegment& observed,
                   const perception::LineSegment& map_line, const LineMatcherOptions& options) {
  if (options.endpoint_gate_m <= 0.0 || !observed.has_endpoints || !map_line.has_endpoints) {
    return true;
  }
  return endpoint_excess_m(geometry::transform_point(pose, observed.start), map_line) <
             options.endpoint_gate_m &&
         endpoint_excess_m(geometry::transform_point(pose, observed.end), map_line) <
             options.endpoint_gate_m;
}

// A map face is seen only from its free side: the robot cannot be behind it. This rejects the far
// face of a thin wall, which is parallel to the near one and would otherwise match whenever the
// pose estimate is off by about the wall's thickness.
bool faces_the_robot(const geometry::Pose2D& pose, const perception::LineSegment& map_line) {
  if (map_line.free_side == 0) return true;
  return perception::signed_distance(map_line, {pose.x, pose.y}) * map_line.free_side > 0.0;
}

std::optional<LineMatch> gated_candidate(const geometry::Pose2D& pose,
                                         const Eigen::Matrix3d& covariance,
                                         const perception::LineSegment& observed,
                                         const Eigen::Matrix2d& noise,
                                         const perception::LineSegment& map_line,
                                         const LineMatcherOptions& options) {
  if (!faces_the_robot(pose, map_line)) return std::nullopt;
  LineMatch match;
  match.prediction = predict_line_measurement(pose, map_line, observed.alpha_rad);
  match.innovation = line_innovation(observed, match.prediction);
  if (std::abs(match.innovation(0)) > options.gate_rho_m ||
      std::abs(match.innovation(1)) > options.gate_alpha_rad) {
    return std::nullopt;
  }
  const Eigen::Matrix2d s =
      match.prediction.h * covariance * match.prediction.h.transpose() + noise;
  const Eigen::LLT<Eigen::Matrix2d> llt(s);
  if (llt.info() != Eigen::Success) return std::nullopt;
  match.mahalanobis2 = match.innovation.dot(llt.solve(match.innovation));
  if (!(match.mahalanobis2 < options.gate_mahalanobis2)) return std::nullopt;
  if (!endpoints_fit(pose, observed, map_line, options)) return std::nullopt;
  match.noise = noise;
  return match;
}

}  // namespace

Eigen::Matrix2d line_measurement_noise(const perception::LineSegment& observed,
                                       const LineMatcherOptions& options) {
  Eigen::Matrix2d noise;
  noise << observed.var_rho_m2 + options.map_var_rho_m2, observed.cov_rho_alpha_m_rad,
      observed.cov_rho_alpha_m_rad, observed.var_alpha_rad2 + options.map_var_alpha_rad2;
  return noise;
}

std::vector<LineMatch> match_lines(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                                   const std::vector<perception::LineSegment>& observed_in_base,
                                   const std::vector<perception::LineSegment>& map_lines,
                                   const LineMatcherOptions& options) {
  std::vector<LineMatch> matches;
  for (std::size_t i = 0; i < observed_in_base.size(); ++i) {
    const perception::LineSegment& observed = observed_in_base[i];
    if (!perception::is_valid(observed)) continue;
    const Eigen::Matrix2d noise = line_measurement_noise(observed, options);
    std::optional<LineMatch> best;
    for (std::size_t j = 0; j < map_lines.size(); ++j) {
      if (!perception::is_valid(map_lines[j])) continue;
      auto candidate = gated_candidate(pose, covariance, observed, noise, map_lines[j], options);
      if (candidate && (!best || candidate->mahalanobis2 < best->mahalanobis2)) {
        candidate->observed_index = static_cast<int>(i);
        candidate->map_index = static_cast<int>(j);
        best = std::move(candidate);
      }
    }
    if (best) matches.push_back(std::move(*best));
  }
  return matches;
}

}  // namespace mobot::estimation
