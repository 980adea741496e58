// armsim's FirmwareTelemetry on bytes encoded here: mode and state of the latest state frame,
// faults in the order they first appeared, replies, boots, the counts summary.json reports.
#include <gtest/gtest.h>

#include <vector>

#include "armsim/firmware_telemetry.h"
#include "core/faults.h"
#include "protocol_frames.h"

using namespace wmra;
using namespace wmra::protocol;

namespace {

struct Feeder {
  armsim::FirmwareTelemetry t;
  void bytes(const std::vector<uint8_t>& b) {
    for (uint8_t x : b) t.feed(x);
  }
  template <class Msg>
  void message(const Msg& m, uint8_t seq) {
    bytes(protocol_frames::message_bytes(m, seq));
  }
};

StateMsg state(uint32_t t_ms, uint8_t arm_state, uint8_t mode, uint32_t faults) {
  StateMsg s{};
  s.t_ms = t_ms;
  s.state = arm_state;
  s.mode = mode;
  s.faults = faults;
  return s;
}

}  // namespace

TEST(FirmwareTelemetry, NothingBeforeTheFirstFrame) {
  Feeder f;
  f.bytes({'b', 'o', 'o', 't', 0xA5});
  EXPECT_EQ(f.t.mode(), -1);
  EXPECT_EQ(f.t.state(), -1);
  EXPECT_TRUE(f.t.faults().empty());
  EXPECT_EQ(f.t.last_state(), nullptr);
  const armsim::TelemetrySummary s = f.t.summary();
  EXPECT_EQ(s.frames, 0u);
  EXPECT_EQ(s.replies, 0u);
  EXPECT_TRUE(s.boot_reset_causes.empty());
  EXPECT_EQ(f.t.stream().parser().skipped_bytes(), 4);
}

TEST(FirmwareTelemetry, DecodesWhatTheFirmwareSays) {
  using core::fault_mask;
  Feeder f;
  f.message(BootMsg{0x01, 0, {}}, 0);
  f.message(state(20, 1, 0, 0), 1);
  EXPECT_EQ(f.t.state(), 1);
  EXPECT_EQ(f.t.mode(), 0);
  f.message(state(40, 6, 2, fault_mask(4)), 2);  // j3_stall
  f.message(ReplyMsg{(uint8_t)MsgType::cmd_rearm, 9, (uint8_t)ReplyStatus::refused}, 3);
  f.message(state(60, 6, 2, fault_mask(3) | fault_mask(4)), 4);  // j2_rail joins it
  f.bytes({0xA5, kVersion, 0x01, 0x05, 0x00, 0x12, 0x34});           // seq 5, bad CRC
  f.message(state(100, 6, 3, fault_mask(core::kFaultBitStickInvalid)), 6);
  f.message(BootMsg{0x08 | 0x04, 2, {}}, 0);  // watchdog and brown-out
  f.message(BootMsg{0x00, 0, {}}, 0);

  EXPECT_EQ(f.t.state(), 6);
  EXPECT_EQ(f.t.mode(), 3);
  EXPECT_EQ(f.t.faults(), (std::vector<std::string>{"j3_stall", "j2_rail", "stick_invalid"}));
  ASSERT_NE(f.t.last_state(), nullptr);
  EXPECT_EQ(f.t.last_state()->t_ms, 100u);
  ASSERT_EQ(f.t.states().size(), 4u);
  EXPECT_EQ(f.t.states()[1].t_ms, 40u);
  ASSERT_EQ(f.t.replies().size(), 1u);
  EXPECT_EQ(f.t.replies()[0].command_seq, 9);
  EXPECT_EQ(f.t.replies()[0].status, (uint8_t)ReplyStatus::refused);
  ASSERT_EQ(f.t.boots().size(), 3u);
  EXPECT_EQ(f.t.boots()[1].calibration, 2);

  const armsim::TelemetrySummary s = f.t.summary();
  EXPECT_EQ(s.frames, 8u);
  EXPECT_EQ(s.crc_errors, 1u);
  EXPECT_EQ(s.seq_gaps, 1u);  // seq 5 lost to the CRC
  EXPECT_EQ(s.replies, 1u);
  EXPECT_EQ(s.boot_reset_causes, (std::vector<std::string>{"power_on", "brown_out+watchdog", "none"}));
}
