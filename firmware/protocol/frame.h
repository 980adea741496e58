// The serial link's framing, shared by the firmware (ATmega2560) and the host tools: the same
// bytes on both sides, so everything here is plain integer code (no struct copies, no
// allocation, nothing that blocks). docs/telemetry.md describes the protocol for host authors.
//
//   0xA5 | version | type | seq | len | payload[len] | crc_lo | crc_hi
//
// The CRC (CRC-16/CCITT-FALSE) covers version to the end of the payload: the sync byte is
// fixed, so it adds nothing to the check.
#pragma once

#include <stdint.h>
#ifdef __AVR__
#include <util/crc16.h>
#endif

namespace wmra {
namespace protocol {

constexpr uint8_t kSync = 0xA5;
constexpr uint8_t kVersion = 3;  // 3: the boot frame's identity, the info frame (a payload's layout changed)
constexpr uint8_t kMaxPayload = 64;
constexpr uint8_t kHeaderBytes = 5;  // sync, version, type, seq, len
constexpr uint8_t kFrameOverhead = kHeaderBytes + 2;
constexpr uint8_t kMaxFrameBytes = kMaxPayload + kFrameOverhead;
constexpr uint16_t kCrcInit = 0xFFFF;

// One byte of CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor),
// table-free: the polynomial's three taps folded into shifts of the byte's top nibble. On the
// AVR, avr-libc's _crc_xmodem_update is the same step (XMODEM differs only in its initial
// value, which is the caller's) in 20 cycles of asm, a third of what avr-gcc makes of the C;
// every simulator test decodes the firmware's frames with the C version, so they must agree.
__attribute__((always_inline)) inline uint16_t crc16_update(uint16_t crc, uint8_t byte) {
#ifdef __AVR__
  return _crc_xmodem_update(crc, byte);
#else
  uint8_t x = (uint8_t)((crc >> 8) ^ byte);
  x ^= (uint8_t)(x >> 4);
  return (uint16_t)((uint16_t)(crc << 8) ^ (uint16_t)((uint16_t)x << 12) ^ (uint16_t)((uint16_t)x << 5) ^ x);
#endif
}

// The CRC of n bytes, continuing from crc.
#ifdef __AVR__
__attribute__((noinline))
#endif
inline uint16_t crc16_update(uint16_t crc, const uint8_t* data, uint8_t n) {
  for (; n > 0; --n) crc = crc16_update(crc, *data++);
  return crc;
}

// Writes a whole frame into out (room for len + kFrameOverhead bytes) and returns its size;
// 0, writing nothing, when len is beyond kMaxPayload (no receiver would accept it). A payload
// already in place (at out + kHeaderBytes: write_message) is not copied.
inline uint8_t write_frame(uint8_t type, uint8_t seq, const uint8_t* payload, uint8_t len, uint8_t* out) {
  if (len > kMaxPayload) return 0;
  out[0] = kSync;
  out[1] = kVersion;
  out[2] = type;
  out[3] = seq;
  out[4] = len;
  if (payload != out + kHeaderBytes) {
    for (uint8_t i = 0; i < len; ++i) out[kHeaderBytes + i] = payload[i];
  }
  const uint16_t crc = crc16_update(kCrcInit, out + 1, (uint8_t)(kHeaderBytes - 1 + len));
  out[kHeaderBytes + len] = (uint8_t)crc;
  out[kHeaderBytes + len + 1] = (uint8_t)(crc >> 8);
  return (uint8_t)(len + kFrameOverhead);
}

struct Frame {
  uint8_t type, seq, len;
  uint8_t payload[kMaxPayload];
};

}  // namespace protocol
}  // namespace wmra
