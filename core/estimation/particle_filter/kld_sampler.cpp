#include "core/estimation/particle_filter/kld_sampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::estimation {

std::size_t kld_particle_count(std::size_t occupied_bins, const KldSamplerOptions& options) {
  if (occupied_bins <= 1) return options.min_particles;
  const double k1 = static_cast<double>(occupied_bins - 1);
  const double a = 2.0 / (9.0 * k1);
  const double x = 1.0 - a + std::sqrt(a) * options.z_quantile;
  const double n = std::ceil(k1 / (2.0 * options.epsilon) * x * x * x);
  if (!(n < static_cast<double>(options.max_particles))) return options.max_particles;
  return std::max(options.min_particles, static_cast<std::size_t>(n));
}

KldSampler::KldSampler(const KldSamplerOptions& options) : options_(options) {
  if (!(options.epsilon > 0.0) || !std::isfinite(options.epsilon) ||
      !std::isfinite(options.z_quantile) || !(options.bins.xy_m > 0.0) ||
      !std::isfinite(options.bins.xy_m) || !(options.bins.theta_rad > 0.0) ||
      !std::isfinite(options.bins.theta_rad) || options.min_particles == 0 ||
      options.min_particles > options.max_particles) {
    throw std::invalid_argument("KLD sampler: option out of range");
  }
}

std::vector<WeightedPose> KldSampler::resample(std::span<const WeightedPose> particles,
                                               double random_fraction,
                                               const RandomPoseFn& random_pose,
                                               std::mt19937_64& rng, double random_weight) const {
  if (particles.empty()) return {};
  std::vector<double> cumulative(particles.size());
  double total = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double w = particles[i].weight;
    total += (w > 0.0 && std::isfinite(w)) ? w : 0.0;
    cumulative[i] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    for (std::size_t i = 0; i < particles.size(); ++i) cumulative[i] = static_cast<double>(i + 1);
    total = static_cast<double>(particles.size());
  }
  for (double& c : cumulative) c /= total;
  const double fraction =
      random_pose && std::isfinite(random_fraction) ? std::clamp(random_fraction, 0.0, 1.0) : 0.0;

  const double injected_weight =
      random_weight > 0.0 && random_weight < 1.0 ? random_weight : 1.0;  // NaN: 1
  std::size_t count = options_.min_particles;
  std::vector<WeightedPose> drawn =
      draw(particles, cumulative, count, fraction, random_pose, rng, injected_weight);
  // At most one round per doubling between the limits, in practice two or three.
  for (int round = 0; round < 16; ++round) {
    const std::size_t needed =
        kld_particle_count(count_occupied_bins(drawn, options_.bins), options_);
    if (needed <= count) break;
    count = needed;
    drawn = draw(particles, cumulative, count, fraction, random_pose, rng, injected_weight);
  }
  return drawn;
}

std::vector<WeightedPose> KldSampler::draw(std::span<const WeightedPose> particles,
                                           std::span<const double> cumulative, std::size_t count,
                                           double random_fraction, const RandomPoseFn& random_pose,
                                           std::mt19937_64& rng, double random_weight) const {
  std::vector<WeightedPose> out;
  out.reserve(count);
  const double step = 1.0 / static_cast<double>(count);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Probabilistic Robotics Table 4.4: one random offset, then a comb of spacing 1/n.
  const double offset = unit(rng) * step;
  std::size_t i = 0;
  for (std::size_t m = 0; m < count; ++m) {
    if (random_fraction > 0.0 && unit(rng) < random_fraction) {
      out.push_back({random_pose(rng), random_weight});
      continue;
    }
    const double u = offset + static_cast<double>(m) * step;
    while (i + 1 < particles.size() && cumulative[i] < u) ++i;
    out.push_back({particles[i].pose, 1.0});
  }
  double total = 0.0;
  for (const WeightedPose& p : out) total += p.weight;
  for (WeightedPose& p : out) p.weight /= total;
  return out;
}

}  // namespace mobot::estimation
