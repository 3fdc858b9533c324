#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace mobot::vision {

// One detected bearing paired with one predicted (a known landmark's bearing from the pose
// estimate). innovation_rad = detected - predicted, wrapped into (-pi, pi].
struct BearingMatch {
  std::size_t detected_index = 0;
  std::size_t predicted_index = 0;
  double innovation_rad = 0.0;
};

// Greedy nearest-neighbour data association for bearings: the closest pair within gate_rad first,
// then the closest of the rest, so no detection and no prediction is used twice. The result is
// in that order (smallest |innovation| first). Non-finite bearings match nothing; a non-finite or
// negative gate matches nothing.
std::vector<BearingMatch> match_bearings(std::span<const double> detected_rad,
                                         std::span<const double> predicted_rad, double gate_rad);

}  // namespace mobot::vision
