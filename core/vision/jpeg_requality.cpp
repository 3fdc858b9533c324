#include "core/vision/jpeg_requality.h"

#include <opencv2/imgcodecs.hpp>

namespace mobot::vision {

std::optional<std::vector<std::uint8_t>> requality_jpeg(std::span<const std::uint8_t> jpeg,
                                                        int quality) {
  if (quality < 1 || quality > 100 || jpeg.empty()) return std::nullopt;
  try {
    // cv::Mat has no constructor for read-only data; imdecode only reads it.
    const cv::Mat file(1, static_cast<int>(jpeg.size()), CV_8UC1,
                       const_cast<std::uint8_t*>(jpeg.data()));
    const cv::Mat pixels = cv::imdecode(file, cv::IMREAD_UNCHANGED);
    if (pixels.empty()) return std::nullopt;
    std::vector<std::uint8_t> out;
    if (!cv::imencode(".jpg", pixels, out, {cv::IMWRITE_JPEG_QUALITY, quality})) {
      return std::nullopt;
    }
    return out;
  } catch (const cv::Exception&) {
    return std::nullopt;
  }
}

}  // namespace mobot::vision
