#include "core/estimation/particle_filter/pose_bins.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace mobot::estimation {

int theta_bin_count(const PoseBinSize& size) {
  return std::max(1, static_cast<int>(std::ceil(2.0 * std::numbers::pi / size.theta_rad - 1e-9)));
}

PoseBin pose_bin(const geometry::Pose2D& pose, const PoseBinSize& size) {
  const int theta_bins = theta_bin_count(size);
  const double heading = geometry::wrap_angle(pose.theta) + std::numbers::pi;  // (0, 2 pi]
  const int theta = static_cast<int>(std::floor(heading / size.theta_rad)) % theta_bins;
  return {static_cast<std::int32_t>(std::floor(pose.x / size.xy_m)),
          static_cast<std::int32_t>(std::floor(pose.y / size.xy_m)),
          static_cast<std::int32_t>(theta)};
}

std::uint64_t bin_key(const PoseBin& bin) {
  constexpr std::uint64_t kMask24 = (std::uint64_t{1} << 24) - 1;
  const auto x = static_cast<std::uint64_t>(static_cast<std::int64_t>(bin.x)) & kMask24;
  const auto y = static_cast<std::uint64_t>(static_cast<std::int64_t>(bin.y)) & kMask24;
  const auto theta = static_cast<std::uint64_t>(bin.theta) & 0xFFFF;
  return (x << 40) | (y << 16) | theta;
}

std::size_t count_occupied_bins(std::span<const WeightedPose> particles, const PoseBinSize& size) {
  std::vector<std::uint64_t> keys;
  keys.reserve(particles.size());
  for (const WeightedPose& particle : particles)
    keys.push_back(bin_key(pose_bin(particle.pose, size)));
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

}  // namespace mobot::estimation
