#pragma once

#include <vector>

#include "core/msgs/laser_scan.h"
#include "core/perception/line_segment.h"

namespace mobot::perception {

// Every knob of the scan line extractor (docs/algorithms.md E2), defaults tuned for a SICK LMS2xx
// at 0.5-1 deg resolution in an office.
struct LineExtractorOptions {
  // Range noise of one beam: sigma = range_sigma_m + range_sigma_fraction * range.
  double range_sigma_m = 0.01;
  double range_sigma_fraction = 0.0;
  // Bearing noise of one beam; keeps grazing-incidence points from looking exact.
  double bearing_sigma_rad = 0.0;

  // Breakpoints between neighbouring returns (Borges & Aldon's adaptive detector): split when two
  // consecutive points are further apart than a wall seen at breakpoint_incidence_rad could place
  // them, plus breakpoint_sigma_factor range sigmas. Missing beams widen the allowed gap.
  double breakpoint_incidence_rad = 0.1745;  // 10 deg
  double breakpoint_sigma_factor = 3.0;

  // Region growing with E2's per-segment dynamic threshold: a seed of seed_points consecutive
  // points is fitted, the threshold_rank-th smallest |residual| (N_p) must lie below
  // threshold_max_m (disT_max), and the segment's distance threshold becomes
  // clamp(threshold_scale * that residual, threshold_min_m, threshold_max_m).
  int seed_points = 7;
  int threshold_rank = 5;
  double threshold_scale = 3.0;
  double threshold_min_m = 0.02;
  double threshold_max_m = 0.10;
  // Isolated outliers inside a segment are dropped; this many in a row end the segment.
  int max_consecutive_outliers = 1;

  // Acceptance of a segment.
  int min_points = 6;
  double min_length_m = 0.3;

  // Neighbouring segments that are collinear within these bounds, and no further apart than
  // merge_max_gap_m, are refitted as one if all their points stay within the larger threshold.
  double merge_alpha_rad = 0.05;
  double merge_rho_m = 0.05;
  double merge_max_gap_m = 0.3;
};

// Extracts straight wall segments from one planar laser scan, in the scan's sensor frame, each
// with its endpoints and the covariance of (rho, alpha). Deterministic; beams that are not finite
// or lie outside [range_min_m, range_max_m) are treated as missing.
class LineExtractor {
 public:
  explicit LineExtractor(const LineExtractorOptions& options = {});

  std::vector<LineSegment> extract(const msgs::LaserScan& scan) const;
  const LineExtractorOptions& options() const { return options_; }

 private:
  LineExtractorOptions options_;
};

}  // namespace mobot::perception
