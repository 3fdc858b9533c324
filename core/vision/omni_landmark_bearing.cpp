#include "core/vision/omni_landmark_bearing.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::vision {
namespace {

constexpr double kPi = std::numbers::pi;
// Where the maps point for panorama pixels outside the mirror's ring: far enough outside the
// image that bilinear sampling sees only the black border.
constexpr float kOutside = -10.0F;

void require_omni(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("OmniLandmarkBearingOptions: " + message);
}

void validate(const OmniCameraModel& model, const OmniLandmarkBearingOptions& o) {
  require_omni(model.width_px > 0 && model.height_px > 0, "the camera model needs a positive size");
  require_omni(o.panorama_width_px >= 16 && o.panorama_height_px >= 8,
               "panorama_width_px must be >= 16 and panorama_height_px >= 8");
  require_omni(std::isfinite(o.min_elevation_rad) && std::isfinite(o.max_elevation_rad) &&
                   o.min_elevation_rad < o.max_elevation_rad,
               "the elevation band must be finite with min < max");
  require_omni(
      std::isfinite(o.seam_padding_rad) && o.seam_padding_rad >= 0.0 && o.seam_padding_rad < kPi,
      "seam_padding_rad must be in [0, pi)");
  require_omni(
      o.hue_centre >= 0 && o.hue_centre < 180 && o.hue_tolerance >= 0 && o.hue_tolerance < 90,
      "hue_centre must be in 0..179 and hue_tolerance in 0..89");
  require_omni(
      o.min_saturation >= 0 && o.min_saturation <= 255 && o.min_value >= 0 && o.min_value <= 255,
      "min_saturation and min_value must be in 0..255");
  require_omni(o.open_kernel_rows >= 1, "open_kernel_rows must be >= 1");
  require_omni(std::isfinite(o.min_line_extent_rad) && o.min_line_extent_rad > 0.0,
               "min_line_extent_rad must be > 0");
  require_omni(std::isfinite(o.max_line_tilt_rad) && o.max_line_tilt_rad >= 0.0 &&
                   o.max_line_tilt_rad < kPi / 2,
               "max_line_tilt_rad must be in [0, pi/2)");
  require_omni(std::isfinite(o.min_aspect) && o.min_aspect >= 0.0, "min_aspect must be >= 0");
  require_omni(o.hough_max_gap_px >= 0, "hough_max_gap_px must be >= 0");
  require_omni(std::isfinite(o.merge_gap_rad) && o.merge_gap_rad >= 0.0,
               "merge_gap_rad must be >= 0");
}

// Hue ranges in OpenCV's 0..180 scale, split where they wrap past 0 or 180.
cv::Mat hue_in_band(const cv::Mat& hsv, const OmniLandmarkBearingOptions& o) {
  const int lo = o.hue_centre - o.hue_tolerance;
  const int hi = o.hue_centre + o.hue_tolerance;
  const auto band = [&](int from, int to) {
    cv::Mat mask;
    cv::inRange(hsv, cv::Scalar(from, o.min_saturation, o.min_value), cv::Scalar(to, 255, 255),
                mask);
    return mask;
  };
  cv::Mat mask = band(std::max(lo, 0), std::min(hi, 179));
  if (lo < 0) cv::bitwise_or(mask, band(lo + 180, 179), mask);
  if (hi > 179) cv::bitwise_or(mask, band(0, hi - 180), mask);
  return mask;
}

enum class Axis { kColumns, kRows };

// Set pixels of a 0/1 mask per column or per row.
std::vector<int> counts_along(const cv::Mat& ones, Axis axis) {
  cv::Mat sums;
  cv::reduce(ones, sums, axis == Axis::kColumns ? 0 : 1, cv::REDUCE_SUM, CV_32S);
  return std::vector<int>(sums.begin<int>(), sums.end<int>());
}

int strongest(const std::vector<int>& counts, int from, int to) {
  const auto first = counts.begin() + std::clamp(from, 0, static_cast<int>(counts.size()) - 1);
  const auto last = counts.begin() + std::clamp(to, 0, static_cast<int>(counts.size()) - 1) + 1;
  return static_cast<int>(std::max_element(first, last) - counts.begin());
}

// The entries around `peak` holding at least half its count: the band's body without the
// anti-aliased fringe or a neighbour touching it.
std::pair<int, int> run_around(const std::vector<int>& counts, int peak) {
  const int half = std::max(1, counts[peak] / 2);
  int first = peak;
  while (first > 0 && counts[first - 1] >= half) --first;
  int last = peak;
  while (last + 1 < static_cast<int>(counts.size()) && counts[last + 1] >= half) ++last;
  return {first, last};
}

}  // namespace

