#include "drivers/sim/camera_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace mobot::sim {
namespace {

constexpr double kMinGain = 0.3;
constexpr double kMaxGain = 2.0;

const CameraNoiseOptions& checked(const CameraNoiseOptions& options) {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("camera noise: " + what);
  };
  require(std::isfinite(options.gain_sigma) && options.gain_sigma >= 0.0,
          "gain_sigma must be finite and >= 0");
  require(std::isfinite(options.gain_tau_s) && options.gain_tau_s > 0.0,
          "gain_tau_s must be finite and > 0");
  require(std::isfinite(options.pixel_sigma) && options.pixel_sigma >= 0.0,
          "pixel_sigma must be finite and >= 0");
  require(std::isfinite(options.blur_sigma_px) && options.blur_sigma_px >= 0.0,
          "blur_sigma_px must be finite and >= 0");
  return options;
}

// SplitMix64 (Steele, Lea, Flood 2014): a std::normal_distribution per pixel would cost more than
// rendering the frame.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

// The standard normal quantile at probability p in (0, 1), by bisection: built once per camera.
double normal_quantile(double p) {
  double low = -10.0;
  double high = 10.0;
  for (int i = 0; i < 80; ++i) {
    const double middle = 0.5 * (low + high);
    (0.5 * std::erfc(-middle / std::numbers::sqrt2) < p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

// Quantiles at the centres of 256 equal slices of probability, rescaled to exactly the wanted
// standard deviation (the cut-off tails would otherwise make it a little narrower).
std::array<float, 256> quantile_table(double sigma) {
  std::array<double, 256> quantiles{};
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < quantiles.size(); ++i) {
    quantiles[i] = normal_quantile((static_cast<double>(i) + 0.5) / 256.0);
    sum_sq += quantiles[i] * quantiles[i];
  }
  const double scale = sigma / std::sqrt(sum_sq / 256.0);
  std::array<float, 256> table{};
  for (std::size_t i = 0; i < table.size(); ++i)
    table[i] = static_cast<float>(scale * quantiles[i]);
  return table;
}

void add_gain_and_noise(cv::Mat& image, double gain, const std::array<float, 256>& half_noise,
                        std::uint64_t seed) {
  std::array<float, 256> gained{};
  for (std::size_t level = 0; level < gained.size(); ++level) {
    gained[level] = static_cast<float>(gain * static_cast<double>(level) + 0.5);
  }
  const auto noisy = [&](std::uint8_t level, std::uint64_t bits) {
    const float value = gained[level] + half_noise[bits & 0xff] + half_noise[(bits >> 8) & 0xff];
    return static_cast<std::uint8_t>(std::clamp(value, 0.0f, 255.0f));
  };
  SplitMix64 random(seed);
  const int values_per_row = image.cols * image.channels();
  for (int row = 0; row < image.rows; ++row) {
    auto* level = image.ptr<std::uint8_t>(row);
    int i = 0;
    // 16 random bits per value, four values per draw.
    for (; i + 3 < values_per_row; i += 4) {
      const std::uint64_t bits = random.next();
      level[i] = noisy(level[i], bits);
      level[i + 1] = noisy(level[i + 1], bits >> 16);
      level[i + 2] = noisy(level[i + 2], bits >> 32);
      level[i + 3] = noisy(level[i + 3], bits >> 48);
    }
    for (; i < values_per_row; ++i) level[i] = noisy(level[i], random.next());
  }
}

}  // namespace

CameraNoise::CameraNoise(CameraNoiseOptions options)
    : options_(checked(options)),
      gain_drift_(options.gain_sigma, options.gain_tau_s),
      half_noise_(quantile_table(options.pixel_sigma / std::numbers::sqrt2)) {}

CameraNoise CameraNoise::none() { return CameraNoise(CameraNoiseOptions{0.0, 1.0, 0.0, 0.0}); }

void CameraNoise::start(std::mt19937_64& rng) { gain_drift_.start(rng); }

void CameraNoise::advance(double dt_s, std::mt19937_64& rng) { gain_drift_.advance(dt_s, rng); }

double CameraNoise::gain() const {
  return std::clamp(1.0 + gain_drift_.value(), kMinGain, kMaxGain);
}

void CameraNoise::apply(cv::Mat& image, std::mt19937_64& rng) const {
  if (image.type() != CV_8UC3) {
    throw std::invalid_argument("camera noise: the image must be CV_8UC3");
  }
  const std::uint64_t seed = rng();
  if (options_.blur_sigma_px > 0.0) {
    cv::GaussianBlur(image, image, cv::Size(), options_.blur_sigma_px);
  }
  const double gain = this->gain();
  if (gain == 1.0 && options_.pixel_sigma == 0.0) return;
  add_gain_and_noise(image, gain, half_noise_, seed);
}

}  // namespace mobot::sim
