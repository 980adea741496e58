// The serial link's receiver (frame.h's frames out of a byte stream), shared by the firmware
// and the host tools. docs/telemetry.md ("Receiving") says the same for host authors.
//
// The bytes from a candidate frame's sync on are held in a buffer of one frame's size. A
// candidate that fails (a wrong version, a len over kMaxPayload, a CRC error, or cut short by a
// gap of kByteGap_ms) is dropped and counted, and its bytes after the sync are looked at again:
// the hunt for a sync resumes at the byte after the failed one. A valid frame whose bytes were
// taken as the tail of a broken one is found that way (a sender that dies mid-frame costs only
// its own frame), and so is one whose first bytes were taken as a broken one's last.
//
//   parser.push(byte);  // a reader without a budget (a host): only when caught_up(), which
//   while (parser.next()) use(parser.frame());  // it is once next() has returned false
//
// A reader that knows the line's timing tells the parser when it has been quiet (line_quiet()).
// A reader with a budget (the firmware, link.cpp) counts steps: feed() a byte read from the
// line while caught_up(), step() otherwise. Each looks at one byte, a new one or one held
// again (the bytes before the next sync in one step), so a rescan of up to kMaxFrameBytes - 1
// held bytes is spread over as many steps and the line's bytes wait in the reader's buffer
// meanwhile. Nothing allocates, nothing blocks; the counters saturate at 0xFFFF rather than
// wrap, so a flood never reads as a few errors.
#pragma once

#include <stdint.h>

#include "protocol/frame.h"

namespace wmra {
namespace protocol {

// A frame's bytes come back to back: a partial frame after this long without a byte is dropped
// so that a sender that dies mid-frame cannot make the next sender's frames its tail.
constexpr uint8_t kByteGap_ms = 3;

class Parser {
 public:
  // every byte given has been looked at: push() or feed() may take the next
  bool caught_up() const { return (uint8_t)(first_ + scan_) == held_; }
  // bytes held: a partial frame, or bytes to look at again
  bool holding() const { return held_ != first_; }

  // A byte from the line, only when caught_up() (the buffer then holds at most a partial frame,
  // kMaxFrameBytes - 1 bytes, and room for this one): true when it is held for a step to look
  // at, false when it was skipped here (hunting, nothing held, a byte that is no sync).
  bool push(uint8_t byte) {
    if (held_ == first_) {  // nothing held: a candidate begins at the front, with a sync
      if (byte != kSync) {
        count(skipped_bytes_);
        return false;
      }
      first_ = held_ = stale_ = 0;
    } else if (held_ == kMaxFrameBytes) {
      to_front();
    }
    buf_.bytes[held_++] = byte;
    return true;
  }

  // push() and its step in one, only when caught_up(): true when the byte completed a valid
  // frame, which frame() holds until the next push or step
  bool feed(uint8_t byte) { return push(byte) && look(byte); }

  // Looks at the next byte held, only when !caught_up(): true when it completed a valid frame.
  // Hunting, it first skips the bytes held up to the next sync, a few cycles each (one step:
  // they were looked at as a failed candidate's, each in a step of its own).
  bool step() {
    if (scan_ == 0) {
      hunt();
      if (first_ == held_) return false;
    }
    return look(buf_.bytes[first_ + scan_]);
  }

  // Steps until a frame is complete (true: frame() holds it) or every byte held has been
  // looked at (false)
  bool next() {
    while (!caught_up()) {
      if (step()) return true;
    }
    return false;
  }

  // The line has brought no byte for quiet_ms: a reader that knows the line's timing says so
  // while caught_up() with nothing waiting to be read (otherwise it is ignored: a byte not
  // looked at yet may be the one a partial frame waits for). At kByteGap_ms or more a partial
  // frame is dropped as cut short and its bytes after the sync are looked at again; every
  // candidate among them that reaches the gap is cut short too.
  void line_quiet(uint8_t quiet_ms) {
    if (!caught_up() || scan_ == 0 || quiet_ms < kByteGap_ms) return;
    stale_ = held_;
    fail(framing_errors_);
  }

  const Frame& frame() const { return buf_.view.frame; }
  uint16_t crc_errors() const { return crc_errors_; }          // frames whose CRC did not match
  uint16_t framing_errors() const { return framing_errors_; }  // wrong version, len > kMaxPayload, cut short
  uint16_t skipped_bytes() const { return skipped_bytes_; }    // bytes in no frame (a failed one's sync aside)

