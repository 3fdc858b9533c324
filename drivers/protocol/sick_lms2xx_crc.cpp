#include "drivers/protocol/sick_lms2xx_crc.h"

namespace mobot::protocol::sick {

std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  constexpr std::uint16_t kGenerator = 0x8005;
  std::uint16_t crc = 0;
  std::uint16_t previous = 0;
  for (const std::uint8_t byte : bytes) {
    const bool carry = (crc & 0x8000U) != 0;
    crc = static_cast<std::uint16_t>(crc << 1U);
    if (carry) crc = static_cast<std::uint16_t>(crc ^ kGenerator);
    crc = static_cast<std::uint16_t>(crc ^ (byte | (previous << 8U)));
    previous = byte;
  }
  return crc;
}

}  // namespace mobot::protocol::sick
