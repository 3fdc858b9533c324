// libFuzzer target: map images as an import sends them (core/mapping/map_image_codec:
// decode_map_image, PGM or PNG bytes -> occupancy grid; OpenCV's decoders behind it are not
// instrumented, but their crashes and allocations are seen). Beyond not crashing: a map comes out
// with the size its header declares, within the cell limit, or the decoder says MapImageError;
// nothing of the image's declared size is allocated before that limit is checked (libFuzzer's
// -malloc_limit_mb, which is -rss_limit_mb by default, catches it).
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/mapping/map_image_codec.h"
#include "core/mapping/map_image_size.h"

namespace {

void check(bool condition) {
  if (!condition) __builtin_trap();
}

// api/rest_maps.cpp's kMaxMapCells: what an import may hold.
constexpr std::size_t kImportMaxCells = 25'000'000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using namespace mobot::mapping;
  // The first byte picks the options; the rest is the image.
  MapImageOptions options;
  options.negate = (data[0] & 1U) != 0;
  options.occupied_thresh = 0.5 + 0.5 * ((data[0] >> 1) & 7U) / 7.0;
  options.free_thresh = 0.4 * ((data[0] >> 4) & 7U) / 7.0;
  const std::span<const std::uint8_t> image(data + 1, size - 1);
  try {
    const OccupancyGrid grid = decode_map_image(image, 0.05, {}, options, kImportMaxCells);
    const auto declared = read_map_image_size(image);
    check(declared.has_value());
    check(static_cast<std::uint64_t>(grid.width()) == declared->width);
    check(static_cast<std::uint64_t>(grid.height()) == declared->height);
    check(grid.cells().size() <= kImportMaxCells);
    for (const std::uint8_t cell : grid.cells()) {
      check(cell == OccupancyGrid::kFree || cell == OccupancyGrid::kOccupied ||
            cell == OccupancyGrid::kUnknown);
    }
  } catch (const MapImageError&) {
  }
  return 0;
}
