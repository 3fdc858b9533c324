#include "core/vision/target_tracker.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace mobot::vision {
namespace {

constexpr std::array<float, 2> kHueRange{0.0F, 180.0F};

void require_tracker(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("TargetTrackerOptions: " + message);
}

bool is_positive(double value) { return std::isfinite(value) && value > 0.0; }

void validate(const TargetTrackerOptions& o) {
  require_tracker(o.hue_bins >= 1 && o.hue_bins <= 180, "hue_bins must be in 1..180");
  require_tracker(o.min_saturation >= 0 && o.min_saturation <= 255,
                  "min_saturation must be in 0..255");
  require_tracker(o.min_value >= 0 && o.min_value <= o.max_value && o.max_value <= 255,
                  "min_value and max_value must satisfy 0 <= min_value <= max_value <= 255");
  require_tracker(o.min_coloured_pixels >= 1, "min_coloured_pixels must be >= 1");
  require_tracker(o.min_coloured_fraction >= 0.0 && o.min_coloured_fraction <= 1.0,
                  "min_coloured_fraction must be in 0..1");
  require_tracker(o.camshift_max_iterations >= 1 && is_positive(o.camshift_epsilon_px),
                  "camshift_max_iterations must be >= 1 and camshift_epsilon_px > 0");
  require_tracker(
      o.occluded_mass_fraction > 0.0 && o.occluded_mass_fraction <= o.reacquire_mass_fraction,
      "occluded_mass_fraction must be > 0 and <= reacquire_mass_fraction");
  require_tracker(std::isfinite(o.reacquire_mass_fraction),
                  "reacquire_mass_fraction must be finite");
  require_tracker(std::isfinite(o.reference_time_constant_s) && o.reference_time_constant_s >= 0.0,
                  "reference_time_constant_s must be >= 0");
  require_tracker(o.collapsed_size_fraction >= 0.0 && o.collapsed_size_fraction < 1.0,
                  "collapsed_size_fraction must be in 0..1");
  require_tracker(is_positive(o.gate_sigmas) && std::isfinite(o.min_gate_px) &&
                      o.min_gate_px >= 0.0 && std::isfinite(o.min_gate_size_fraction) &&
                      o.min_gate_size_fraction >= 0.0,
                  "gate_sigmas must be > 0, min_gate_px and min_gate_size_fraction >= 0");
  require_tracker(std::isfinite(o.search_sigmas) && o.search_sigmas >= 0.0 &&
                      std::isfinite(o.max_search_scale) && o.max_search_scale >= 1.0,
                  "search_sigmas must be >= 0 and max_search_scale >= 1");
  require_tracker(is_positive(o.lost_after_s), "lost_after_s must be > 0");
  require_tracker(is_positive(o.acceleration_sigma_px_s2) && is_positive(o.measurement_sigma_px) &&
                      is_positive(o.initial_velocity_sigma_px_s),
                  "the Kalman sigmas must be > 0");
}

bool is_bgr(const cv::Mat& frame) { return !frame.empty() && frame.type() == CV_8UC3; }

bool inside(const cv::Rect& box, cv::Size image) {
  return box.x >= 0 && box.y >= 0 && static_cast<std::int64_t>(box.x) + box.width <= image.width &&
         static_cast<std::int64_t>(box.y) + box.height <= image.height;
}

cv::Mat to_hsv(const cv::Mat& bgr) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  return hsv;
}

// Where hue means something: grey, dark and blown-out pixels have a hue of noise.
cv::Mat colour_mask(const cv::Mat& hsv, const TargetTrackerOptions& o) {
  cv::Mat mask;
  cv::inRange(hsv, cv::Scalar(0, o.min_saturation, o.min_value), cv::Scalar(180, 255, o.max_value),
              mask);
  return mask;
}

cv::Mat hue_histogram(const cv::Mat& hsv_box, const cv::Mat& mask_box, int bins) {
  const std::array<int, 1> channels{0};
  const std::array<int, 1> sizes{bins};
  std::array<const float*, 1> ranges{kHueRange.data()};
  cv::Mat histogram;
  cv::calcHist(&hsv_box, 1, channels.data(), mask_box, histogram, 1, sizes.data(), ranges.data());
  cv::normalize(histogram, histogram, 0, 255, cv::NORM_MINMAX);
  return histogram;
}

