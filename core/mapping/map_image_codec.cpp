#include "core/mapping/map_image_codec.h"

#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/mapping/map_image_size.h"

namespace mobot::mapping {
namespace {

constexpr std::uint8_t kOccupiedPixel = 0;
constexpr std::uint8_t kFreePixel = 254;
constexpr std::uint8_t kUnknownPixel = 205;

cv::Mat decode_grey(std::span<const std::uint8_t> image_bytes) {
  if (image_bytes.empty()) throw MapImageError("the image is empty");
  const cv::Mat encoded(1, static_cast<int>(image_bytes.size()), CV_8UC1,
                        const_cast<std::uint8_t*>(image_bytes.data()));
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(encoded, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& error) {
    // OpenCV throws on some malformed headers (a side over its 2^20 pixels, say) instead of
    // returning an empty image.
    throw MapImageError(std::string("the image cannot be decoded: ") + error.err);
  }
  if (decoded.empty())
    throw MapImageError("the image is neither a PGM nor a PNG that can be decoded");
  if (decoded.depth() == CV_16U) decoded.convertTo(decoded, CV_8U, 1.0 / 257.0);
  if (decoded.depth() != CV_8U) throw MapImageError("the image must have 8 or 16 bits per channel");
  cv::Mat grey;
  switch (decoded.channels()) {
    case 1:
      grey = decoded;
      break;
    case 3:
    case 4: {
      // map_server averages the colour channels (alpha ignored) rather than weighting them.
      std::vector<cv::Mat> channels;
      cv::split(decoded, channels);
      cv::Mat sum;
      channels[0].convertTo(sum, CV_32F);
      cv::accumulate(channels[1], sum);
      cv::accumulate(channels[2], sum);
      sum.convertTo(grey, CV_8U, 1.0 / 3.0);
      break;
    }
    default:
      throw MapImageError("the image has an unsupported number of channels");
  }
  return grey;
}

void check_cells(std::uint64_t cells, std::size_t max_cells) {
  if (cells > max_cells) {
    throw MapImageError("the image has " + std::to_string(cells) + " pixels; the limit is " +
                        std::to_string(max_cells));
  }
}

std::uint8_t classify(std::uint8_t pixel, const MapImageOptions& options) {
  const double value = options.negate ? pixel : 255 - pixel;
  const double p = value / 255.0;
  if (p > options.occupied_thresh) return OccupancyGrid::kOccupied;
  if (p < options.free_thresh) return OccupancyGrid::kFree;
  return OccupancyGrid::kUnknown;
}

cv::Mat pixels_top_row_first(const OccupancyGrid& grid) {
  const std::vector<std::uint8_t> pixels = map_image_pixels(grid);
  cv::Mat image(grid.height(), grid.width(), CV_8UC1);
  for (int row = 0; row < grid.height(); ++row) {
    const auto* source = pixels.data() + static_cast<std::size_t>(grid.height() - 1 - row) *
                                             static_cast<std::size_t>(grid.width());
    std::copy(source, source + grid.width(), image.ptr<std::uint8_t>(row));
  }
  return image;
}

std::vector<std::uint8_t> encode(const OccupancyGrid& grid, const std::string& extension) {
  if (grid.width() == 0 || grid.height() == 0) throw MapImageError("the map is empty");
  std::vector<std::uint8_t> out;
  if (!cv::imencode(extension, pixels_top_row_first(grid), out)) {
    throw MapImageError("cannot encode the map as " + extension);
  }
  return out;
}

}  // namespace

OccupancyGrid decode_map_image(std::span<const std::uint8_t> image_bytes, double resolution_m,
                               const geometry::Pose2D& origin, const MapImageOptions& options,
                               std::size_t max_cells) {
  if (!(resolution_m > 0.0)) throw MapImageError("the resolution must be positive");
  if (image_bytes.empty()) throw MapImageError("the image is empty");
  // Only the two formats a map comes in reach OpenCV (not its TIFF, JPEG 2000 or EXR decoders),
  // and only at a size the server can hold: a decoder allocates what the header declares.
  const std::optional<MapImageSize> declared = read_map_image_size(image_bytes);
  if (!declared) throw MapImageError("the image is neither a PGM nor a PNG");
  check_cells(declared->pixels(), max_cells);
  const cv::Mat grey = decode_grey(image_bytes);
  check_cells(static_cast<std::uint64_t>(grey.rows) * static_cast<std::uint64_t>(grey.cols),
              max_cells);
  OccupancyGrid grid(grey.cols, grey.rows, resolution_m, origin);
  for (int row = 0; row < grey.rows; ++row) {
    const auto* pixels = grey.ptr<std::uint8_t>(row);
    const int grid_row = grey.rows - 1 - row;
    for (int col = 0; col < grey.cols; ++col)
      grid.set({col, grid_row}, classify(pixels[col], options));
  }
  return grid;
}

std::vector<std::uint8_t> map_image_pixels(const OccupancyGrid& grid) {
  std::vector<std::uint8_t> pixels(grid.cells().size());
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const std::uint8_t cell = grid.cells()[i];
    if (cell == OccupancyGrid::kUnknown) {
      pixels[i] = kUnknownPixel;
    } else if (cell >= OccupancyGrid::kOccupiedThreshold) {
      pixels[i] = kOccupiedPixel;
    } else if (cell <= 25) {  // map_saver's free threshold
      pixels[i] = kFreePixel;
    } else {
      pixels[i] = kUnknownPixel;
    }
  }
  return pixels;
}

std::vector<std::uint8_t> encode_map_pgm(const OccupancyGrid& grid) { return encode(grid, ".pgm"); }

std::vector<std::uint8_t> encode_map_png(const OccupancyGrid& grid) { return encode(grid, ".png"); }

std::string encode_map_yaml(const OccupancyGrid& grid, const std::string& image_file) {
  char text[512];
  std::snprintf(text, sizeof text,
                "image: %s\nresolution: %.9g\norigin: [%.9g, %.9g, %.9g]\nnegate: 0\n"
                "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n",
                image_file.c_str(), grid.resolution_m(), grid.origin().x, grid.origin().y,
                grid.origin().theta);
  return text;
}

}  // namespace mobot::mapping
