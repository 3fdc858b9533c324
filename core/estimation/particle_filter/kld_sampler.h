#pragma once

#include <cstddef>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "core/estimation/particle_filter/pose_bins.h"
#include "core/estimation/weighted_pose.h"

namespace mobot::estimation {

struct KldSamplerOptions {
  // Fox's bound: with probability given by z_quantile, the KL divergence between the sampled
  // and the true belief stays below epsilon (the task's kld_err 0.05).
  double epsilon = 0.05;
  // The upper standard normal quantile z_(1-delta), taken as given as AMCL takes its kld_z
  // (0.99 is the quantile itself, not a probability to invert).
  double z_quantile = 0.99;
  // The histogram: AMCL's 0.5 m x 0.5 m x 10 deg.
  PoseBinSize bins;
  // The Dashgo thesis' AMCL limits.
  std::size_t min_particles = 2000;
  std::size_t max_particles = 5000;
};

// Fox (2003), "Adapting the sample size in particle filters through KLD-sampling": the particles
// needed when the samples fall in k bins,
//   n = ceil((k - 1) / (2 epsilon) * (1 - 2 / (9 (k - 1)) + sqrt(2 / (9 (k - 1))) z)^3),
// clamped to [min_particles, max_particles]; k <= 1 needs min_particles.
std::size_t kld_particle_count(std::size_t occupied_bins, const KldSamplerOptions& options);

// Draws a random pose (the augmented-MCL injection: uniform over the map's free space).
using RandomPoseFn = std::function<geometry::Pose2D(std::mt19937_64&)>;

// docs/algorithms.md E4: KLD-adaptive resampling with a low-variance (systematic) draw. AMCL draws
// one multinomial sample at a time until the bins it fills ask for no more; a systematic draw
// needs its size first, so the size is the fixed point of n = kld_particle_count(bins of a draw of
// n), starting from min_particles (the count only grows, so a few rounds reach it).
class KldSampler {
 public:
  // Throws std::invalid_argument for epsilon or bin sizes not positive, a non-finite
  // z_quantile, min_particles 0 or above max_particles.
  explicit KldSampler(const KldSamplerOptions& options = {});

  const KldSamplerOptions& options() const { return options_; }

  // The new set. Each drawn slot is replaced, with probability random_fraction (clamped to
  // [0, 1]; ignored without random_pose), by random_pose(rng). The drawn particles weigh 1, the
  // random ones random_weight (clamped to (0, 1]; the importance weight of a pose drawn from the
  // free space rather than the motion), all normalised to sum 1. Weights that do not sum to a
  // positive finite number are taken as uniform; no particles give no particles.
  std::vector<WeightedPose> resample(std::span<const WeightedPose> particles,
                                     double random_fraction, const RandomPoseFn& random_pose,
                                     std::mt19937_64& rng, double random_weight = 1.0) const;

 private:
  std::vector<WeightedPose> draw(std::span<const WeightedPose> particles,
                                 std::span<const double> cumulative, std::size_t count,
                                 double random_fraction, const RandomPoseFn& random_pose,
                                 std::mt19937_64& rng, double random_weight) const;

  KldSamplerOptions options_;
};

}  // namespace mobot::estimation
