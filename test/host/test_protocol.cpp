// firmware/protocol: the CRC against its published check value and the textbook bitwise
// definition, the wire layout of every message (the offsets docs/telemetry.md gives), and the
// parser against split, corrupted, truncated and random input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "protocol/messages.h"
#include "protocol/parser.h"
#include "protocol_frames.h"
#include "protocol_vectors.h"

using namespace wmra::protocol;
using wmra::protocol_frames::frame_bytes;
using wmra::protocol_frames::message_bytes;
using wmra::protocol_vectors::sample_state;  // every field set, negative ones too

namespace {

// CRC-16/CCITT-FALSE as its definition reads: MSB first, one bit at a time
uint16_t crc_bitwise_update(uint16_t crc, uint8_t byte) {
  crc ^= (uint16_t)(byte << 8);
  for (int b = 0; b < 8; ++b) crc = (uint16_t)(crc & 0x8000 ? (crc << 1) ^ 0x1021 : crc << 1);
  return crc;
}
uint16_t crc_bitwise(const uint8_t* bytes, size_t n) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < n; ++i) crc = crc_bitwise_update(crc, bytes[i]);
  return crc;
}

// feeds bytes back to back; returns every frame completed
std::vector<Frame> feed_all(Parser& p, const std::vector<uint8_t>& bytes) {
  std::vector<Frame> frames;
  for (uint8_t b : bytes) {
    p.push(b);
    while (p.next()) frames.push_back(p.frame());
  }
  return frames;
}

// the line quiet for ms since its last byte: every frame the parser then finds in what it holds
std::vector<Frame> silence(Parser& p, uint8_t ms) {
  p.line_quiet(ms);
  std::vector<Frame> frames;
  while (p.next()) frames.push_back(p.frame());
  return frames;
}

std::vector<uint8_t> cat(std::vector<std::vector<uint8_t>> parts) {
  std::vector<uint8_t> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

uint16_t le16(const uint8_t* p) { return (uint16_t)(p[0] | p[1] << 8); }

}  // namespace

TEST(Crc, CheckValueAndBitwiseDefinition) {
  const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  uint16_t crc = kCrcInit;
  for (uint8_t b : check) crc = crc16_update(crc, b);
  EXPECT_EQ(crc, 0x29B1);
  EXPECT_EQ(crc_bitwise(check, sizeof check), 0x29B1);
  // every byte from every 16th register value: the nibble form is the bitwise one
  for (uint32_t reg = 0; reg <= 0xFFFF; reg += 16) {
    for (uint32_t b = 0; b < 256; ++b) {
      ASSERT_EQ(crc16_update((uint16_t)reg, (uint8_t)b), crc_bitwise_update((uint16_t)reg, (uint8_t)b)) << reg << " " << b;
    }
  }
}

TEST(Frame, LayoutAndCrcLittleEndian) {
  const std::vector<uint8_t> f = frame_bytes(0x12, 7, {0x01});
  ASSERT_EQ(f.size(), 8u);
  EXPECT_EQ(f[0], 0xA5);
  EXPECT_EQ(f[1], 3);  // kVersion: 3 since the boot frame's identity and the info frame
  EXPECT_EQ(f[2], 0x12);
  EXPECT_EQ(f[3], 7);
  EXPECT_EQ(f[4], 1);
  EXPECT_EQ(f[5], 0x01);
  EXPECT_EQ(le16(&f[6]), crc_bitwise(&f[1], 5));  // not over the sync byte
  EXPECT_EQ(frame_bytes(0x10, 0, {}).size(), 7u);

  std::vector<uint8_t> big(kMaxPayload + 1, 0x55), out(kMaxPayload + 1 + kFrameOverhead, 0xEE);
  EXPECT_EQ(write_frame(1, 0, big.data(), kMaxPayload + 1, out.data()), 0);
  EXPECT_EQ(out[0], 0xEE);  // nothing written
  EXPECT_EQ(write_frame(1, 0, big.data(), kMaxPayload, out.data()), kMaxFrameBytes);
}

