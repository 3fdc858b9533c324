#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/estimation/particle_filter/pose_bins.h"
#include "core/estimation/particle_filter/pose_moments.h"
#include "core/estimation/weighted_pose.h"

namespace mobot::estimation {

// One hypothesis of the particle cloud.
struct ParticleCluster {
  std::size_t count = 0;  // particles in it
  PoseMoments moments;    // moments.weight: the weight it carries
};

// docs/algorithms.md E4: AMCL's pf_kdtree_cluster. Particles are binned (x, y, heading); bins
// that touch, the 26 around each in (x, y, heading) with the heading wrapping at +-pi, form one
// cluster. Sorted by weight, heaviest first; empty for no particles.
std::vector<ParticleCluster> cluster_particles(std::span<const WeightedPose> particles,
                                               const PoseBinSize& size);

}  // namespace mobot::estimation
