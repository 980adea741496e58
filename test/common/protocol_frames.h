// Whole frames of the serial protocol (firmware/protocol) as byte vectors, for host tests.
#pragma once

#include <vector>

#include "protocol/messages.h"

namespace wmra {
namespace protocol_frames {

inline std::vector<uint8_t> frame_bytes(uint8_t type, uint8_t seq, const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> out(payload.size() + protocol::kFrameOverhead);
  out.resize(protocol::write_frame(type, seq, payload.data(), (uint8_t)payload.size(), out.data()));
  return out;
}

template <class Msg>
std::vector<uint8_t> message_bytes(const Msg& m, uint8_t seq) {
  std::vector<uint8_t> out(protocol::kMaxFrameBytes);
  out.resize(protocol::write_message(m, seq, out.data()));
  return out;
}

}  // namespace protocol_frames
}  // namespace wmra
