#pragma once

#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// One hypothesis of a sampled belief: a particle of the particle filter (docs/algorithms.md E4),
// or a pose drawn from any belief for display. Weights of a set sum to 1 once normalised.
struct WeightedPose {
  geometry::Pose2D pose;
  double weight = 0.0;
};

}  // namespace mobot::estimation
