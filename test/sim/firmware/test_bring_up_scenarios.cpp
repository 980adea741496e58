// What a technician bringing up a board relies on (docs/arm-guide.md, bring-up; SPEC 7): the boot
// frame names the firmware (its version, the commit it was built from, the configuration's hash),
// and `info` answers in any state with the same and the configured numbers. The firmware ELF in
// the simulator; the expected numbers worked out here from the configuration and the arm's limits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "build_identity.h"
#include "config/control_config.h"
#include "config/motion_config.h"
#include "config/version.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;
using protocol::MsgType;
using test::command;
using test::kFirmware;
using test::Rig;

void expect_this_build(const protocol::Identity& id) {
  EXPECT_EQ(id.version[0], config::kProductVersion.major);
  EXPECT_EQ(id.version[1], config::kProductVersion.minor);
  EXPECT_EQ(id.version[2], config::kProductVersion.patch);
  const uint8_t commit[6] = WMRA_BUILD_COMMIT_BYTES;  // the host side's stamp of the same tree
  for (int i = 0; i < 6; ++i) EXPECT_EQ(id.commit[i], commit[i]) << "commit byte " << i;
  EXPECT_EQ(id.config_hash, (uint32_t)WMRA_CONFIG_HASH);
  EXPECT_EQ(id.build_flags & ~(protocol::kBuildTreeChanged | protocol::kBuildCommitUnknown), 0);
}

TEST(BringUp, TheBootFrameNamesTheBuild) {
  Rig rig(kFirmware);
  rig.run_to(0.3);
  ASSERT_EQ(rig.telemetry.boots().size(), 1u);
  expect_this_build(rig.telemetry.boots()[0].identity);
}

// before homing (the arm waits for the person, drives off), running, and stopped: the reply, then
// the info frame
TEST(BringUp, InfoAnswersInEveryStateWithTheConfiguredNumbers) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  rig.sim.send_serial(command(MsgType::cmd_info, 1));
  rig.run_to(rig.sim.time_s() + 0.1);
  ASSERT_GE(rig.start(20.0), 0);
  rig.sim.send_serial(command(MsgType::cmd_info, 2));
  rig.run_to(rig.sim.time_s() + 0.1);
  rig.sim.send_serial(command(MsgType::cmd_stop, 3));
  rig.run_to(rig.sim.time_s() + 0.1);
  rig.sim.send_serial(command(MsgType::cmd_info, 4));
  rig.run_to(rig.sim.time_s() + 0.1);

  int info_replies = 0;
  for (const protocol::ReplyMsg& r : rig.telemetry.replies()) {
    if (r.command_type != (uint8_t)MsgType::cmd_info) continue;
    ++info_replies;
    EXPECT_EQ(r.status, (uint8_t)protocol::ReplyStatus::ok) << "info seq " << (int)r.command_seq;
  }
  EXPECT_EQ(info_replies, 3);
  ASSERT_EQ(rig.telemetry.infos().size(), 3u);
  for (const protocol::InfoMsg& info : rig.telemetry.infos()) {
    expect_this_build(info.identity);
    EXPECT_EQ(info.hand_speed_mm_s, std::lround(1000.0 * config::kMaxHandSpeed_m_s.num / config::kMaxHandSpeed_m_s.den));
    EXPECT_EQ(info.wrist_speed_mrad_s, std::lround(1000.0 * config::kMaxWristSpeed_rad_s.num / config::kMaxWristSpeed_rad_s.den));
    EXPECT_EQ(info.loop_hz, config::kLoopHz);
    for (int j = 0; j < 6; ++j) {
      EXPECT_EQ(info.joint_speed_mrad_s[j], 10 * config::kJointSpeedLimit_crad_s[j]) << "J" << j + 1;
      const double margin_rad = arm::deg_to_rad(config::kSoftLimitMargin_deg);
      EXPECT_NEAR(info.soft_min_mrad[j], 1000 * (arm::q_min_rad(j) + margin_rad), 0.5) << "J" << j + 1;
      EXPECT_NEAR(info.soft_max_mrad[j], 1000 * (arm::q_max_rad(j) - margin_rad), 0.5) << "J" << j + 1;
    }
  }
}

}  // namespace