TEST(Messages, StateOffsetsAsDocumented) {
  EXPECT_EQ(kStatePayloadBytes, 59);
  uint8_t p[kMaxPayload];
  ASSERT_EQ(encode(sample_state(), p), kStatePayloadBytes);
  EXPECT_EQ(p[0], 0xEF);  // t_ms 0x89abcdef, little-endian
  EXPECT_EQ(p[3], 0x89);
  EXPECT_EQ(p[4], 6);     // state
  EXPECT_EQ(p[5], 3);     // mode
  EXPECT_EQ(p[6], 0x09);  // faults 0x80030009
  EXPECT_EQ(p[9], 0x80);
  EXPECT_EQ(p[10], 6);    // slowed_by
  EXPECT_EQ(p[11], 9);    // reset_cause
  EXPECT_EQ(le16(p + 12), 0x0421);          // switches
  EXPECT_EQ(le16(p + 14), 0x8000);          // q_mrad[0] = -32768
  EXPECT_EQ((int16_t)le16(p + 16), -19661);
  EXPECT_EQ(le16(p + 24), 32767);           // q_mrad[5]
  EXPECT_EQ((int16_t)le16(p + 26), 1000);   // qd_mrad_s[0]
  EXPECT_EQ((int16_t)le16(p + 36), -1005);  // qd_mrad_s[5]
  EXPECT_EQ((int16_t)le16(p + 38), 10770);  // p_0p1mm
  EXPECT_EQ((int16_t)le16(p + 40), -1);
  EXPECT_EQ((int16_t)le16(p + 42), -32768);
  EXPECT_EQ((int16_t)le16(p + 44), -1000);  // stick_permille
  EXPECT_EQ((int16_t)le16(p + 46), 1000);
  EXPECT_EQ(p[48], 55);                     // speed_scale_pct
  EXPECT_EQ(le16(p + 49), 0xFEDC);          // loop_cycles_max
  EXPECT_EQ(le16(p + 51), 0x0102);          // rx_crc_errors
  EXPECT_EQ(le16(p + 53), 0xFFFF);          // rx_framing_errors
  EXPECT_EQ(le16(p + 55), 7);               // rx_rejected
  EXPECT_EQ(le16(p + 57), 0x1234);          // rx_overruns
}

TEST(Messages, OtherPayloadsAsDocumented) {
  uint8_t p[kMaxPayload];
  ASSERT_EQ(encode(ReplyMsg{0x12, 9, 3}, p), 3);
  EXPECT_EQ(p[0], 0x12);
  EXPECT_EQ(p[1], 9);
  EXPECT_EQ(p[2], 3);
  ASSERT_EQ(encode(BootMsg{8, 2, Identity{{0, 7, 1}, {0x85, 0xe4, 0xee, 0x73, 0xd9, 0x0a}, 1, 0x12345678}}, p), 16);
  EXPECT_EQ(p[0], 8);
  EXPECT_EQ(p[1], 2);
  // the identity: version, commit, flags, the configuration's hash little-endian
  const uint8_t identity[14] = {0, 7, 1, 0x85, 0xe4, 0xee, 0x73, 0xd9, 0x0a, 1, 0x78, 0x56, 0x34, 0x12};
  for (int i = 0; i < 14; ++i) EXPECT_EQ(p[2 + i], identity[i]) << "byte " << 2 + i;
  InfoMsg info{};
  info.hand_speed_mm_s = 150;
  info.joint_speed_mrad_s[5] = 1500;
  info.soft_min_mrad[0] = -1518;
  info.soft_max_mrad[5] = 6231;
  info.loop_hz = 1000;
  ASSERT_EQ(encode(info, p), 56);
  EXPECT_EQ(p[14] | p[15] << 8, 150);        // after the identity's 14 bytes
  EXPECT_EQ(p[28] | p[29] << 8, 1500);       // joint_speed_mrad_s from 18
  EXPECT_EQ((int16_t)(p[30] | p[31] << 8), -1518);  // soft_min_mrad from 30
  EXPECT_EQ(p[52] | p[53] << 8, 6231);       // soft_max_mrad from 42
  EXPECT_EQ(p[54] | p[55] << 8, 1000);
  ASSERT_EQ(encode(VelocityCmd{{150, -150, 0}, {800, -1, 32767}}, p), 12);
  EXPECT_EQ(le16(p), 150);
  EXPECT_EQ((int16_t)le16(p + 2), -150);
  EXPECT_EQ(le16(p + 6), 800);
  EXPECT_EQ((int16_t)le16(p + 8), -1);
  EXPECT_EQ(le16(p + 10), 32767);
  ASSERT_EQ(encode(CalibrationMsg{{819, 800, 1}, {15564, 15000, 2}, {-1, 4000, 3}, 5}, p), 19);
  EXPECT_EQ(le16(p), 819);
  EXPECT_EQ(le16(p + 2), 800);
  EXPECT_EQ(le16(p + 6), 15564);  // at_max_counts_x16
  EXPECT_EQ((int16_t)le16(p + 12), -1);  // reading_counts_x16
  EXPECT_EQ(le16(p + 14), 4000);
  EXPECT_EQ(p[18], 5);  // from_command
  ASSERT_EQ(encode(PotCalibrationCmd{3, 1459, 15564}, p), 5);
  EXPECT_EQ(p[0], 3);
  EXPECT_EQ(le16(p + 1), 1459);
  EXPECT_EQ(le16(p + 3), 15564);
}

