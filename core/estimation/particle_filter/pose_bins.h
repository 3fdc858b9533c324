#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <span>

#include "core/estimation/weighted_pose.h"
#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// The histogram the particle filter measures its belief with (AMCL's kd-tree leaves): KLD
// sampling counts the occupied bins, clustering joins neighbouring ones.
struct PoseBinSize {
  double xy_m = 0.5;
  double theta_rad = 10.0 * std::numbers::pi / 180.0;
};

struct PoseBin {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t theta = 0;  // 0 .. theta_bins - 1, from -pi; heading bins wrap around

  bool operator==(const PoseBin&) const = default;
};

// The number of heading bins (the last one is narrower when theta_rad does not divide 2 pi).
int theta_bin_count(const PoseBinSize& size);
// The bin of a finite pose; a bin size that is not positive and finite is a programming error.
PoseBin pose_bin(const geometry::Pose2D& pose, const PoseBinSize& size);
// A key that orders and hashes bins (x and y are kept to 24 bits each: +-8 million bins).
std::uint64_t bin_key(const PoseBin& bin);
// How many distinct bins the poses fall in (the k of KLD sampling).
std::size_t count_occupied_bins(std::span<const WeightedPose> particles, const PoseBinSize& size);

}  // namespace mobot::estimation
