// Host side of the serial protocol (firmware/protocol): frames out of a byte stream with the
// counts a host reports, the names of the firmware's codes, and each frame as one JSON line.
// Shared by wmra-telemetry and armsim's FirmwareTelemetry.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "protocol/messages.h"
#include "protocol/parser.h"

namespace wmra {
namespace telemetry {

// Names of codes and of the set bits of bit fields; a value no table names reads "unknown_N"
// (codes) or "bit_N" (bits), so that a newer firmware still decodes.
std::string state_name(uint8_t state);   // core::ArmState
std::string mode_name(uint8_t mode);     // config::Mode
std::string calibration_name(uint8_t calibration);
std::string status_name(uint8_t status);  // protocol::ReplyStatus
std::vector<std::string> fault_names(uint32_t faults);         // core::FaultBit
std::vector<std::string> reset_cause_names(uint8_t mcusr);     // power_on, external, brown_out, watchdog, jtag, inferred
std::vector<std::string> slow_reason_names(uint8_t slowed_by);  // core::SlowReason
std::vector<std::string> switch_names(uint16_t switches);       // j1_low, j1_high, ..., j6_zero
// the JSON name of a frame type: state, reply, boot, or the command's name (stop, mode, ...);
// nullptr for a type the protocol does not define
const char* type_name(uint8_t type);
inline bool is_command(uint8_t type) { return type >= (uint8_t)protocol::MsgType::cmd_stop; }

// The frames of a byte stream, as protocol::Parser finds them, and the gaps in the firmware's
// sequence numbers: a state, reply or boot frame whose seq is not one more than the previous
// one's (a boot frame starts the count again: the firmware reset), and the frames missing in
// them (a gap from 4 to 7 is 2). Host commands carry the host's numbers and are left out of it.
// As the parser's: stream.push(byte); while (stream.next()) use(stream.frame());
class FrameStream {
 public:
  void push(uint8_t byte) { parser_.push(byte); }  // once next() has returned false
  bool next();  // true when the bytes pushed completed a frame: frame() holds it
  const protocol::Frame& frame() const { return parser_.frame(); }
  const protocol::Parser& parser() const { return parser_; }
  uint64_t frames() const { return frames_; }
  uint64_t seq_gaps() const { return seq_gaps_; }
  uint64_t missing_frames() const { return missing_frames_; }  // by number (256 or more in one gap read as fewer)
  // "frames N, crc errors N, framing errors N, skipped bytes N, seq gaps N"
  std::string summary() const;

 private:
  protocol::Parser parser_;
  uint64_t frames_ = 0, seq_gaps_ = 0, missing_frames_ = 0;
  int last_seq_ = -1;  // -1: no firmware frame yet
};

// One line of JSON (no newline): {"type":"state","seq":12,"t_ms":1020,...}. Every frame gets
// "type" and "seq"; a frame whose payload does not fit its type adds "error" (the
// check_command status, or "bad_length") and its payload in hex.
std::string to_json(const protocol::Frame& frame);

std::string to_hex(const uint8_t* bytes, size_t n);  // lowercase, no spaces
std::string version_text(const protocol::Identity& id);  // "major.minor.patch"

}  // namespace telemetry
}  // namespace wmra