TEST(Messages, RoundTripThroughTheParser) {
  Parser parser;
  const StateMsg state = sample_state();
  const ReplyMsg reply{0x17, 200, 4};
  const BootMsg boot{0x0F, 3, {}};
  const VelocityCmd velocity{{-32768, 32767, 1}, {-800, 0, 5}};
  const auto frames = feed_all(parser, cat({message_bytes(state, 255), message_bytes(reply, 0), message_bytes(boot, 1),
                                           message_bytes(velocity, 2)}));
  ASSERT_EQ(frames.size(), 4u);
  StateMsg s;
  ReplyMsg r;
  BootMsg b;
  VelocityCmd v;
  ASSERT_TRUE(decode(frames[0], s));
  EXPECT_EQ(frames[0].seq, 255);
  EXPECT_EQ(s.t_ms, state.t_ms);
  EXPECT_EQ(s.state, state.state);
  EXPECT_EQ(s.mode, state.mode);
  EXPECT_EQ(s.faults, state.faults);
  EXPECT_EQ(s.slowed_by, state.slowed_by);
  EXPECT_EQ(s.reset_cause, state.reset_cause);
  EXPECT_EQ(s.switches, state.switches);
  EXPECT_TRUE(std::equal(s.q_mrad, s.q_mrad + 6, state.q_mrad));
  EXPECT_TRUE(std::equal(s.qd_mrad_s, s.qd_mrad_s + 6, state.qd_mrad_s));
  EXPECT_TRUE(std::equal(s.p_0p1mm, s.p_0p1mm + 3, state.p_0p1mm));
  EXPECT_TRUE(std::equal(s.stick_permille, s.stick_permille + 2, state.stick_permille));
  EXPECT_EQ(s.speed_scale_pct, state.speed_scale_pct);
  EXPECT_EQ(s.loop_cycles_max, state.loop_cycles_max);
  EXPECT_EQ(s.rx_crc_errors, state.rx_crc_errors);
  EXPECT_EQ(s.rx_framing_errors, state.rx_framing_errors);
  EXPECT_EQ(s.rx_rejected, state.rx_rejected);
  EXPECT_EQ(s.rx_overruns, state.rx_overruns);
  ASSERT_TRUE(decode(frames[1], r));
  EXPECT_EQ(r.command_type, 0x17);
  EXPECT_EQ(r.command_seq, 200);
  EXPECT_EQ(r.status, 4);
  ASSERT_TRUE(decode(frames[2], b));
  EXPECT_EQ(b.reset_cause, 0x0F);
  EXPECT_EQ(b.calibration, 3);
  ASSERT_TRUE(decode(frames[3], v));
  EXPECT_EQ(v.v_mm_s[0], -32768);
  EXPECT_EQ(v.v_mm_s[1], 32767);
  EXPECT_EQ(v.w_mrad_s[0], -800);
  EXPECT_EQ(v.w_mrad_s[2], 5);
  EXPECT_EQ(parser.crc_errors() + parser.framing_errors() + parser.skipped_bytes(), 0);
}

TEST(Messages, DecodeRefusesAnotherTypeOrLength) {
  Frame f{};
  f.type = (uint8_t)MsgType::reply;
  f.len = 3;
  BootMsg boot{7, 7, {}};
  EXPECT_FALSE(decode(f, boot));  // a reply is not a boot message
  EXPECT_EQ(boot.reset_cause, 7);  // untouched
  ReplyMsg reply;
  EXPECT_TRUE(decode(f, reply));
  f.len = 4;
  EXPECT_FALSE(decode(f, reply));
  f.type = (uint8_t)MsgType::state;
  f.len = kStatePayloadBytes - 1;
  StateMsg state;
  EXPECT_FALSE(decode(f, state));
}

