#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mobot::msgs {

// One camera frame, rows top to bottom, pixels packed as the encoding says.
struct Image {
  double stamp_s = 0.0;
  int width = 0;
  int height = 0;
  std::string encoding = "bgr8";  // bgr8 | mono8 | jpeg (data is the compressed file)
  int jpeg_quality = 0;           // jpeg: the quality it was compressed with, 1..100 (0: unknown)
  std::vector<std::uint8_t> data;
};

}  // namespace mobot::msgs
