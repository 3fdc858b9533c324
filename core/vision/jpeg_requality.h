#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace mobot::vision {

// A JPEG file compressed again at `quality` (1..100), for a client whose link is thinner than the
// camera's own quality assumes. nullopt when `jpeg` does not decode or the quality is out of range.
std::optional<std::vector<std::uint8_t>> requality_jpeg(std::span<const std::uint8_t> jpeg,
                                                        int quality);

}  // namespace mobot::vision
