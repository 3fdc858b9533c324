#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::mapping {

// An image that is not a map: undecodable, empty or too large.
class MapImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ROS map_server's "trinary" interpretation of a map image.
struct MapImageOptions {
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
};

// Decodes a PGM or PNG image held in memory (colour is averaged to grey, as map_server does).
// Pixel p = (255 - v) / 255 (v / 255 when negated): p > occupied_thresh -> occupied,
// p < free_thresh -> free, otherwise unknown. Image row 0 is the top of the map; grid row 0 is
// the bottom. Other formats, and images whose header declares more than max_cells pixels, are
// refused before anything is decoded (MapImageError).
OccupancyGrid decode_map_image(std::span<const std::uint8_t> image_bytes, double resolution_m,
                               const geometry::Pose2D& origin, const MapImageOptions& options,
                               std::size_t max_cells);

// Converts grid cells to map_saver's pixel values: occupied 0, free 254, unknown 205.
std::vector<std::uint8_t> map_image_pixels(const OccupancyGrid& grid);
std::vector<std::uint8_t> encode_map_pgm(const OccupancyGrid& grid);
std::vector<std::uint8_t> encode_map_png(const OccupancyGrid& grid);
// The map_server YAML that goes with encode_map_pgm's image, naming it `image_file`.
std::string encode_map_yaml(const OccupancyGrid& grid, const std::string& image_file);

}  // namespace mobot::mapping