struct OmniLandmarkBearingDetector::Candidate {
  double x_min = 0.0;
  double x_max = 0.0;
  int y_min = 0;
  int y_max = 0;
};

std::string_view error_code(OmniFrameError error) {
  switch (error) {
    case OmniFrameError::kInvalidFrame:
      return "invalid_frame";
    case OmniFrameError::kFrameSizeMismatch:
      return "frame_size_mismatch";
  }
  return "unknown";
}

OmniLandmarkBearingDetector::OmniLandmarkBearingDetector(const OmniCameraModel& model,
                                                         OmniLandmarkBearingOptions options)
    : model_(model), options_(options) {
  validate(model_, options_);
  column_step_rad_ = 2.0 * kPi / options_.panorama_width_px;
  row_step_rad_ =
      (options_.max_elevation_rad - options_.min_elevation_rad) / options_.panorama_height_px;
  padding_px_ = static_cast<int>(std::ceil(options_.seam_padding_rad / column_step_rad_));
  const cv::Size size(options_.panorama_width_px + 2 * padding_px_, options_.panorama_height_px);
  cv::Mat map_x(size, CV_32FC1, cv::Scalar(kOutside));
  cv::Mat map_y(size, CV_32FC1, cv::Scalar(kOutside));
  for (int row = 0; row < size.height; ++row) {
    const double elevation = elevation_of_row_rad(row);
    for (int k = 0; k < size.width; ++k) {
      const auto pixel = model_.project({azimuth_of_column_rad(k - padding_px_), elevation});
      if (!pixel) continue;
      map_x.at<float>(row, k) = static_cast<float>(pixel->u);
      map_y.at<float>(row, k) = static_cast<float>(pixel->v);
    }
  }
  cv::convertMaps(map_x, map_y, map_xy_, map_frac_, CV_16SC2);
}

double OmniLandmarkBearingDetector::azimuth_of_column_rad(double column_px) const {
  return geometry::wrap_angle(kPi - (column_px + 0.5) * column_step_rad_);
}

double OmniLandmarkBearingDetector::column_of_azimuth_px(double azimuth_rad) const {
  // Azimuth pi is the left edge of column 0: (-pi, pi] maps onto [0, width).
  const double from_left = kPi - geometry::wrap_angle(azimuth_rad);
  return from_left / column_step_rad_ - 0.5;
}

double OmniLandmarkBearingDetector::elevation_of_row_rad(double row_px) const {
  return options_.max_elevation_rad - (row_px + 0.5) * row_step_rad_;
}

cv::Mat OmniLandmarkBearingDetector::padded_panorama(const cv::Mat& omni_bgr) const {
  cv::Mat panorama;
  cv::remap(omni_bgr, panorama, map_xy_, map_frac_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  return panorama;
}

cv::Mat OmniLandmarkBearingDetector::unwarp(const cv::Mat& omni_bgr) const {
  if (omni_bgr.empty() || omni_bgr.type() != CV_8UC3 ||
      omni_bgr.size() != cv::Size(model_.width_px, model_.height_px)) {
    return {};
  }
  return padded_panorama(omni_bgr)(
             cv::Rect(padding_px_, 0, options_.panorama_width_px, options_.panorama_height_px))
      .clone();
}

cv::Mat OmniLandmarkBearingDetector::colour_mask(const cv::Mat& panorama_bgr) const {
  cv::Mat hsv;
  cv::cvtColor(panorama_bgr, hsv, cv::COLOR_BGR2HSV);
  cv::Mat mask = hue_in_band(hsv, options_);
  const cv::Mat bar =
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, options_.open_kernel_rows));
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, bar);
  return mask;
}

