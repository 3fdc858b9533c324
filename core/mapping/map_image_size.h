#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace mobot::mapping {

// The pixel dimensions a map image declares in its header.
struct MapImageSize {
  std::uint64_t width = 0;
  std::uint64_t height = 0;

  std::uint64_t pixels() const { return width * height; }
};

// Reads the size from a PNG's IHDR chunk or a PGM's header (binary P5 or plain P2, comments
// allowed, read as OpenCV reads them), without decoding: a decoder allocates the whole image before
// it finds out that the data is missing, so a few hundred bytes that declare a huge image must be
// refused first.
// nullopt: neither a PNG nor a PGM header. Each dimension is capped at 2^31 (no PNG or PGM decoder
// takes more), so pixels() cannot overflow.
std::optional<MapImageSize> read_map_image_size(std::span<const std::uint8_t> image_bytes);

}  // namespace mobot::mapping
