#pragma once

namespace mobot::drivers::modbus {

// The Modbus RTU frames of one read, as the bus and its schedule count them.
// A request: slave, function, address (2), quantity (2), CRC (2).
inline constexpr int kRequestBytes = 8;
// A reply: slave, function, byte count, data, CRC (2); one register, or one byte of bits.
inline constexpr int kRegisterReplyBytes = 5 + 2;
inline constexpr int kBitsReplyBytes = 5 + 1;
// An exception reply: slave, function | 0x80, exception code, CRC (2).
inline constexpr int kExceptionReplyBytes = 5;

}  // namespace mobot::drivers::modbus