// Near-vertical Hough segments, grouped side by side into one candidate per landmark.
std::vector<OmniLandmarkBearingDetector::Candidate> OmniLandmarkBearingDetector::vertical_runs(
    const cv::Mat& mask) const {
  const double min_length_px = options_.min_line_extent_rad / row_step_rad_;
  std::vector<cv::Vec4i> segments;
  cv::HoughLinesP(mask, segments, 1.0, kPi / 180.0,
                  std::max(1, static_cast<int>(0.5 * min_length_px)), min_length_px,
                  options_.hough_max_gap_px);
  const double max_slope = std::tan(options_.max_line_tilt_rad);
  std::vector<Candidate> runs;
  for (const cv::Vec4i& s : segments) {
    const double dx = std::abs(s[2] - s[0]);
    const double dy = std::abs(s[3] - s[1]);
    if (dy <= 0.0 || dx > max_slope * dy) continue;
    runs.push_back({static_cast<double>(std::min(s[0], s[2])),
                    static_cast<double>(std::max(s[0], s[2])), std::min(s[1], s[3]),
                    std::max(s[1], s[3])});
  }
  std::sort(runs.begin(), runs.end(),
            [](const Candidate& a, const Candidate& b) { return a.x_min < b.x_min; });
  const double merge_gap_px = 1.0 + options_.merge_gap_rad / column_step_rad_;
  std::vector<Candidate> grouped;
  for (const Candidate& run : runs) {
    if (!grouped.empty() && run.x_min <= grouped.back().x_max + merge_gap_px) {
      Candidate& group = grouped.back();
      group.x_max = std::max(group.x_max, run.x_max);
      group.y_min = std::min(group.y_min, run.y_min);
      group.y_max = std::max(group.y_max, run.y_max);
    } else {
      grouped.push_back(run);
    }
  }
  return grouped;
}

// The Hough segments find the line; its extent and bearing come from the coloured pixels around
// them (the segments may cover only part of a wide band): the run of columns around the
// strongest, the run of rows over those columns, and the centroid of the columns, which resolves
// a fraction of a column.
std::optional<LandmarkBearing> OmniLandmarkBearingDetector::measure(const Candidate& candidate,
                                                                    const cv::Mat& ones) const {
  const std::vector<int> columns =
      counts_along(ones.rowRange(candidate.y_min, candidate.y_max + 1), Axis::kColumns);
  const auto [left, right] = run_around(
      columns,
      strongest(columns, static_cast<int>(candidate.x_min), static_cast<int>(candidate.x_max)));
  const std::vector<int> rows = counts_along(ones.colRange(left, right + 1), Axis::kRows);
  const auto [top, bottom] = run_around(rows, strongest(rows, candidate.y_min, candidate.y_max));
  LandmarkBearing bearing;
  bearing.width_rad = (right - left + 1) * column_step_rad_;
  bearing.extent_rad = (bottom - top + 1) * row_step_rad_;
  if (bearing.extent_rad < options_.min_line_extent_rad ||
      bearing.extent_rad < options_.min_aspect * bearing.width_rad) {
    return std::nullopt;
  }
  double sum = 0.0;
  double moment = 0.0;
  for (int i = left; i <= right; ++i) {
    sum += columns[i];
    moment += static_cast<double>(columns[i]) * i;
  }
  bearing.bearing_rad = azimuth_of_column_rad(moment / sum - padding_px_);
  bearing.support_px = static_cast<int>(sum);
  return bearing;
}

OmniLandmarkDetection OmniLandmarkBearingDetector::detect(const cv::Mat& omni_bgr) const {
  OmniLandmarkDetection detection;
  if (omni_bgr.empty() || omni_bgr.type() != CV_8UC3) {
    detection.error = OmniFrameError::kInvalidFrame;
    return detection;
  }
  if (omni_bgr.size() != cv::Size(model_.width_px, model_.height_px)) {
    detection.error = OmniFrameError::kFrameSizeMismatch;
    return detection;
  }
  const cv::Mat mask = colour_mask(padded_panorama(omni_bgr));
  const cv::Mat ones = mask / 255;
  std::vector<LandmarkBearing> found;
  for (const Candidate& candidate : vertical_runs(mask)) {
    if (auto bearing = measure(candidate, ones)) found.push_back(*bearing);
  }
  std::sort(found.begin(), found.end(), [](const LandmarkBearing& a, const LandmarkBearing& b) {
    return a.support_px > b.support_px;
  });
  // The seam padding shows a landmark near the seam twice (or once whole and once cut): keep the
  // strongest of those that overlap.
  for (const LandmarkBearing& candidate : found) {
    const bool seen = std::any_of(
        detection.landmarks.begin(), detection.landmarks.end(), [&](const LandmarkBearing& kept) {
          return std::abs(geometry::wrap_angle(candidate.bearing_rad - kept.bearing_rad)) <=
                 0.5 * (candidate.width_rad + kept.width_rad) + options_.merge_gap_rad;
        });
    if (!seen) detection.landmarks.push_back(candidate);
  }
  return detection;
}

}  // namespace mobot::vision