// How much each pixel looks like the target, 0..255.
cv::Mat back_project(const cv::Mat& hsv, const cv::Mat& mask, const cv::Mat& histogram) {
  const std::array<int, 1> channels{0};
  std::array<const float*, 1> ranges{kHueRange.data()};
  cv::Mat probability;
  cv::calcBackProject(&hsv, 1, channels.data(), histogram, probability, ranges.data());
  cv::bitwise_and(probability, mask, probability);
  return probability;
}

// A window of `size` around `centre`, clipped to the image; empty when nothing of it is inside.
// Safe for any centre, however far the prediction coasted.
cv::Rect clipped_window(cv::Point2d centre, cv::Size2d size, cv::Size image) {
  if (!std::isfinite(centre.x) || !std::isfinite(centre.y)) return {};
  const auto span = [](double middle, double length, int limit) {
    const double lo = std::clamp(middle - 0.5 * length, 0.0, static_cast<double>(limit));
    const double hi = std::clamp(middle + 0.5 * length, 0.0, static_cast<double>(limit));
    return std::array<int, 2>{static_cast<int>(std::lround(lo)), static_cast<int>(std::lround(hi))};
  };
  const auto [x0, x1] = span(centre.x, size.width, image.width);
  const auto [y0, y1] = span(centre.y, size.height, image.height);
  return {x0, y0, x1 - x0, y1 - y0};
}

// CamShift's RotatedRect stands for the ellipse of the blob's second moments (camshiftdemo draws
// it so); the box of the rectangle itself would be up to 1.4 times too wide for a round target
// whose noise-driven angle happens to be 45 deg.
cv::Size2d ellipse_extent(const cv::RotatedRect& window) {
  const double angle = window.angle * CV_PI / 180.0;
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  const double w = window.size.width;
  const double h = window.size.height;
  return {std::hypot(w * c, h * s), std::hypot(w * s, h * c)};
}

cv::Rect bounding_in(const cv::RotatedRect& window, cv::Size image) {
  return clipped_window(window.center, ellipse_extent(window), image);
}

double mass_in(const cv::Mat& probability, const cv::RotatedRect& window) {
  const cv::Rect box = bounding_in(window, probability.size());
  return box.empty() ? 0.0 : cv::sum(probability(box))[0];
}

cv::TermCriteria camshift_criteria(const TargetTrackerOptions& o) {
  return {cv::TermCriteria::EPS | cv::TermCriteria::COUNT, o.camshift_max_iterations,
          o.camshift_epsilon_px};
}

}  // namespace

std::string_view to_string(TrackStatus status) {
  switch (status) {
    case TrackStatus::kIdle:
      return "idle";
    case TrackStatus::kTracking:
      return "tracking";
    case TrackStatus::kOccluded:
      return "occluded";
    case TrackStatus::kLost:
      return "lost";
  }
  return "unknown";
}

std::string_view error_code(TrackerError error) {
  switch (error) {
    case TrackerError::kInvalidFrame:
      return "invalid_frame";
    case TrackerError::kInvalidStamp:
      return "invalid_stamp";
    case TrackerError::kEmptyBox:
      return "empty_box";
    case TrackerError::kBoxOutsideImage:
      return "box_outside_image";
    case TrackerError::kTooFewColouredPixels:
      return "too_few_coloured_pixels";
    case TrackerError::kFrameSizeChanged:
      return "frame_size_changed";
  }
  return "unknown";
}

TargetTracker::TargetTracker(TargetTrackerOptions options)
    : options_(options), kalman_(4, 2, 0, CV_64F) {
  validate(options_);
  kalman_.measurementMatrix = (cv::Mat_<double>(2, 4) << 1, 0, 0, 0, 0, 1, 0, 0);
  kalman_.measurementNoiseCov =
      cv::Mat::eye(2, 2, CV_64F) * (options_.measurement_sigma_px * options_.measurement_sigma_px);
}