TEST(Parser, FramesSplitAtEveryByteBoundary) {
  const auto a = message_bytes(sample_state(), 1);
  const auto b = frame_bytes((uint8_t)MsgType::cmd_stop, 2, {});
  const auto c = message_bytes(ReplyMsg{0x12, 3, 0}, 3);
  const auto stream = cat({a, b, c});
  for (size_t split = 0; split <= stream.size(); ++split) {
    Parser p;
    const auto first = feed_all(p, std::vector<uint8_t>(stream.begin(), stream.begin() + split));
    // only the frames wholly inside the first part are complete
    const size_t whole = (split >= a.size()) + (split >= a.size() + b.size()) + (split == stream.size());
    ASSERT_EQ(first.size(), whole) << split;
    auto frames = first;
    for (const Frame& f : feed_all(p, std::vector<uint8_t>(stream.begin() + split, stream.end()))) frames.push_back(f);
    ASSERT_EQ(frames.size(), 3u) << split;
    EXPECT_EQ(frames[0].type, (uint8_t)MsgType::state);
    EXPECT_EQ(frames[1].seq, 2);
    EXPECT_EQ(frames[2].len, 3);
    EXPECT_EQ(p.crc_errors() + p.framing_errors() + p.skipped_bytes(), 0) << split;
  }
}

TEST(Parser, EveryFlippedBitIsRejectedAndCounted) {
  const auto good = message_bytes(ReplyMsg{0x13, 4, 0}, 9);
  std::vector<uint8_t> tail;  // valid frames after it
  for (int i = 0; i < 12; ++i) tail = cat({tail, good});
  for (size_t bit = 0; bit < 8 * good.size(); ++bit) {
    auto bad = good;
    bad[bit / 8] ^= (uint8_t)(1u << (bit % 8));
    Parser p;
    EXPECT_TRUE(feed_all(p, bad).empty()) << bit;
    // A length made longer takes the tail's first frames as its own; when its CRC fails (or,
    // waiting still, the line falls silent) they are looked at again: none is lost.
    auto after = feed_all(p, tail);
    for (const Frame& f : silence(p, kByteGap_ms)) after.push_back(f);
    EXPECT_EQ(after.size(), 12u) << bit;
    EXPECT_GE(p.crc_errors() + p.framing_errors() + p.skipped_bytes(), 1) << bit;
    for (const Frame& f : after) {
      EXPECT_EQ(frame_bytes(f.type, f.seq, std::vector<uint8_t>(f.payload, f.payload + f.len)), good) << bit;
    }
  }
}

TEST(Parser, GarbageThenAValidFrame) {
  Parser p;
  // plain noise, a stray sync, a sync with a wrong version, a sync then a repeated sync
  const std::vector<uint8_t> garbage = {0x00, 0xFF, 0x13, 0xA5, 0x01, 0x77, 0xA5, 0xA5};
  const auto frames = feed_all(p, cat({garbage, message_bytes(BootMsg{1, 0, {}}, 0)}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, (uint8_t)MsgType::boot);
  EXPECT_EQ(p.skipped_bytes(), 7);   // 00 ff 13, 01 looked at again, 77, and the two syncs before the frame's own
  EXPECT_EQ(p.framing_errors(), 1);  // version 1
  EXPECT_EQ(p.crc_errors(), 0);
}

TEST(Parser, LengthBeyondMaxPayloadIsAFramingError) {
  Parser p;
  const std::vector<uint8_t> too_long = {0xA5, kVersion, 0x01, 0x00, kMaxPayload + 1};
  const auto frames = feed_all(p, cat({too_long, message_bytes(ReplyMsg{}, 1)}));
  EXPECT_EQ(p.framing_errors(), 1);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, (uint8_t)MsgType::reply);
  // a length of exactly kMaxPayload is fine
  Parser q;
  EXPECT_EQ(feed_all(q, frame_bytes(0x40, 0, std::vector<uint8_t>(kMaxPayload, 0xA5))).size(), 1u);
  EXPECT_EQ(q.framing_errors(), 0);
}

TEST(Parser, AByteLostCostsOnlyItsFrame) {
  // the lost byte makes the parser take the next frame's sync as the CRC's high byte: the
  // CRC fails and that sync starts the next frame
  auto a = message_bytes(sample_state(), 1);
  a.erase(a.begin() + 20);
  Parser p;
  const auto frames = feed_all(p, cat({a, message_bytes(sample_state(), 2)}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].seq, 2);
  EXPECT_EQ(p.crc_errors(), 1);
}

// The half frame (issue 30, finding 7): a host that dies mid-frame leaves a velocity
// command cut after 3 of its 12 payload bytes; the next host sends stop frames.
const std::vector<uint8_t> kHalfFrame = {0xA5, 0x03, 0x17, 0x05, 0x0C, 0x32, 0x00, 0x00};
std::vector<uint8_t> stop_frame(uint8_t seq) { return frame_bytes((uint8_t)MsgType::cmd_stop, seq, {}); }

