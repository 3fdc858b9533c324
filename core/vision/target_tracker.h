#pragma once

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include <optional>
#include <string_view>

namespace mobot::vision {

// docs/algorithms.md E6: CamShift on a hue histogram, centred by a constant-velocity Kalman filter.
struct TargetTrackerOptions {
  // The colour model, as OpenCV's camshiftdemo: a hue histogram over the pixels saturated and
  // bright enough for their hue to mean something (OpenCV's 8-bit HSV: H 0..180, S and V 0..255).
  int hue_bins = 16;
  int min_saturation = 60;
  int min_value = 32;
  int max_value = 255;
  // start() refuses a box with fewer coloured pixels than this, or than this fraction of its area.
  int min_coloured_pixels = 50;
  double min_coloured_fraction = 0.05;

  int camshift_max_iterations = 10;
  double camshift_epsilon_px = 1.0;

  // The target counts as occluded when the back-projection mass in CamShift's window falls below
  // this fraction of the reference (the mass at start, followed slowly while the target is whole),
  // and as seen again when it is back above the second, higher one: the hysteresis keeps a target
  // half behind an edge from flickering between the two.
  double occluded_mass_fraction = 0.35;
  double reacquire_mass_fraction = 0.6;
  // The reference mass and window size follow the target (nearing, receding) with this time
  // constant, only while at least reacquire_mass_fraction of it is seen; 0 keeps the start values.
  double reference_time_constant_s = 5.0;
  // CamShift's window is a collapse when its shorter side is below this fraction of the nominal's.
  double collapsed_size_fraction = 0.25;
  // CamShift's centre must lie within this many standard deviations of the predicted measurement,
  // or within min_gate_size_fraction of the nominal window's size (a target that overlaps its
  // predicted self is itself, however sharply it turned), or min_gate_px: beyond all three it has
  // locked onto something else.
  double gate_sigmas = 4.0;
  double min_gate_size_fraction = 0.5;
  double min_gate_px = 10.0;
  // While occluded the search window grows by this many position standard deviations each side,
  // up to max_search_scale times the nominal window.
  double search_sigmas = 2.0;
  double max_search_scale = 3.0;
  // Occluded for longer than this (since the last frame it was seen in): lost.
  double lost_after_s = 3.0;

  // Kalman filter over [x, y, x', y'] in pixels and pixels per second. Process noise is a white
  // acceleration of this standard deviation; the measurement is CamShift's centre, whose sigma
  // grows by (1 - mass fraction) x the window's size while the target is partly hidden.
  double acceleration_sigma_px_s2 = 150.0;
  double measurement_sigma_px = 3.0;
  double initial_velocity_sigma_px_s = 200.0;
};

enum class TrackStatus {
  kIdle,      // not started, or stopped
  kTracking,  // seen in this frame
  kOccluded,  // not seen; coasting on the prediction
  kLost,      // not seen for longer than lost_after_s; stays lost until start()
};

std::string_view to_string(TrackStatus status);

enum class TrackerError {
  kInvalidFrame,          // "invalid_frame": empty, or not 8-bit 3-channel BGR
  kInvalidStamp,          // "invalid_stamp": not finite, or not after the last frame's
  kEmptyBox,              // "empty_box": zero or negative width or height
  kBoxOutsideImage,       // "box_outside_image": not wholly inside the frame
  kTooFewColouredPixels,  // "too_few_coloured_pixels": the box is grey, dark or washed out
  kFrameSizeChanged,      // "frame_size_changed": the frame is not the size tracking started on
};

std::string_view error_code(TrackerError error);

struct TrackState {
  TrackStatus status = TrackStatus::kIdle;
  // CamShift's result when tracking; the predicted window (nominal size) while occluded or lost.
  cv::RotatedRect window;
  // The window's bounding box clipped to the image: empty when the prediction left the image.
  cv::Rect box;
  // The Kalman filter's estimate (OpenCV pixel coordinates: integers are pixel centres). It lags
  // a sharp turn by a few frames; window.center is CamShift's raw measurement while tracking.
  cv::Point2d centre_px;
  cv::Point2d velocity_px_s;
  double stamp_s = 0.0;  // the last accepted frame
  double since_seen_s = 0.0;
  // Back-projection mass in CamShift's window over the reference: ~1 when the target is whole.
  double mass_fraction = 0.0;
  // Set when update() refused this frame; except for kFrameSizeChanged (which loses the target)
  // the tracker then changed nothing and the rest is the previous state.
  std::optional<TrackerError> frame_error;
};

// One target in one camera's frames. Frames must come with increasing stamps; the Kalman
// transition uses the real time between them (F = [[1,0,dt,0],[0,1,0,dt],[0,0,1,0],[0,0,0,1]])
// rather than the source's dt = 1 frame, so velocities are in px/s and a dropped frame or a varying
// frame rate predicts right. Not for concurrent use.
class TargetTracker {
 public:
  // Throws std::invalid_argument on options out of range.
  explicit TargetTracker(TargetTrackerOptions options = {});

  // Learns the colour of what `box` holds and starts tracking it. On an error nothing changes
  // (a running track keeps running). The box must lie wholly in the frame: clip it before.
  std::optional<TrackerError> start(const cv::Mat& bgr, cv::Rect box, double stamp_s);
  // Follows the target into this frame. Idle and lost trackers ignore frames. A frame of another
  // size than at start loses the target (its pixel coordinates would mean something else), and so
  // does a gap between frames longer than lost_after_s.
  TrackState update(const cv::Mat& bgr, double stamp_s);
  void stop();

  const TrackState& state() const { return state_; }
  const TargetTrackerOptions& options() const { return options_; }

 private:
  struct Measurement {
    cv::RotatedRect window;
    double mass_fraction = 0.0;
    bool accepted = false;
  };

  void predict(double dt_s);
  Measurement measure(const cv::Mat& back_projection, cv::Point2d predicted) const;
  double gate_px() const;
  void accept(const Measurement& measurement, double dt_s);
  void coast(double mass_fraction);
  void lose(double stamp_s);
  void publish_filter_state();

  TargetTrackerOptions options_;
  cv::Mat hue_histogram_;
  cv::KalmanFilter kalman_;
  cv::Size frame_size_;
  cv::Size2d nominal_size_px_;
  double reference_mass_ = 0.0;
  double last_seen_s_ = 0.0;
  TrackState state_;
};

}  // namespace mobot::vision
