#include "core/perception/line_extractor.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

#include "core/perception/line_fitter.h"

namespace mobot::perception {
namespace {

struct ScanPoint {
  geometry::Point2D xy;
  double range_m = 0.0;
  double bearing_rad = 0.0;
  int beam = 0;
};

// A segment under construction: the scan points it owns (in scan order) and its own threshold.
struct Segment {
  std::vector<int> members;
  double threshold_m = 0.0;
};

LineExtractorOptions sanitized(LineExtractorOptions options) {
  options.seed_points = std::max(options.seed_points, 3);
  options.threshold_rank = std::clamp(options.threshold_rank, 2, options.seed_points);
  options.min_points = std::max(options.min_points, 3);
  options.max_consecutive_outliers = std::max(options.max_consecutive_outliers, 0);
  options.threshold_min_m = std::min(options.threshold_min_m, options.threshold_max_m);
  return options;
}

std::vector<ScanPoint> valid_points(const msgs::LaserScan& scan) {
  std::vector<ScanPoint> points;
  points.reserve(scan.ranges_m.size());
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double range_m = scan.ranges_m[i];
    if (!std::isfinite(range_m) || range_m < scan.range_min_m || range_m >= scan.range_max_m) {
      continue;
    }
    const double bearing_rad =
        static_cast<double>(scan.angle_min_rad) +
        static_cast<double>(i) * static_cast<double>(scan.angle_increment_rad);
    points.push_back({{range_m * std::cos(bearing_rad), range_m * std::sin(bearing_rad)},
                      range_m,
                      bearing_rad,
                      static_cast<int>(i)});
  }
  return points;
}

double range_sigma_m(const LineExtractorOptions& options, double range_m) {
  return options.range_sigma_m + options.range_sigma_fraction * range_m;
}

bool is_breakpoint(const ScanPoint& a, const ScanPoint& b, double increment_rad,
                   const LineExtractorOptions& options) {
  const double gap_rad = std::abs(increment_rad) * (b.beam - a.beam);
  if (gap_rad >= options.breakpoint_incidence_rad) return true;
  const double near_m = std::min(a.range_m, b.range_m);
  const double allowed_m =
      near_m * std::sin(gap_rad) / std::sin(options.breakpoint_incidence_rad - gap_rad) +
      options.breakpoint_sigma_factor * range_sigma_m(options, near_m);
  return distance_m(a.xy, b.xy) > allowed_m;
}

LineSegment fit_members(std::span<const ScanPoint> points, const std::vector<int>& members) {
  LineFitter fitter;
  for (const int i : members) fitter.add(points[i].xy);
  return fitter.fit();
}

double max_abs_residual_m(std::span<const ScanPoint> points, const std::vector<int>& members,
                          const LineSegment& line) {
  double worst_m = 0.0;
  for (const int i : members)
    worst_m = std::max(worst_m, std::abs(signed_distance(line, points[i].xy)));
  return worst_m;
}

// E2's dynamic threshold from a seed window [begin, begin + seed_points): nullopt when the seed is
// not straight enough or its first point is off the line (the segment must start at the seed).
std::optional<Segment> seed_segment(std::span<const ScanPoint> points, int begin,
                                    const LineExtractorOptions& options) {
  std::vector<int> window(static_cast<std::size_t>(options.seed_points));
  for (int k = 0; k < options.seed_points; ++k) window[static_cast<std::size_t>(k)] = begin + k;
  const LineSegment seed_line = fit_members(points, window);
  std::vector<double> residuals_m;
  residuals_m.reserve(window.size());
  for (const int i : window)
    residuals_m.push_back(std::abs(signed_distance(seed_line, points[i].xy)));
  std::vector<double> sorted_m = residuals_m;
  std::sort(sorted_m.begin(), sorted_m.end());
  const double ranked_m = sorted_m[static_cast<std::size_t>(options.threshold_rank - 1)];
  if (ranked_m >= options.threshold_max_m) return std::nullopt;

  Segment segment;
  segment.threshold_m = std::clamp(options.threshold_scale * ranked_m, options.threshold_min_m,
                                   options.threshold_max_m);
  if (residuals_m.front() > segment.threshold_m) return std::nullopt;
  for (std::size_t k = 0; k < window.size(); ++k) {
    if (residuals_m[k] <= segment.threshold_m) segment.members.push_back(window[k]);
  }
  return segment;
}

// Grows a seeded segment along the scan up to `end`, refitting after every accepted point.
void grow_segment(std::span<const ScanPoint> points, int from, int end,
                  const LineExtractorOptions& options, Segment& segment) {
  LineFitter fitter;
  for (const int i : segment.members) fitter.add(points[i].xy);
  LineSegment line = fitter.fit();
  int outliers_in_row = 0;
  for (int j = from; j < end; ++j) {
    if (std::abs(signed_distance(line, points[j].xy)) <= segment.threshold_m) {
      segment.members.push_back(j);
      fitter.add(points[j].xy);
      line = fitter.fit();
      outliers_in_row = 0;
    } else if (++outliers_in_row > options.max_consecutive_outliers) {
      break;
    }
  }
}

bool long_enough(std::span<const ScanPoint> points, const Segment& segment,
                 const LineExtractorOptions& options) {
  if (static_cast<int>(segment.members.size()) < options.min_points) return false;
  return distance_m(points[segment.members.front()].xy, points[segment.members.back()].xy) >=
         options.min_length_m;
}

// Sequential region growing over one cluster [begin, end) of consecutive returns.
void segment_cluster(std::span<const ScanPoint> points, int begin, int end,
                     const LineExtractorOptions& options, std::vector<Segment>& segments) {
  int start = begin;
  while (end - start >= options.seed_points) {
    std::optional<Segment> segment = seed_segment(points, start, options);
    if (!segment) {
      ++start;
      continue;
    }
    grow_segment(points, start + options.seed_points, end, options, *segment);
    if (!long_enough(points, *segment, options)) {
      ++start;
      continue;
    }
    start = segment->members.back() + 1;
    segments.push_back(std::move(*segment));
  }
}

std::optional<Segment> try_merge(std::span<const ScanPoint> points, const Segment& first,
                                 const Segment& second, const LineExtractorOptions& options) {
  const LineSegment a = fit_members(points, first.members);
  const LineSegment b = fit_members(points, second.members);
  if (std::abs(geometry::wrap_angle(a.alpha_rad - b.alpha_rad)) > options.merge_alpha_rad ||
      std::abs(a.rho_m - b.rho_m) > options.merge_rho_m ||
      distance_m(points[first.members.back()].xy, points[second.members.front()].xy) >
          options.merge_max_gap_m) {
    return std::nullopt;
  }
  Segment merged;
  merged.members = first.members;
  merged.members.insert(merged.members.end(), second.members.begin(), second.members.end());
  merged.threshold_m = std::max(first.threshold_m, second.threshold_m);
  if (max_abs_residual_m(points, merged.members, fit_members(points, merged.members)) >
      merged.threshold_m) {
    return std::nullopt;
  }
  return merged;
}

void merge_neighbours(std::span<const ScanPoint> points, bool full_circle,
                      const LineExtractorOptions& options, std::vector<Segment>& segments) {
  bool merged_any = true;
  while (merged_any) {
    merged_any = false;
    for (std::size_t k = 0; k + 1 < segments.size(); ++k) {
      if (auto merged = try_merge(points, segments[k], segments[k + 1], options)) {
        segments[k] = std::move(*merged);
        segments.erase(segments.begin() + static_cast<std::ptrdiff_t>(k) + 1);
        merged_any = true;
      }
    }
  }
  // A 360 deg scan starts in the middle of some wall: join its two halves.
  if (full_circle && segments.size() >= 2) {
    if (auto merged = try_merge(points, segments.back(), segments.front(), options)) {
      segments.front() = std::move(*merged);
      segments.pop_back();
    }
  }
}

LineSegment finish(std::span<const ScanPoint> points, const Segment& segment,
                   const LineExtractorOptions& options) {
  LineSegment line = fit_members(points, segment.members);
  line.has_endpoints = true;
  line.start = project_onto(line, points[segment.members.front()].xy);
  line.end = project_onto(line, points[segment.members.back()].xy);
  std::vector<geometry::Point2D> xy;
  std::vector<double> perpendicular_var_m2;
  xy.reserve(segment.members.size());
  perpendicular_var_m2.reserve(segment.members.size());
  for (const int i : segment.members) {
    const ScanPoint& p = points[i];
    const double incidence = p.bearing_rad - line.alpha_rad;
    const double sigma_r = range_sigma_m(options, p.range_m);
    const double along_beam = sigma_r * std::cos(incidence);
    const double across_beam = p.range_m * options.bearing_sigma_rad * std::sin(incidence);
    // A floor keeps grazing beams from claiming zero perpendicular error.
    const double floor_m2 = 0.01 * sigma_r * sigma_r + 1e-12;
    xy.push_back(p.xy);
    perpendicular_var_m2.push_back(
        std::max(along_beam * along_beam + across_beam * across_beam, floor_m2));
  }
  return with_covariance(line, xy, perpendicular_var_m2);
}

}  // namespace