TEST(Parser, HalfAFrameThenAGapThenStops) {
  Parser p;
  EXPECT_TRUE(feed_all(p, kHalfFrame).empty());
  EXPECT_TRUE(silence(p, kByteGap_ms - 1).empty());
  EXPECT_TRUE(p.holding()) << "a gap shorter than kByteGap_ms keeps the partial frame";
  EXPECT_TRUE(silence(p, kByteGap_ms).empty());
  EXPECT_FALSE(p.holding()) << "dropped after kByteGap_ms";
  EXPECT_EQ(p.framing_errors(), 1);  // cut short
  EXPECT_EQ(p.skipped_bytes(), 7);   // its bytes after the sync, looked at again
  const auto frames = feed_all(p, cat({stop_frame(0), stop_frame(1)}));
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].type, (uint8_t)MsgType::cmd_stop);
  EXPECT_EQ(frames[0].seq, 0);
  EXPECT_EQ(frames[1].seq, 1);
  EXPECT_EQ(p.crc_errors(), 0);
}

// No gap: the broken frame takes the stops' bytes as its tail. (The parser before the rescan
// found neither stop: the first was payload, the second's sync and version too, and the rest
// of it went to the hunt from the failed CRC's byte on.)
TEST(Parser, HalfAFrameThenStopsWithNoGap) {
  // two stops: the first and the second's sync and version complete its payload, the second's
  // type and seq its CRC, which fails: the rescan finds the first in the bytes held, and the
  // second once its last bytes come
  Parser p;
  const auto frames = feed_all(p, cat({kHalfFrame, stop_frame(0), stop_frame(1)}));
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].seq, 0);
  EXPECT_EQ(frames[1].seq, 1);
  EXPECT_EQ(p.crc_errors(), 1);
  EXPECT_EQ(p.framing_errors(), 0);
  EXPECT_EQ(p.skipped_bytes(), 7);
  EXPECT_FALSE(p.holding());
  // one stop: the broken frame still wants two bytes when the line falls silent; the stop is
  // found when the gap drops it
  Parser q;
  EXPECT_TRUE(feed_all(q, cat({kHalfFrame, stop_frame(0)})).empty());
  EXPECT_TRUE(silence(q, kByteGap_ms - 1).empty());
  const auto late = silence(q, kByteGap_ms);
  ASSERT_EQ(late.size(), 1u);
  EXPECT_EQ(late[0].type, (uint8_t)MsgType::cmd_stop);
  EXPECT_EQ(q.framing_errors(), 1);
  EXPECT_EQ(q.crc_errors(), 0);
}

// Garbage of every kind, alone and in pairs, straight before a frame (no gap): the frame is
// found, once, by the silence after it at the latest, and nothing else is.
TEST(Parser, GarbageOfEveryKindBeforeAFrameWithNoGap) {
  const std::vector<uint8_t> velocity = message_bytes(VelocityCmd{{150, -150, 0}, {0, 800, -800}}, 7);
  const std::vector<uint8_t> state = message_bytes(sample_state(), 8);
  std::vector<std::vector<uint8_t>> kinds = {
      {0x00, 0xFF, 0x13},                    // noise
      {0xA5},                                // a stray sync
      {0xA5, 0xA5},                          // two
      {0xA5, 0x01},                          // a wrong version
      {0xA5, kVersion, 0x01, 0x00, 0x41},    // a length over kMaxPayload
      {0xA5, kVersion, 0xA5, kVersion, 0x40},  // syncs inside a header, a length of 64
  };
  auto bad_crc = stop_frame(3);
  bad_crc.back() ^= 0x40;
  kinds.push_back(bad_crc);
  // a frame cut short after every one of its bytes (the state frame's, 64 payload bytes, takes
  // any frame after it whole)
  for (const auto* whole : {&velocity, &state, &kHalfFrame})
    for (size_t n = 1; n < whole->size(); ++n) kinds.emplace_back(whole->begin(), whole->begin() + (long)n);
  size_t cases = 0;
  for (const auto& frame : {stop_frame(9), velocity, state}) {
    for (size_t a = 0; a < kinds.size(); ++a) {
      for (size_t b = 0; b <= kinds.size(); b += 7) {  // alone (b == kinds.size() is none), and with every 7th kind after it
        const std::vector<uint8_t> garbage = b < kinds.size() ? cat({kinds[a], kinds[b]}) : kinds[a];
        Parser p;
        auto found = feed_all(p, cat({garbage, frame}));
        for (const Frame& f : silence(p, kByteGap_ms)) found.push_back(f);
        ASSERT_EQ(found.size(), 1u) << "kind " << a << " then " << b << ", frame of " << frame.size();
        EXPECT_EQ(frame_bytes(found[0].type, found[0].seq, std::vector<uint8_t>(found[0].payload, found[0].payload + found[0].len)),
                  frame)
            << "kind " << a << " then " << b;
        EXPECT_FALSE(p.holding());
        ++cases;
      }
    }
  }
  EXPECT_GT(cases, 1000u);
}

