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
constexpr uint8_t kVersion = 2;  // 2: the state frame's rx_overruns (a payload's layout changed)
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

// The CRC of n bytes, continuing from crc. On the AVR one copy, at -O2 whatever the caller's
// level: built for size, the step was a call per byte (its 24 cycles came to ~60).
#ifdef __AVR__
__attribute__((noinline, optimize("O2")))
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

// Byte-fed receiver: one call per byte (from a UART ISR's buffer or a host read), constant
// time, no allocation. Outside a frame it hunts for kSync; a frame whose header or CRC is
// wrong is dropped and counted, and the hunt goes on from the byte that failed, which may
// itself be the next frame's sync (a byte lost inside one frame then costs only that frame).
// The counters saturate at 0xFFFF rather than wrap, so a flood never reads as a few errors.
class Parser {
 public:
  // true when this byte completed a valid frame: frame() holds it until the next feed
  bool feed(uint8_t byte) {
    switch (step_) {
      case Step::hunt:
        if (byte == kSync) {
          step_ = Step::version;
        } else {
          count(skipped_bytes_);
        }
        return false;
      case Step::version:
        if (byte == kSync) {  // the sync before was a stray byte; this one may start a frame
          count(skipped_bytes_);
        } else if (byte != kVersion) {
          reject(framing_errors_, byte);
        } else {
          crc_ = crc16_update(kCrcInit, byte);
          step_ = Step::type;
        }
        return false;
      case Step::type:
        frame_.type = byte;
        return take(byte, Step::seq);
      case Step::seq:
        frame_.seq = byte;
        return take(byte, Step::len);
      case Step::len:
        if (byte > kMaxPayload) {
          reject(framing_errors_, byte);
          return false;
        }
        frame_.len = byte;
        at_ = 0;
        return take(byte, byte ? Step::payload : Step::crc_lo);
      case Step::payload:
        frame_.payload[at_++] = byte;
        return take(byte, at_ == frame_.len ? Step::crc_lo : Step::payload);
      case Step::crc_lo:
        crc_ ^= byte;  // the low byte becomes 0 when it matches; crc_hi checks the rest
        step_ = Step::crc_hi;
        return false;
      case Step::crc_hi:
        if (crc_ == (uint16_t)((uint16_t)byte << 8)) {
          step_ = Step::hunt;
          return true;
        }
        reject(crc_errors_, byte);
        return false;
    }
    return false;
  }

  const Frame& frame() const { return frame_; }
  uint16_t crc_errors() const { return crc_errors_; }          // frames whose CRC did not match
  uint16_t framing_errors() const { return framing_errors_; }  // wrong version, len > kMaxPayload
  uint16_t skipped_bytes() const { return skipped_bytes_; }    // bytes outside any frame

 private:
  enum class Step : uint8_t { hunt, version, type, seq, len, payload, crc_lo, crc_hi };

  static void count(uint16_t& counter) {
    if (counter != 0xFFFF) ++counter;
  }
  // a byte inside the CRC: fold it in, move on
  bool take(uint8_t byte, Step next) {
    crc_ = crc16_update(crc_, byte);
    step_ = next;
    return false;
  }
  void reject(uint16_t& counter, uint8_t byte) {
    count(counter);
    step_ = byte == kSync ? Step::version : Step::hunt;
  }

  Frame frame_ = {};
  Step step_ = Step::hunt;
  uint8_t at_ = 0;
  uint16_t crc_ = 0;
  uint16_t crc_errors_ = 0, framing_errors_ = 0, skipped_bytes_ = 0;
};

}  // namespace protocol
}  // namespace wmra