std::optional<TrackerError> TargetTracker::start(const cv::Mat& bgr, cv::Rect box, double stamp_s) {
  if (!is_bgr(bgr)) return TrackerError::kInvalidFrame;
  if (!std::isfinite(stamp_s)) return TrackerError::kInvalidStamp;
  if (box.width <= 0 || box.height <= 0) return TrackerError::kEmptyBox;
  if (!inside(box, bgr.size())) return TrackerError::kBoxOutsideImage;

  const cv::Mat hsv = to_hsv(bgr);
  const cv::Mat mask = colour_mask(hsv, options_);
  const double needed = std::max(static_cast<double>(options_.min_coloured_pixels),
                                 options_.min_coloured_fraction * box.area());
  if (cv::countNonZero(mask(box)) < needed) return TrackerError::kTooFewColouredPixels;

  cv::Mat histogram = hue_histogram(hsv(box), mask(box), options_.hue_bins);
  const cv::Mat probability = back_project(hsv, mask, histogram);
  // The reference is what CamShift makes of the box, so later frames compare like with like.
  cv::Rect search = box;
  const cv::RotatedRect found = cv::CamShift(probability, search, camshift_criteria(options_));
  const double mass = mass_in(probability, found);
  if (found.size.width < 1.0F || found.size.height < 1.0F || mass <= 0.0) {
    return TrackerError::kTooFewColouredPixels;
  }

  hue_histogram_ = std::move(histogram);
  frame_size_ = bgr.size();
  nominal_size_px_ = ellipse_extent(found);
  reference_mass_ = mass;
  last_seen_s_ = stamp_s;
  const double p = options_.measurement_sigma_px * options_.measurement_sigma_px;
  const double v = options_.initial_velocity_sigma_px_s * options_.initial_velocity_sigma_px_s;
  kalman_.statePost = (cv::Mat_<double>(4, 1) << found.center.x, found.center.y, 0.0, 0.0);
  kalman_.errorCovPost = cv::Mat::diag((cv::Mat_<double>(4, 1) << p, p, v, v));
  state_ = TrackState{};
  state_.status = TrackStatus::kTracking;
  state_.window = found;
  state_.stamp_s = stamp_s;
  state_.mass_fraction = 1.0;
  publish_filter_state();
  return std::nullopt;
}

TrackState TargetTracker::update(const cv::Mat& bgr, double stamp_s) {
  state_.frame_error.reset();
  if (state_.status == TrackStatus::kIdle || state_.status == TrackStatus::kLost) return state_;
  const auto refuse = [this](TrackerError error) {
    TrackState refused = state_;
    refused.frame_error = error;
    return refused;
  };
  if (!is_bgr(bgr)) return refuse(TrackerError::kInvalidFrame);
  if (!std::isfinite(stamp_s) || stamp_s <= state_.stamp_s) {
    return refuse(TrackerError::kInvalidStamp);
  }
  if (bgr.size() != frame_size_) {
    lose(stamp_s);
    state_.frame_error = TrackerError::kFrameSizeChanged;
    return state_;
  }
  const double dt_s = stamp_s - state_.stamp_s;
  // No frames for that long is not seeing the target for that long, and a prediction over such a
  // gap would be worthless.
  if (dt_s > options_.lost_after_s) {
    lose(stamp_s);
    return state_;
  }

  predict(dt_s);
  state_.stamp_s = stamp_s;
  const cv::Point2d predicted(kalman_.statePre.at<double>(0), kalman_.statePre.at<double>(1));
  const cv::Mat hsv = to_hsv(bgr);
  const Measurement measurement =
      measure(back_project(hsv, colour_mask(hsv, options_), hue_histogram_), predicted);
  if (measurement.accepted) {
    accept(measurement, dt_s);
  } else {
    coast(measurement.mass_fraction);
  }
  publish_filter_state();
  return state_;
}

void TargetTracker::stop() { state_ = TrackState{}; }

void TargetTracker::lose(double stamp_s) {
  state_.status = TrackStatus::kLost;
  state_.stamp_s = stamp_s;
  state_.since_seen_s = stamp_s - last_seen_s_;
}

void TargetTracker::predict(double dt_s) {
  cv::Mat& f = kalman_.transitionMatrix;
  f = cv::Mat::eye(4, 4, CV_64F);
  f.at<double>(0, 2) = dt_s;
  f.at<double>(1, 3) = dt_s;
  // Discrete white acceleration: a constant acceleration over each frame interval.
  const double q = options_.acceleration_sigma_px_s2 * options_.acceleration_sigma_px_s2;
  const double pp = q * std::pow(dt_s, 4) / 4.0;
  const double pv = q * std::pow(dt_s, 3) / 2.0;
  const double vv = q * dt_s * dt_s;
  kalman_.processNoiseCov = (cv::Mat_<double>(4, 4) << pp, 0, pv, 0,  //
                             0, pp, 0, pv,                            //
                             pv, 0, vv, 0,                            //
                             0, pv, 0, vv);
  kalman_.predict();
}