// A frame that comes with gaps shorter than kByteGap_ms between its bytes (a host writing it in
// pieces) is whole.
TEST(Parser, GapsShorterThanTheTimeoutInsideAFrame) {
  const auto stop = stop_frame(5);
  Parser p;
  int found = 0;
  for (uint8_t b : stop) {
    p.push(b);
    while (p.next()) ++found;
    for (uint8_t ms = 0; ms < kByteGap_ms; ++ms) found += (int)silence(p, ms).size();
  }
  EXPECT_EQ(found, 1);
  EXPECT_EQ(p.framing_errors() + p.crc_errors() + p.skipped_bytes(), 0);
}

// The silence is the line's only while every byte has been looked at: bytes waiting to be
// looked at are not a gap (the firmware's rescans may leave some for a later tick).
TEST(Parser, IdleWithBytesWaitingIsNoGap) {
  const auto stop = stop_frame(6);
  Parser p;
  EXPECT_TRUE(feed_all(p, {stop.begin(), stop.begin() + 4}).empty());
  p.push(stop[4]);  // not looked at yet
  p.line_quiet(kByteGap_ms);
  EXPECT_EQ(p.framing_errors(), 0);
  auto found = feed_all(p, {});
  while (p.next()) found.push_back(p.frame());
  for (const Frame& f : feed_all(p, {stop.begin() + 5, stop.end()})) found.push_back(f);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].seq, 6);
}

// A gap ends every candidate that began before it: a partial frame inside the dropped one's
// bytes is dropped too, so the first frame after the gap is found as it comes, not taken as
// that one's tail (the stop below would be a 7-byte payload).
TEST(Parser, CandidatesFromBeforeAGapEndAtIt) {
  Parser p;
  EXPECT_TRUE(feed_all(p, cat({kHalfFrame, {0xA5, kVersion, 0x10, 0x00, 0x07}})).empty());
  EXPECT_TRUE(silence(p, kByteGap_ms).empty());
  EXPECT_FALSE(p.holding());
  EXPECT_EQ(p.framing_errors(), 2);
  const auto frames = feed_all(p, stop_frame(1));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, (uint8_t)MsgType::cmd_stop);
}

