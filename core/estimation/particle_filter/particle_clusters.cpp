#include "core/estimation/particle_filter/particle_clusters.h"

#include <algorithm>
#include <unordered_map>

namespace mobot::estimation {

std::vector<ParticleCluster> cluster_particles(std::span<const WeightedPose> particles,
                                               const PoseBinSize& size) {
  if (particles.empty()) return {};
  const int theta_bins = theta_bin_count(size);
  // Bin of each particle, and one entry per occupied bin.
  std::vector<PoseBin> bins;
  std::vector<std::size_t> bin_of_particle(particles.size());
  std::unordered_map<std::uint64_t, std::size_t> bin_index;
  bin_index.reserve(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const PoseBin bin = pose_bin(particles[i].pose, size);
    const auto [it, inserted] = bin_index.try_emplace(bin_key(bin), bins.size());
    if (inserted) bins.push_back(bin);
    bin_of_particle[i] = it->second;
  }
  // Flood fill over touching bins.
  constexpr std::size_t kUnlabelled = static_cast<std::size_t>(-1);
  std::vector<std::size_t> label(bins.size(), kUnlabelled);
  std::size_t clusters = 0;
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < bins.size(); ++seed) {
    if (label[seed] != kUnlabelled) continue;
    label[seed] = clusters;
    stack.push_back(seed);
    while (!stack.empty()) {
      const PoseBin bin = bins[stack.back()];
      stack.pop_back();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dt = -1; dt <= 1; ++dt) {
            const PoseBin next{bin.x + dx, bin.y + dy, (bin.theta + dt + theta_bins) % theta_bins};
            const auto it = bin_index.find(bin_key(next));
            if (it == bin_index.end() || label[it->second] != kUnlabelled) continue;
            label[it->second] = clusters;
            stack.push_back(it->second);
          }
        }
      }
    }
    ++clusters;
  }
  std::vector<std::vector<WeightedPose>> members(clusters);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    members[label[bin_of_particle[i]]].push_back(particles[i]);
  }
  std::vector<ParticleCluster> out;
  out.reserve(clusters);
  for (const auto& cluster : members) {
    out.push_back({cluster.size(), weighted_pose_moments(cluster)});
  }
  std::stable_sort(out.begin(), out.end(), [](const ParticleCluster& a, const ParticleCluster& b) {
    return a.moments.weight > b.moments.weight;
  });
  return out;
}

}  // namespace mobot::estimation
