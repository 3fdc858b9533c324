#pragma once

#include <opencv2/core.hpp>

#include <optional>
#include <string_view>
#include <vector>

#include "core/vision/omni_camera_model.h"

namespace mobot::vision {

// docs/algorithms.md E2, measurement 3 from pixels: the bearing of R1's red lit cylinder in the
// omni image. Unwarp to a panorama, threshold the colour in HSV, open, Hough for near-vertical
// lines, column -> bearing.
struct OmniLandmarkBearingOptions {
  // The panorama: columns span the full turn, rows the elevation band, top row highest.
  int panorama_width_px = 720;  // 0.5 deg a column
  int panorama_height_px = 160;
  double min_elevation_rad = -1.0471975511965976;  // -60 deg
  double max_elevation_rad = 0.3490658503988659;   // +20 deg
  // The panorama is unrolled this much further on both sides of the seam (directly behind), so a
  // landmark standing across it is seen whole once. Must exceed the widest landmark.
  double seam_padding_rad = 0.2617993877991494;  // 15 deg

  // The landmark's colour in OpenCV's 8-bit HSV (hue 0..180, wrapping: red straddles 0).
  int hue_centre = 0;
  int hue_tolerance = 10;
  int min_saturation = 100;
  int min_value = 60;
  // The opening's structuring element is a vertical bar: it wipes out specks and thin horizontal
  // streaks but keeps a line one column wide (a landmark far away).
  int open_kernel_rows = 5;

  // A landmark is a near-vertical run of the colour at least this tall, this many times taller
  // than wide (a red patch on the floor is wide and short). 8 deg: R1's 1.5 m cylinder seen from
  // a camera 1.2 m up spans that much 10 m away.
  double min_line_extent_rad = 0.13962634015954636;  // 8 deg
  double max_line_tilt_rad = 0.17453292519943295;    // 10 deg
  double min_aspect = 3.0;
  int hough_max_gap_px = 4;
  // Hough segments closer than this side by side are one landmark.
  double merge_gap_rad = 0.017453292519943295;  // 1 deg
};

struct LandmarkBearing {
  double bearing_rad = 0.0;  // azimuth CCW from the heading, in (-pi, pi]
  double width_rad = 0.0;    // angular width of the coloured band
  double extent_rad = 0.0;   // elevation span of the line found
  int support_px = 0;        // coloured panorama pixels on the line: how sure the detection is
};

enum class OmniFrameError {
  kInvalidFrame,       // "invalid_frame": empty, or not 8-bit BGR
  kFrameSizeMismatch,  // "frame_size_mismatch": not the camera model's width x height
};

std::string_view error_code(OmniFrameError error);

struct OmniLandmarkDetection {
  std::optional<OmniFrameError> error;
  std::vector<LandmarkBearing> landmarks;  // strongest support first
};

// Builds the unwarping maps once for one camera model; detect() then costs one remap and a few
// filters on the panorama. detect() is const and keeps no state: safe to call from any thread.
class OmniLandmarkBearingDetector {
 public:
  // Throws std::invalid_argument on options out of range or a model without a positive size.
  explicit OmniLandmarkBearingDetector(const OmniCameraModel& model,
                                       OmniLandmarkBearingOptions options = {});

  OmniLandmarkDetection detect(const cv::Mat& omni_bgr) const;
  // The panorama without the seam padding (for a dashboard or a log); empty on a bad frame.
  cv::Mat unwarp(const cv::Mat& omni_bgr) const;

  // Column c (pixel centres at integers, 0..width-1) looks at azimuth pi - (c + 0.5) * 2 pi /
  // width: the heading in the middle, the robot's left to the left, the seam directly behind.
  double azimuth_of_column_rad(double column_px) const;
  double column_of_azimuth_px(double azimuth_rad) const;
  // Row r looks at elevation max - (r + 0.5) * (max - min) / height.
  double elevation_of_row_rad(double row_px) const;

  const OmniLandmarkBearingOptions& options() const { return options_; }

 private:
  struct Candidate;

  cv::Mat padded_panorama(const cv::Mat& omni_bgr) const;
  cv::Mat colour_mask(const cv::Mat& panorama_bgr) const;
  std::vector<Candidate> vertical_runs(const cv::Mat& mask) const;
  std::optional<LandmarkBearing> measure(const Candidate& candidate, const cv::Mat& ones) const;

  OmniCameraModel model_;
  OmniLandmarkBearingOptions options_;
  int padding_px_ = 0;
  double column_step_rad_ = 0.0;
  double row_step_rad_ = 0.0;
  cv::Mat map_xy_;  // cv::remap's fixed-point maps over the padded panorama
  cv::Mat map_frac_;
};

}  // namespace mobot::vision