// A fuzzed line: valid frames, frames cut short, runs of bytes made of what frames are made of
// (syncs, the version, short lengths), random bytes, and gaps of 1 to 5 ms between them, fed as
// the firmware feeds them (feed, then steps until caught up). Every frame the parser gives is in
// the line as it came, byte for byte, with a correct CRC (the ring's wrap and the rescans
// assemble nothing else), and every valid frame with a gap of kByteGap_ms before and after it
// is found.
TEST(Parser, FuzzedLineWithGaps) {
  std::mt19937 rng(3030u);
  const auto pick = [&](uint32_t n) { return (uint32_t)(rng() % n); };
  std::vector<uint8_t> line;
  std::vector<uint8_t> quiet_after;  // the line's silence after each byte, ms
  std::vector<std::vector<uint8_t>> isolated;  // the valid frames with a gap on either side
  uint32_t serial = 0;
  const auto add = [&](const std::vector<uint8_t>& bytes) {
    for (uint8_t b : bytes) {
      line.push_back(b);
      quiet_after.push_back(0);
    }
  };
  const auto gap = [&] {
    if (!quiet_after.empty() && pick(4) != 0) quiet_after.back() = (uint8_t)(1 + pick(5));
  };
  while (line.size() < 400000) {
    const uint32_t kind = pick(10);
    std::vector<uint8_t> payload(pick(kMaxPayload + 1));
    for (uint8_t& b : payload) b = (uint8_t)rng();
    if (payload.size() >= 4)
      for (int i = 0; i < 4; ++i) payload[i] = (uint8_t)(serial >> (8 * i));  // each frame its own
    ++serial;
    const std::vector<uint8_t> frame = frame_bytes((uint8_t)rng(), (uint8_t)rng(), payload);
    if (kind < 3) {  // a valid frame, gaps of 1 to 5 ms before and after it or not
      gap();
      const bool gap_before = !quiet_after.empty() && quiet_after.back() >= kByteGap_ms;
      add(frame);
      gap();
      if (gap_before && quiet_after.back() >= kByteGap_ms) isolated.push_back(frame);
    } else if (kind < 5) {  // a frame cut short
      add(std::vector<uint8_t>(frame.begin(), frame.begin() + 1 + pick((uint32_t)frame.size() - 1)));
    } else if (kind < 8) {  // what frames are made of
      const uint8_t parts[] = {kSync, kVersion, (uint8_t)pick(8), (uint8_t)pick(kMaxPayload + 2), (uint8_t)rng()};
      std::vector<uint8_t> run(1 + pick(40));
      for (uint8_t& b : run) b = parts[pick(5)];
      add(run);
    } else if (kind < 9) {
      std::vector<uint8_t> run(1 + pick(40));
      for (uint8_t& b : run) b = (uint8_t)rng();
      add(run);
    } else {
      gap();
    }
  }

  Parser p;
  std::vector<std::vector<uint8_t>> found;
  size_t max_steps = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    size_t steps = 1;
    std::vector<Frame> frames;
    if (p.feed(line[i])) frames.push_back(p.frame());
    for (; !p.caught_up(); ++steps)
      if (p.step()) frames.push_back(p.frame());
    if (quiet_after[i]) {
      p.line_quiet(quiet_after[i]);
      for (; !p.caught_up(); ++steps)
        if (p.step()) frames.push_back(p.frame());
    }
    max_steps = std::max(max_steps, steps);
    for (const Frame& f : frames) {
      const std::vector<uint8_t> whole = frame_bytes(f.type, f.seq, std::vector<uint8_t>(f.payload, f.payload + f.len));
      const auto from = line.begin() + (long)(i + 1 > 2 * kMaxFrameBytes ? i + 1 - 2 * kMaxFrameBytes : 0);
      const auto at = std::search(from, line.begin() + (long)i + 1, whole.begin(), whole.end());
      ASSERT_NE(at, line.begin() + (long)i + 1) << "a frame not in the line, at byte " << i;
      ASSERT_EQ(le16(&*at + whole.size() - 2), crc_bitwise(&*at + 1, whole.size() - 3));
      found.push_back(whole);
    }
  }
  size_t missed = 0;
  for (const auto& frame : isolated) missed += std::find(found.begin(), found.end(), frame) == found.end();
  std::printf("%zu bytes, %zu frames found, %zu of them with a gap either side, %zu missed; at most %zu steps after a byte\n",
              line.size(), found.size(), isolated.size(), missed, max_steps);
  EXPECT_GT(isolated.size(), 1000u);
  EXPECT_EQ(missed, 0u);
}

TEST(Parser, OneMegabyteOfRandomBytes) {
  std::mt19937 rng(20240501u);
  std::vector<uint8_t> bytes(1u << 20);
  for (auto& b : bytes) b = (uint8_t)rng();
  Parser p;
  int valid = 0;
  for (size_t i = 0; i < bytes.size(); ++i) {
    p.push(bytes[i]);
    while (p.next()) {
      ++valid;
      // a frame the parser accepts is really in the stream, within the bytes held (a rescan
      // finds one that ends before this byte), with a correct CRC
      const Frame& f = p.frame();
      const std::vector<uint8_t> whole = frame_bytes(f.type, f.seq, std::vector<uint8_t>(f.payload, f.payload + f.len));
      const auto from = bytes.begin() + (long)(i + 1 > 2 * kMaxFrameBytes ? i + 1 - 2 * kMaxFrameBytes : 0);
      const auto found = std::search(from, bytes.begin() + (long)i + 1, whole.begin(), whole.end());
      ASSERT_NE(found, bytes.begin() + (long)i + 1) << "a frame not in the stream at byte " << i;
      EXPECT_EQ(le16(&*found + whole.size() - 2), crc_bitwise(&*found + 1, whole.size() - 3));
    }
  }
  // a sync (1/256), the version (1/256), a length <= 64 (1/4) and the CRC (1/65536) by chance:
  // about 4 candidate frames per MB and 6e-5 valid ones; each candidate is a CRC error (or, rarely,
  // a frame cut by a sync inside it)
  size_t candidates = 0;
  for (size_t i = 0; i + 4 < bytes.size(); ++i)
    candidates += bytes[i] == kSync && bytes[i + 1] == kVersion && bytes[i + 4] <= kMaxPayload;
  std::printf("%zu candidate headers, %u CRC errors, %d valid frames\n", candidates, (unsigned)p.crc_errors(), valid);
  EXPECT_LE(valid, 1);
  EXPECT_LE(p.crc_errors(), candidates);
  EXPECT_GE(p.crc_errors() + 1, candidates);
  // most syncs are followed by a wrong version
  EXPECT_GT(p.framing_errors(), 3500);
  EXPECT_LT(p.framing_errors(), 4700);
  EXPECT_EQ(p.skipped_bytes(), 0xFFFF);  // saturated, not wrapped
}

