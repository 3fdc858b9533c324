#include "core/vision/bearing_match.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/pose2d.h"

namespace mobot::vision {

std::vector<BearingMatch> match_bearings(std::span<const double> detected_rad,
                                         std::span<const double> predicted_rad, double gate_rad) {
  std::vector<BearingMatch> pairs;
  if (!std::isfinite(gate_rad) || gate_rad < 0.0) return pairs;
  for (std::size_t d = 0; d < detected_rad.size(); ++d) {
    for (std::size_t p = 0; p < predicted_rad.size(); ++p) {
      const double innovation = geometry::wrap_angle(detected_rad[d] - predicted_rad[p]);
      // NaN fails the comparison and drops out here.
      if (std::abs(innovation) <= gate_rad) pairs.push_back({d, p, innovation});
    }
  }
  // Ties broken by index so the result does not depend on the sort's whims.
  std::sort(pairs.begin(), pairs.end(), [](const BearingMatch& a, const BearingMatch& b) {
    const double ea = std::abs(a.innovation_rad);
    const double eb = std::abs(b.innovation_rad);
    if (ea != eb) return ea < eb;
    if (a.detected_index != b.detected_index) return a.detected_index < b.detected_index;
    return a.predicted_index < b.predicted_index;
  });
  std::vector<bool> detected_used(detected_rad.size(), false);
  std::vector<bool> predicted_used(predicted_rad.size(), false);
  std::vector<BearingMatch> matches;
  for (const BearingMatch& pair : pairs) {
    if (detected_used[pair.detected_index] || predicted_used[pair.predicted_index]) continue;
    detected_used[pair.detected_index] = true;
    predicted_used[pair.predicted_index] = true;
    matches.push_back(pair);
  }
  return matches;
}

}  // namespace mobot::vision