TargetTracker::Measurement TargetTracker::measure(const cv::Mat& probability,
                                                  cv::Point2d predicted) const {
  cv::Size2d search = nominal_size_px_;
  if (state_.status == TrackStatus::kTracking) {
    search = ellipse_extent(state_.window);
  } else {
    const double grow = 2.0 * options_.search_sigmas;
    search.width = std::min(search.width + grow * std::sqrt(kalman_.errorCovPre.at<double>(0, 0)),
                            options_.max_search_scale * nominal_size_px_.width);
    search.height = std::min(search.height + grow * std::sqrt(kalman_.errorCovPre.at<double>(1, 1)),
                             options_.max_search_scale * nominal_size_px_.height);
  }
  Measurement measurement;
  cv::Rect window = clipped_window(predicted, search, frame_size_);
  if (window.empty()) return measurement;
  measurement.window = cv::CamShift(probability, window, camshift_criteria(options_));
  const cv::Size2f size = measurement.window.size;
  const double shortest_nominal = std::min(nominal_size_px_.width, nominal_size_px_.height);
  if (std::min(size.width, size.height) <
      std::max(1.0, options_.collapsed_size_fraction * shortest_nominal)) {
    return measurement;
  }
  measurement.mass_fraction = mass_in(probability, measurement.window) / reference_mass_;
  const double needed = state_.status == TrackStatus::kTracking ? options_.occluded_mass_fraction
                                                                : options_.reacquire_mass_fraction;
  const cv::Point2d centre(measurement.window.center.x, measurement.window.center.y);
  measurement.accepted =
      measurement.mass_fraction >= needed && cv::norm(centre - predicted) <= gate_px();
  return measurement;
}

double TargetTracker::gate_px() const {
  const cv::Mat& p = kalman_.errorCovPre;
  const double r = options_.measurement_sigma_px * options_.measurement_sigma_px;
  const double variance = std::max(p.at<double>(0, 0), p.at<double>(1, 1)) + r;
  const double size_gate =
      options_.min_gate_size_fraction * std::min(nominal_size_px_.width, nominal_size_px_.height);
  return std::max({options_.min_gate_px, size_gate, options_.gate_sigmas * std::sqrt(variance)});
}

void TargetTracker::accept(const Measurement& measurement, double dt_s) {
  // The centroid of a partly hidden blob sits off its centre by up to about the hidden fraction of
  // its radius, always the same way: counted as noise, it cannot drag the velocity along, which
  // would send the prediction astray once the target is wholly hidden.
  const double hidden = 1.0 - std::min(measurement.mass_fraction, 1.0);
  const double diameter_px = 0.5 * (nominal_size_px_.width + nominal_size_px_.height);
  const double sigma = options_.measurement_sigma_px;
  kalman_.measurementNoiseCov =
      cv::Mat::eye(2, 2, CV_64F) * (sigma * sigma + std::pow(hidden * diameter_px, 2));
  const cv::Mat z =
      (cv::Mat_<double>(2, 1) << measurement.window.center.x, measurement.window.center.y);
  kalman_.correct(z);
  state_.status = TrackStatus::kTracking;
  state_.window = measurement.window;
  state_.mass_fraction = measurement.mass_fraction;
  last_seen_s_ = state_.stamp_s;
  // A partly hidden target must not teach the reference that it got smaller.
  if (options_.reference_time_constant_s <= 0.0 ||
      measurement.mass_fraction < options_.reacquire_mass_fraction) {
    return;
  }
  const double alpha = std::min(1.0, dt_s / options_.reference_time_constant_s);
  reference_mass_ += alpha * (measurement.mass_fraction - 1.0) * reference_mass_;
  const cv::Size2d seen = ellipse_extent(measurement.window);
  nominal_size_px_ += (seen - nominal_size_px_) * alpha;
}

void TargetTracker::coast(double mass_fraction) {
  const cv::Point2d predicted(kalman_.statePost.at<double>(0), kalman_.statePost.at<double>(1));
  const bool lost = state_.stamp_s - last_seen_s_ > options_.lost_after_s;
  state_.status = lost ? TrackStatus::kLost : TrackStatus::kOccluded;
  state_.window =
      cv::RotatedRect(cv::Point2f(static_cast<float>(predicted.x), static_cast<float>(predicted.y)),
                      cv::Size2f(static_cast<float>(nominal_size_px_.width),
                                 static_cast<float>(nominal_size_px_.height)),
                      0.0F);
  state_.mass_fraction = mass_fraction;
}

void TargetTracker::publish_filter_state() {
  const cv::Mat& x = kalman_.statePost;
  state_.centre_px = {x.at<double>(0), x.at<double>(1)};
  state_.velocity_px_s = {x.at<double>(2), x.at<double>(3)};
  state_.box = bounding_in(state_.window, frame_size_);
  state_.since_seen_s = state_.stamp_s - last_seen_s_;
}

}  // namespace mobot::vision