TEST(Commands, CheckCommand) {
  auto check = [](MsgType type, std::vector<uint8_t> payload) {
    Frame f{};
    f.type = (uint8_t)type;
    f.len = (uint8_t)payload.size();
    std::copy(payload.begin(), payload.end(), f.payload);
    return check_command(f);
  };
  using S = ReplyStatus;
  for (MsgType t : {MsgType::cmd_stop, MsgType::cmd_rearm, MsgType::cmd_home, MsgType::cmd_get_calibration}) {
    EXPECT_EQ(check(t, {}), S::ok);
    EXPECT_EQ(check(t, {0}), S::bad_length);
  }
  EXPECT_EQ(check(MsgType::cmd_mode, {0}), S::ok);
  EXPECT_EQ(check(MsgType::cmd_mode, {4}), S::ok);  // gripper
  EXPECT_EQ(check(MsgType::cmd_mode, {5}), S::bad_argument);
  EXPECT_EQ(check(MsgType::cmd_mode, {}), S::bad_length);
  EXPECT_EQ(check(MsgType::cmd_mode, {1, 0}), S::bad_length);
  EXPECT_EQ(check(MsgType::cmd_speed_scale, {0}), S::ok);
  EXPECT_EQ(check(MsgType::cmd_speed_scale, {100}), S::ok);
  EXPECT_EQ(check(MsgType::cmd_speed_scale, {101}), S::bad_argument);
  EXPECT_EQ(check(MsgType::cmd_speed_scale, {255}), S::bad_argument);
  EXPECT_EQ(check(MsgType::cmd_speed_scale, {}), S::bad_length);
  for (MsgType t : {MsgType::cmd_goto_pose, MsgType::cmd_store_pose}) {
    EXPECT_EQ(check(t, {0}), S::ok);
    EXPECT_EQ(check(t, {3}), S::ok);
    EXPECT_EQ(check(t, {4}), S::bad_argument);
    EXPECT_EQ(check(t, {}), S::bad_length);
  }
  EXPECT_EQ(check(MsgType::cmd_velocity, std::vector<uint8_t>(12, 0xFF)), S::ok);
  EXPECT_EQ(check(MsgType::cmd_velocity, std::vector<uint8_t>(11, 0)), S::bad_length);
  EXPECT_EQ(check(MsgType::cmd_velocity, std::vector<uint8_t>(13, 0)), S::bad_length);
  // the joint and the values are the firmware's to check (it knows which joints have pots)
  EXPECT_EQ(check(MsgType::cmd_pot_calibration, {9, 0xFF, 0xFF, 0, 0}), S::ok);
  EXPECT_EQ(check(MsgType::cmd_pot_calibration, {3, 0, 0, 0}), S::bad_length);
  EXPECT_EQ(check(MsgType::cmd_pot_calibration, {3, 0, 0, 0, 0, 0}), S::bad_length);
  EXPECT_EQ(check(MsgType::cmd_stick_centre, {0}), S::ok);  // forget
  EXPECT_EQ(check(MsgType::cmd_stick_centre, {1}), S::ok);  // store
  EXPECT_EQ(check(MsgType::cmd_stick_centre, {2}), S::bad_argument);
  EXPECT_EQ(check(MsgType::cmd_stick_centre, {}), S::bad_length);
  EXPECT_EQ(check(MsgType::cmd_info, {}), S::ok);
  EXPECT_EQ(check(MsgType::cmd_info, {0}), S::bad_length);
  // jog: joint 1..6, a speed of two bytes (its range is the firmware's to cap)
  for (uint8_t joint = 1; joint <= 6; ++joint) EXPECT_EQ(check(MsgType::cmd_jog, {joint, 0xFF, 0x7F}), S::ok) << (int)joint;
  EXPECT_EQ(check(MsgType::cmd_jog, {0, 100, 0}), S::bad_argument);
  EXPECT_EQ(check(MsgType::cmd_jog, {7, 100, 0}), S::bad_argument);
  EXPECT_EQ(check(MsgType::cmd_jog, {3, 100}), S::bad_length);
  // not commands: the firmware's own types, the gaps around the command range
  for (uint8_t t : {0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x0F, 0x1D, 0xFF}) EXPECT_EQ(check((MsgType)t, {}), S::unknown_command) << (int)t;
}
