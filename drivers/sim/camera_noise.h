#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <random>

#include "drivers/sim/gauss_markov.h"

namespace mobot::sim {

struct CameraNoiseOptions {
  // The scene's brightness drifts (clouds, lamps, auto-exposure hunting): a gain of 1 plus a
  // Gauss-Markov process of this stationary standard deviation and correlation time.
  double gain_sigma = 0.06;
  double gain_tau_s = 8.0;
  // Sensor noise per pixel and channel, in grey levels (0..255).
  double pixel_sigma = 3.0;
  // Gaussian blur of the optics, in pixels; 0 = sharp.
  double blur_sigma_px = 0.0;
};

// Everything between a perfect rendering and what a camera delivers. Multiplicative gain and
// zero-mean noise on all three channels alike keep a saturated colour's hue, which is what a
// CamShift tracker and the landmark detector key on.
class CameraNoise {
 public:
  // Throws std::invalid_argument naming the option when one is negative or non-finite, or
  // gain_tau_s is not > 0.
  explicit CameraNoise(CameraNoiseOptions options = {});
  // No gain drift, no noise, no blur.
  static CameraNoise none();

  // Draws the gain from its stationary distribution (a camera switched on at a random moment).
  void start(std::mt19937_64& rng);
  // Lets the gain drift for dt_s.
  void advance(double dt_s, std::mt19937_64& rng);
  // Clamped so a long drift never turns the picture black or negative.
  double gain() const;

  // Blur, gain and noise applied in place to a CV_8UC3 image. Takes one draw from rng (the seed of
  // a fast generator for the per-pixel noise), so the stream's use does not grow with image size.
  void apply(cv::Mat& image, std::mt19937_64& rng) const;

  const CameraNoiseOptions& options() const { return options_; }

 private:
  CameraNoiseOptions options_;
  GaussMarkov gain_drift_;
  // The pixel noise is the sum of two of these, each picked by 8 random bits: the 256 quantiles of
  // a gaussian of standard deviation pixel_sigma / sqrt(2). Drawing std::normal_distribution per
  // pixel would cost more than rendering the frame.
  std::array<float, 256> half_noise_{};
};

}  // namespace mobot::sim