LineExtractor::LineExtractor(const LineExtractorOptions& options) : options_(sanitized(options)) {}

std::vector<LineSegment> LineExtractor::extract(const msgs::LaserScan& scan) const {
  const double increment_rad = scan.angle_increment_rad;
  if (!std::isfinite(increment_rad) || increment_rad == 0.0 || !std::isfinite(scan.angle_min_rad)) {
    return {};
  }
  const std::vector<ScanPoint> points = valid_points(scan);
  const std::span<const ScanPoint> view(points);

  std::vector<Segment> segments;
  int cluster_begin = 0;
  const int count = static_cast<int>(points.size());
  for (int i = 1; i <= count; ++i) {
    if (i == count || is_breakpoint(points[i - 1], points[i], increment_rad, options_)) {
      segment_cluster(view, cluster_begin, i, options_, segments);
      cluster_begin = i;
    }
  }
  const double span_rad = std::abs(increment_rad) * static_cast<double>(scan.ranges_m.size());
  const bool full_circle = span_rad >= 2.0 * std::numbers::pi - 1.5 * std::abs(increment_rad);
  merge_neighbours(view, full_circle, options_, segments);

  std::vector<LineSegment> lines;
  lines.reserve(segments.size());
  for (const Segment& segment : segments) lines.push_back(finish(view, segment, options_));
  return lines;
}

}  // namespace mobot::perception