 private:
  static void count(uint16_t& counter) {
    if (counter != 0xFFFF) ++counter;
  }
  // The bytes held from first_ on to the buffer's front, when a frame found away from it is to
  // be read as one (frame()) or the buffer is full: each byte moves at most once for a
  // candidate, which has had a step for it.
  void to_front() {
    const uint8_t n = (uint8_t)(held_ - first_);
    for (uint8_t i = 0; i < n; ++i) buf_.bytes[i] = buf_.bytes[first_ + i];
    stale_ = stale_ > first_ ? (uint8_t)(stale_ - first_) : 0;
    held_ = n;
    first_ = 0;
  }
  // the bytes held before the next sync are skipped
  void hunt() {
    uint8_t n = 0;
    while (first_ + n < held_ && buf_.bytes[first_ + n] != kSync) ++n;
    skipped_bytes_ = (uint16_t)(0xFFFF - skipped_bytes_ < n ? 0xFFFF : skipped_bytes_ + n);
    first_ = (uint8_t)(first_ + n);
  }
  // the candidate is no frame: the hunt resumes at the byte after its sync
  void fail(uint16_t& counter) {
    count(counter);
    ++first_;
    scan_ = 0;
  }

  // the next byte of the candidate at first_ (its sync at scan_ 0)
  bool look(uint8_t byte) {
    const uint8_t at = scan_++;
    bool complete = false;
    if (at == 0) {
      // a sync: hunt() stops at one, and push() holds one first
    } else if (at == 1) {
      if (byte == kVersion) {
        crc_ = crc16_update(kCrcInit, byte);
      } else if (byte == kSync) {
        count(skipped_bytes_);  // the sync before was a stray byte; this one may begin a frame
        ++first_;
        scan_ = 0;
      } else {
        fail(framing_errors_);
      }
    } else if (at < kHeaderBytes) {
      if (at == 4 && byte > kMaxPayload) {
        fail(framing_errors_);
      } else {
        crc_at_ = (uint8_t)(kHeaderBytes + byte);  // (at 4: the len)
        crc_ = crc16_update(crc_, byte);
      }
    } else if (at < crc_at_) {
      crc_ = crc16_update(crc_, byte);
    } else if (at == crc_at_) {
      crc_ ^= byte;  // the low byte becomes 0 when it matches; the high one checks the rest
    } else if (crc_ == (uint16_t)((uint16_t)byte << 8)) {
      if (first_ != 0) to_front();  // frame() reads it from the front
      first_ = scan_;               // the hunt goes on after it
      scan_ = 0;
      complete = true;
    } else {
      fail(crc_errors_);
    }
    // a candidate that began before a gap and has reached it was cut short
    if (stale_ != 0 && scan_ != 0 && (uint8_t)(first_ + scan_) == stale_) fail(framing_errors_);
    return complete;
  }

  // (the small fields first: on the AVR each is then a load at a short offset from the parser;
  // behind the buffer each took an address computed apart, 16 cycles a byte of a valid frame
  // more in the firmware: armsim --profile, a flood of frames)
  uint8_t first_ = 0;  // where the candidate (or the hunt) begins in the buffer
  uint8_t held_ = 0;   // bytes held in the buffer (those before first_ are done with)
  uint8_t scan_ = 0;   // bytes of the candidate looked at: 0 while hunting
  uint8_t stale_ = 0;  // the bytes before this index came before a gap of kByteGap_ms (0: none)
  uint8_t crc_at_ = 0;  // the candidate's CRC's place in it (kHeaderBytes + its len)
  uint16_t crc_ = 0;
  uint16_t crc_errors_ = 0, framing_errors_ = 0, skipped_bytes_ = 0;
  // A frame found is at the buffer's front: its fields are the bytes after the sync and the
  // version, read in place (no copy a byte, no second frame's worth of RAM). The AVR and the
  // host compilers (GCC) define reading a union's other member; Frame is bytes only.
  union Buffer {
    uint8_t bytes[kMaxFrameBytes];
    struct {
      uint8_t sync, version;
      Frame frame;
    } view;
  } buf_ = {};
  static_assert(sizeof(Buffer) == kMaxFrameBytes && sizeof(Frame) == kMaxFrameBytes - 4, "a frame's bytes, the view inside them");
};

}  // namespace protocol
}  // namespace wmra
