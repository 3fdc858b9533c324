#include "core/mapping/map_image_size.h"

#include <algorithm>
#include <array>

namespace mobot::mapping {
namespace {

constexpr std::uint64_t kMaxDimension = std::uint64_t{1} << 31;

// PNG (ISO/IEC 15948 5.2, 11.2.2): the signature, then the IHDR chunk's length (13) and type, then
// its width and height as big-endian 32-bit numbers.
constexpr std::array<std::uint8_t, 8> kPngSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
constexpr std::array<std::uint8_t, 8> kIhdrChunkStart{0, 0, 0, 13, 'I', 'H', 'D', 'R'};

std::uint64_t big_endian_32(std::span<const std::uint8_t> bytes) {
  return (std::uint64_t{bytes[0]} << 24) | (std::uint64_t{bytes[1]} << 16) |
         (std::uint64_t{bytes[2]} << 8) | std::uint64_t{bytes[3]};
}

std::optional<MapImageSize> png_size(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 24 || !std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin()) ||
      !std::equal(kIhdrChunkStart.begin(), kIhdrChunkStart.end(), bytes.begin() + 8)) {
    return std::nullopt;
  }
  return MapImageSize{std::min(big_endian_32(bytes.subspan(16, 4)), kMaxDimension),
                      std::min(big_endian_32(bytes.subspan(20, 4)), kMaxDimension)};
}

bool is_pnm_space(std::uint8_t byte) {
  return byte == ' ' || byte == '\t' || byte == '\n' || byte == '\v' || byte == '\f' ||
         byte == '\r';
}

// The header's numbers as OpenCV's PxM decoder reads them (grfmt_pxm.cpp, ReadNumber), which is
// what must agree with the size checked here: whitespace and comments ('#' to the end of the line,
// the line end included) before each number, and the byte that ends a number is consumed with it.
class PgmHeaderReader {
 public:
  explicit PgmHeaderReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  std::optional<std::uint64_t> number() {
    std::optional<std::uint8_t> byte = next();
    while (byte && !is_digit(*byte)) {
      if (*byte == '#') {
        do {
          byte = next();
        } while (byte && *byte != '\n' && *byte != '\r');
        if (byte) byte = next();
      } else if (is_pnm_space(*byte)) {
        byte = next();
      } else {
        return std::nullopt;
      }
    }
    if (!byte) return std::nullopt;
    std::uint64_t value = 0;
    while (byte && is_digit(*byte)) {
      value = std::min(value * 10 + (*byte - '0'), kMaxDimension);
      byte = next();
    }
    return value;
  }

 private:
  static bool is_digit(std::uint8_t byte) { return byte >= '0' && byte <= '9'; }

  std::optional<std::uint8_t> next() {
    if (at_ == bytes_.size()) return std::nullopt;
    return bytes_[at_++];
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 2;  // after the magic number
};

// "P5" or "P2" and a whitespace byte: the signature OpenCV decodes as a PGM.
std::optional<MapImageSize> pgm_size(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 3 || bytes[0] != 'P' || (bytes[1] != '5' && bytes[1] != '2') ||
      !is_pnm_space(bytes[2])) {
    return std::nullopt;
  }
  PgmHeaderReader reader(bytes);
  const auto width = reader.number();
  const auto height = reader.number();
  if (!width || !height) return std::nullopt;
  return MapImageSize{*width, *height};
}

}  // namespace

std::optional<MapImageSize> read_map_image_size(std::span<const std::uint8_t> image_bytes) {
  if (auto size = png_size(image_bytes)) return size;
  return pgm_size(image_bytes);
}

}  // namespace mobot::mapping
