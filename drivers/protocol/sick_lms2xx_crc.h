#pragma once

#include <cstdint>
#include <span>

namespace mobot::protocol::sick {

// The CRC-16 an LMS 200/211/291 puts behind every telegram, over the bytes from STX through the
// last payload byte: generator 0x8005, start value 0, and each step shifts the register once and
// XORs in the current byte together with the one before it (current in the low byte). That last
// part makes it none of the textbook CRC-16 variants, so a generic CRC routine does not fit. On the
// wire it follows the payload low byte first.
std::uint16_t crc16(std::span<const std::uint8_t> bytes);

}  // namespace mobot::protocol::sick
