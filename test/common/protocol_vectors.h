// Fixed messages and a fixed byte stream for the serial protocol (firmware/protocol), and the
// text of what the encoder, parser and decoder make of them. Compiled into an AVR image and
// into a host test, which compare the text byte for byte: the firmware's frames must be the
// very bytes the host tools decode.
#pragma once

#include <stdint.h>

#include "kinematics_vectors.h"
#include "protocol/messages.h"
#include "protocol/parser.h"

namespace wmra {
namespace protocol_vectors {

using namespace protocol;
using vectors::hex;

inline StateMsg sample_state() {
  StateMsg s = {};
  s.t_ms = 0x89ABCDEFu;
  s.state = 6;
  s.mode = 3;
  s.faults = 0x80030009u;
  s.slowed_by = 6;
  s.reset_cause = 9;
  s.switches = 0x0421;
  for (uint8_t j = 0; j < 6; ++j) {
    s.q_mrad[j] = (int16_t)(-32768L + 13107L * j);  // long: int is 16 bits on the AVR
    s.qd_mrad_s[j] = (int16_t)(1000 - 401 * j);
  }
  s.p_0p1mm[0] = 10770;
  s.p_0p1mm[1] = -1;
  s.p_0p1mm[2] = -32768;
  s.stick_permille[0] = -1000;
  s.stick_permille[1] = 1000;
  s.speed_scale_pct = 55;
  s.loop_cycles_max = 0xFEDC;
  s.rx_crc_errors = 0x0102;
  s.rx_framing_errors = 0xFFFF;
  s.rx_rejected = 7;
  s.rx_overruns = 0x1234;
  return s;
}

template <class Put>
void bytes_line(Put& put, char tag, const uint8_t* bytes, uint8_t n) {
  put(tag);
  for (uint8_t i = 0; i < n; ++i) hex(put, bytes[i], 2);
  put('\n');
}

// an Io for a message's fields(): each field in hex, as wide as its type
template <class Put>
struct PrintFields {
  Put& put;
  template <class T>
  void operator()(const T& v) {
    put(' ');
    hex(put, (uint32_t)v, (uint8_t)(2 * sizeof(T)));
  }
};

template <class Msg, class Put>
void fields_line(Put& put, char tag, const Msg& m) {
  put(tag);
  PrintFields<Put> print{put};
  Msg::fields(print, m);
  put('\n');
}

// the message's frame through the parser and decode: true when it came back
template <class Msg>
bool round_trip(Parser& parser, const Msg& m, Msg& back) {
  uint8_t frame[kMaxFrameBytes];
  const uint8_t n = write_message(m, 1, frame);
  bool decoded = false;
  for (uint8_t i = 0; i < n; ++i) {
    parser.push(frame[i]);
    while (parser.next()) decoded = decode(parser.frame(), back);
  }
  return decoded;
}

// garbage, frames good and bad, and a frame with a byte lost, in one stream
constexpr uint8_t kStream[] = {
    0x00, 0xA5, 0x01, 0xA5, 0xA5,                    // noise, a wrong version (1), a stray sync
    0xA5, 0x03, 0x12, 0x07, 0x01, 0x05, 0x00, 0x00,  // mode 5: CRC below is wrong
    0xA5, 0x03, 0x01, 0x00, 0x41,                    // length 65
    0xA5, 0x03, 0x10, 0x00, 0x00, 0x7F, 0x5C,        // stop, seq 0
    0xA5, 0x03, 0x13, 0x09, 0x01, 0x65, 0x06,        // speed 101, its CRC's high byte lost
    0xA5, 0x03, 0x11, 0x0A, 0x00, 0x84, 0x84,        // rearm, seq 10
    0xFF,
};

// Lines: C the CRC check value; S R B V K whole frames of each message; P every frame the
// parser finds in kStream (type, seq, len, check_command status, payload), then its counters;
// D the fields of each message decoded back from its frame.
template <class Put>
void emit_all(Put& put) {
  uint16_t crc = kCrcInit;
  for (uint8_t c = '1'; c <= '9'; ++c) crc = crc16_update(crc, c);
  put('C');
  hex(put, crc, 4);
  put('\n');

  const StateMsg state = sample_state();
  const ReplyMsg reply = {(uint8_t)MsgType::cmd_velocity, 0xFE, (uint8_t)ReplyStatus::refused};
  const BootMsg boot = {0x08, (uint8_t)Calibration::defaults_bad_crc, {{0, 7, 1}, {0x85, 0xe4, 0xee, 0x73, 0xd9, 0x0a}, 1, 0x12345678}};
  const VelocityCmd velocity = {{150, -150, -32768}, {800, -800, 32767}};
  uint8_t frame[kMaxFrameBytes];
  bytes_line(put, 'S', frame, write_message(state, 0xFF, frame));
  bytes_line(put, 'R', frame, write_message(reply, 0x00, frame));
  bytes_line(put, 'B', frame, write_message(boot, 0x80, frame));
  bytes_line(put, 'V', frame, write_message(velocity, 0x7F, frame));
  const CalibrationMsg calibration = {{100, -200, 300}, {16000, -32768, 32767}, {1, 2, -3}, 0x05};
  bytes_line(put, 'K', frame, write_message(calibration, 0x42, frame));

  Parser parser;
  for (uint8_t b : kStream) {
    parser.push(b);
    while (parser.next()) {
      const Frame& f = parser.frame();
      put('P');
      hex(put, f.type, 2);
      hex(put, f.seq, 2);
      hex(put, f.len, 2);
      hex(put, (uint8_t)check_command(f), 1);
      bytes_line(put, ' ', f.payload, f.len);
    }
  }
  put('P');
  hex(put, parser.crc_errors(), 4);
  hex(put, parser.framing_errors(), 4);
  hex(put, parser.skipped_bytes(), 4);
  put('\n');

  // each message back from its own frame
  StateMsg state_back = {};
  ReplyMsg reply_back = {};
  BootMsg boot_back = {};
  VelocityCmd velocity_back = {};
  const uint8_t decoded = (uint8_t)(round_trip(parser, state, state_back) + round_trip(parser, reply, reply_back) +
                                    round_trip(parser, boot, boot_back) + round_trip(parser, velocity, velocity_back));
  put('D');
  hex(put, decoded, 1);
  put('\n');
  fields_line(put, 'D', state_back);
  fields_line(put, 'D', reply_back);
  fields_line(put, 'D', boot_back);
  fields_line(put, 'D', velocity_back);
}

}  // namespace protocol_vectors
}  // namespace wmra
