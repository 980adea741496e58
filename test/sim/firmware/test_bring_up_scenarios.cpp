// What a technician bringing up a board relies on (docs/arm-guide.md, bring-up; SPEC 7): the boot
// frame names the firmware (its version, the commit it was built from, the configuration's hash),
// and `info` answers in any state with the same and the configured numbers; `jog` turns one joint
// slowly, before homing (a stepper stopped by its switches) or running with the stick neutral,
// and nothing else. The firmware ELF in the simulator, motion judged on the plant's true angles;
// the expected numbers worked out here from the configuration and the arm's limits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "build_identity.h"
#include "config/control_config.h"
#include "config/motion_config.h"
#include "config/version.h"
#include "core/faults.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"
#include "telemetry_json.h"

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

// jog commands every 40 ms for `seconds` (the firmware stops a jog 100 ms after the last); the
// replies' statuses counted
struct JogReplies {
  int ok = 0, refused = 0, other = 0;
};
JogReplies jog_for(Rig& rig, uint8_t joint, int16_t mrad_s, double seconds) {
  const size_t replies_before = rig.telemetry.replies().size();
  const double t0 = rig.sim.time_s();
  static uint8_t seq = 0;
  for (double t = 0; t < seconds; t += 0.04) {
    rig.sim.send_serial(command(MsgType::cmd_jog, seq++, {joint, (uint8_t)mrad_s, (uint8_t)((uint16_t)mrad_s >> 8)}));
    rig.run_to(t0 + t + 0.04);
  }
  JogReplies r;
  for (size_t i = replies_before; i < rig.telemetry.replies().size(); ++i) {
    const protocol::ReplyMsg& m = rig.telemetry.replies()[i];
    if (m.command_type != (uint8_t)MsgType::cmd_jog) continue;
    if (m.status == (uint8_t)protocol::ReplyStatus::ok) ++r.ok;
    else if (m.status == (uint8_t)protocol::ReplyStatus::refused) ++r.refused;
    else ++r.other;
  }
  return r;
}

double largest_other_travel(const plant::Joints& a, const plant::Joints& b, int jogged) {
  double m = 0;
  for (int j = 0; j < 6; ++j)
    if (j != jogged) m = std::max(m, std::fabs(b[j] - a[j]));
  return m;
}

// Before homing, with the drives off: a jog of a DC joint turns it at the speed asked (capped),
// nothing else moves, it stops within the stream's timeout after the last command, and the arm
// waits for the person again, without a fault (the standstill watch takes the new rest).
TEST(BringUp, AJogBeforeHomingTurnsOneJointAndTheArmWaitsAgain) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  const plant::Joints before = rig.sim.q();
  const JogReplies r = jog_for(rig, 3, 1000, 1.0);  // J3, asked 1 rad/s: capped
  EXPECT_EQ(rig.state(), core::ArmState::jog);
  const double t_last = rig.sim.time_s();
  rig.run_to(t_last + 0.15);
  const plant::Joints stopped = rig.sim.q();
  rig.run_to(t_last + 1.0);
  const plant::Joints after = rig.sim.q();
  const double turned = after[2] - before[2];
  std::printf("jog J3 before homing: %d ok, %d refused; turned %.1f mrad, others at most %.2f mrad, %.2f mrad after 0.15 s\n", r.ok,
              r.refused, 1000 * turned, 1000 * largest_other_travel(before, after, 2), 1000 * std::fabs(after[2] - stopped[2]));
  EXPECT_EQ(r.ok, 25);
  EXPECT_EQ(r.refused + r.other, 0);
  // 0.1 rad/s for about the second of commands and the timeout, less the ramps
  EXPECT_GT(turned, 0.085);
  EXPECT_LT(turned, 0.115);
  EXPECT_LT(largest_other_travel(before, after, 2), 2e-3);
  EXPECT_LT(std::fabs(after[2] - stopped[2]), 3e-3) << "J3 went on after the jog";
  EXPECT_EQ(rig.state(), core::ArmState::wait_home);
  EXPECT_EQ(rig.last().faults, 0u);
  // and the person's ask still homes the arm
  ASSERT_GE(rig.start(rig.sim.time_s() + 25.0), 0);
}

// Before homing a stepper's count is not its angle: slower (kJogUnhomedStepperSpeed_mrad_s), and
// its switch stops it (J1 from 86 deg towards its high switch at 90)
TEST(BringUp, AStepperJoggedBeforeHomingStopsAtItsSwitch) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  const plant::Joints before = rig.sim.q();
  jog_for(rig, 1, 100, 1.0);
  const double speed = (rig.sim.q()[0] - before[0]) / 1.0;
  const JogReplies r = jog_for(rig, 1, 100, 3.0);  // on into the switch
  rig.run_to(rig.sim.time_s() + 0.5);
  const plant::Joints after = rig.sim.q();
  std::printf("jog J1 before homing: %.1f mrad/s over its first second; at the end %.2f deg (switch at %.0f), switch %s, %d ok\n",
              1000 * speed, (180.0 / arm::kPi * (after[0])), (double)arm::q_max_deg[0], rig.sim.plant().limit_closed(0, true) ? "closed" : "open", r.ok);
  EXPECT_NEAR(speed, config::kJogUnhomedStepperSpeed_mrad_s / 1000.0, 0.01);
  EXPECT_TRUE(rig.sim.plant().limit_closed(0, true));
  EXPECT_LT(after[0], arm::q_max_rad(0) + 0.01) << "J1 ran on past its switch";
  EXPECT_LT(largest_other_travel(before, after, 0), 2e-3);
  EXPECT_EQ(rig.state(), core::ArmState::wait_home);
  EXPECT_EQ(rig.last().faults, 0u);
}

// Running: a jog turns the joint and the arm runs again from where it ended: the stick's
// commanded position starts there (no pull back to where the hand was before the jog)
TEST(BringUp, AJogWhileRunningAndTheArmStaysWhereItEnded) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.start(25.0), 0);
  rig.run_to(rig.sim.time_s() + 1.0);
  const plant::Joints before = rig.sim.q();
  const JogReplies r = jog_for(rig, 4, -100, 1.0);
  rig.run_to(rig.sim.time_s() + 0.5);
  const plant::Joints ended = rig.sim.q();
  EXPECT_EQ(rig.state(), core::ArmState::running);
  rig.run_to(rig.sim.time_s() + 2.0);  // running, the stick neutral
  const plant::Joints later = rig.sim.q();
  double moved_after = 0;
  for (int j = 0; j < 6; ++j) moved_after = std::max(moved_after, std::fabs(later[j] - ended[j]));
  std::printf("jog J4 running: %d ok; turned %.1f mrad, others %.2f mrad; after it %.2f mrad\n", r.ok, 1000 * (ended[3] - before[3]),
              1000 * largest_other_travel(before, ended, 3), 1000 * moved_after);
  EXPECT_EQ(r.ok, 25);
  EXPECT_LT(ended[3] - before[3], -0.085);
  EXPECT_GT(ended[3] - before[3], -0.115);
  EXPECT_LT(largest_other_travel(before, ended, 3), 2e-3);
  EXPECT_LT(moved_after, 2e-3) << "something moved after the jog";
}

// Refused where the state does not allow it (stopped, homing, a move under way, the stick
// deflected), nothing moving for it; a joint outside 1..6 is a bad argument
TEST(BringUp, AJogIsRefusedWhereTheArmIsNotFreeForIt) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  rig.sim.send_serial(command(MsgType::cmd_jog, 1, {0, 100, 0}));
  rig.sim.send_serial(command(MsgType::cmd_jog, 2, {7, 100, 0}));
  rig.run_to(rig.sim.time_s() + 0.1);
  const auto& replies = rig.telemetry.replies();
  ASSERT_GE(replies.size(), 2u);
  EXPECT_EQ(replies[replies.size() - 2].status, (uint8_t)protocol::ReplyStatus::bad_argument);
  EXPECT_EQ(replies.back().status, (uint8_t)protocol::ReplyStatus::bad_argument);

  rig.sim.send_serial(command(MsgType::cmd_home, 3));  // homing
  rig.run_to(rig.sim.time_s() + 0.5);
  ASSERT_EQ(rig.state(), core::ArmState::homing);
  EXPECT_EQ(jog_for(rig, 2, 100, 0.2).refused, 5);
  ASSERT_GE(rig.run_until_state(core::ArmState::running, rig.sim.time_s() + 25.0), 0);

  rig.sim.set_joystick(0.5, 0);  // deflected
  rig.run_to(rig.sim.time_s() + 0.3);
  EXPECT_EQ(jog_for(rig, 2, 100, 0.2).refused, 5);
  rig.sim.set_joystick(0, 0);
  rig.run_to(rig.sim.time_s() + 1.0);

  rig.sim.send_serial(command(MsgType::cmd_stop, 4));
  rig.run_to(rig.sim.time_s() + 0.3);
  ASSERT_EQ(rig.state(), core::ArmState::stopped);
  const plant::Joints before = rig.sim.q();
  EXPECT_EQ(jog_for(rig, 2, 100, 0.5).refused, 13);
  EXPECT_LT(largest_other_travel(before, rig.sim.q(), -1), 1e-3);
  EXPECT_EQ(rig.state(), core::ArmState::stopped);
}

// Running, a DC joint jogged towards its soft limit slows to a stop there
TEST(BringUp, AJogStopsAtTheSoftLimit) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.start(25.0), 0);
  double highest = rig.sim.q()[3];
  const double t0 = rig.sim.time_s();
  rig.sim.every(0.01, [&highest](const sim::ArmSimulator& s) { highest = std::max(highest, s.q()[3]); });
  // J4 from the ready pose up to its soft limit at 160 - 3 deg: at most ~40 s at 0.1 rad/s
  for (int k = 0; k < 60 && rig.sim.q()[3] < arm::q_max_rad(3) - arm::deg_to_rad(config::kSoftLimitMargin_deg) - 0.01; ++k)
    jog_for(rig, 4, 100, 1.0);
  jog_for(rig, 4, 100, 2.0);  // pushing on at the limit
  rig.run_to(rig.sim.time_s() + 0.5);
  const double soft = arm::q_max_rad(3) - arm::deg_to_rad(config::kSoftLimitMargin_deg);
  std::printf("jog J4 up: highest %.2f deg against the soft limit %.2f deg, after %.0f s\n", (180.0 / arm::kPi * (highest)),
              (180.0 / arm::kPi * (soft)), rig.sim.time_s() - t0);
  EXPECT_GT(highest, soft - arm::deg_to_rad(1));
  EXPECT_LT(highest, soft + arm::deg_to_rad(0.5));
  EXPECT_EQ(rig.state(), core::ArmState::running);
  EXPECT_EQ(rig.last().faults, 0u);
}

// The person takes over: the stick deflected during a jog stops it at once (within the ramp),
// and the arm waits for the stick to rest as after any deflection; every joint, J6 and J5 too,
// jogs before homing without a fault
TEST(BringUp, TheStickDeflectedEndsAJogAndEveryJointJogsBeforeHoming) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  for (uint8_t joint = 1; joint <= 6; ++joint) {
    const plant::Joints before = rig.sim.q();
    const JogReplies r = jog_for(rig, joint, joint % 2 ? -60 : 60, 0.5);
    rig.run_to(rig.sim.time_s() + 0.5);
    const plant::Joints after = rig.sim.q();
    const double turned = after[joint - 1] - before[joint - 1];
    std::printf("jog J%d before homing: %d ok, turned %.1f mrad, others %.2f mrad, state %s, faults %u\n", joint, r.ok, 1000 * turned,
                1000 * largest_other_travel(before, after, joint - 1), core::to_string(rig.state()), (unsigned)rig.last().faults);
    EXPECT_EQ(r.ok, 13) << "J" << (int)joint;
    EXPECT_GT(std::fabs(turned), 0.015) << "J" << (int)joint;
    EXPECT_EQ(turned > 0, joint % 2 == 0) << "J" << (int)joint << " turned the wrong way";
    EXPECT_LT(largest_other_travel(before, after, joint - 1), 2e-3) << "J" << (int)joint;
    EXPECT_EQ(rig.state(), core::ArmState::wait_home) << "J" << (int)joint;
    EXPECT_EQ(rig.last().faults, 0u) << "J" << (int)joint;
  }
  // J2 jogging, then the stick deflected: it stops, and later commands are refused
  jog_for(rig, 2, 100, 0.5);
  rig.sim.set_joystick(0.6, 0);
  const plant::Joints at_deflection = rig.sim.q();
  const JogReplies during = jog_for(rig, 2, 100, 0.5);
  const plant::Joints after = rig.sim.q();
  std::printf("stick deflected during a J2 jog: %.1f mrad more, %d refused, state %s\n", 1000 * (after[1] - at_deflection[1]),
              during.refused, core::to_string(rig.state()));
  EXPECT_LT(after[1] - at_deflection[1], 0.01);
  EXPECT_GE(during.refused, 10);
  EXPECT_NE(rig.state(), core::ArmState::jog);
}

// A jog that a stop or the stick ended does not start again while its commands keep coming (a
// host still sending them after the re-arm, or when the stick is let go): they are refused until
// the host pauses for the timeout, then a new jog is accepted
TEST(BringUp, AJogThatEndedStaysEndedUntilItsCommandsPause) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  jog_for(rig, 3, 100, 0.5);
  rig.sim.send_serial(command(MsgType::cmd_stop, 1));
  jog_for(rig, 3, 100, 0.5);
  ASSERT_EQ(rig.state(), core::ArmState::stopped);
  rig.sim.send_serial(command(MsgType::cmd_rearm, 2));
  jog_for(rig, 3, 100, 1.0);  // wait_neutral, then the wait: the commands still coming
  const plant::Joints rearmed = rig.sim.q();
  const JogReplies after = jog_for(rig, 3, 100, 1.0);
  const double moved_after_rearm = std::fabs(rig.sim.q()[2] - rearmed[2]);
  EXPECT_EQ(rig.state(), core::ArmState::wait_home);
  rig.run_to(rig.sim.time_s() + 0.2);  // the host pauses
  const plant::Joints paused = rig.sim.q();
  const JogReplies anew = jog_for(rig, 3, 100, 0.5);
  std::printf("jog after stop and re-arm: %d refused, J3 %.2f mrad; after a pause: %d ok, J3 %.1f mrad\n", after.refused,
              1000 * moved_after_rearm, anew.ok, 1000 * (rig.sim.q()[2] - paused[2]));
  EXPECT_EQ(after.ok, 0);
  EXPECT_LT(moved_after_rearm, 1e-3) << "the jog started again by itself";
  EXPECT_EQ(anew.ok, 13);
  EXPECT_GT(rig.sim.q()[2] - paused[2], 0.02);

  // running: the stick takes the jog over; let go, the jog's commands still coming move nothing
  ASSERT_GE(rig.start(rig.sim.time_s() + 25.0), 0);
  rig.run_to(rig.sim.time_s() + 1.0);
  jog_for(rig, 2, 100, 0.5);
  rig.sim.set_joystick(0, 0.6);
  jog_for(rig, 2, 100, 0.4);
  rig.sim.set_joystick(0, 0);
  jog_for(rig, 2, 100, 0.8);  // the hand comes to rest after the stick's release
  const plant::Joints released = rig.sim.q();
  const JogReplies taken = jog_for(rig, 2, 100, 1.0);
  double moved = 0;
  for (int j = 0; j < 6; ++j) moved = std::max(moved, std::fabs(rig.sim.q()[j] - released[j]));
  std::printf("jog after the stick took it over: %d ok, %d refused; the arm moved %.2f mrad\n", taken.ok, taken.refused, 1000 * moved);
  EXPECT_EQ(taken.ok, 0);
  EXPECT_LT(moved, 1.5e-3);
  EXPECT_EQ(rig.state(), core::ArmState::running);
}

// Before homing J6 (no switch, its angle not recorded) goes no further than
// kJogUnhomedTravel_deg from where its count stood at power-up, however long the jog
TEST(BringUp, J6JoggedBeforeHomingStaysWithinItsTravel) {
  Rig rig(kFirmware);
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  const double start = rig.sim.q()[5];
  jog_for(rig, 6, 100, 15.0);
  rig.run_to(rig.sim.time_s() + 0.5);
  const double up = rig.sim.q()[5] - start;
  jog_for(rig, 6, -100, 30.0);
  rig.run_to(rig.sim.time_s() + 0.5);
  const double down = rig.sim.q()[5] - start;
  const double travel = arm::deg_to_rad(config::kJogUnhomedTravel_deg);
  std::printf("J6 jogged before homing: up to %+.1f deg, down to %+.1f deg from its start (travel %d deg)\n", 180 / arm::kPi * up,
              180 / arm::kPi * down, config::kJogUnhomedTravel_deg);
  EXPECT_GT(up, travel - 0.02);
  EXPECT_LT(up, travel + 0.01);
  EXPECT_LT(down, -travel + 0.02);
  EXPECT_GT(down, -travel - 0.01);
  EXPECT_EQ(rig.last().faults, 0u);
}

// Before homing a DC joint's switch closing in a jog means its pot reads wrong (its angle is the
// pot's): the arm stops with limit_unexpected, where the jog would otherwise stop at the switch
// without a word. J4's pot calibrated 10 deg off (it reads 10 deg low), jogged up.
TEST(BringUp, AJogOntoADcSwitchBeforeHomingNamesThePot) {
  app::Settings s{};
  constexpr int16_t kTenDeg_counts_x16 = 461;  // J4: 320 deg over 14,745 counts x 16
  s.pot_at_min_counts_x16[2] = 819 + kTenDeg_counts_x16;
  s.pot_at_max_counts_x16[2] = 15564 + kTenDeg_counts_x16;
  s.pot_calibrated = 0x04;
  Rig rig(kFirmware);
  rig.sim.set_eeprom(test::settings_block(s));
  ASSERT_GE(rig.run_until_state(core::ArmState::wait_home, 10.0), 0);
  for (int k = 0; k < 40 && rig.state() != core::ArmState::fault; ++k) jog_for(rig, 4, 100, 1.0);
  rig.run_to(rig.sim.time_s() + 0.5);
  const double q4 = rig.sim.q()[3];
  std::printf("J4 jogged up with its pot 10 deg low: state %s, faults %s, J4 at %.2f deg (switch at 160, hard stop 163)\n",
              core::to_string(rig.state()), telemetry::fault_names(rig.last().faults).empty() ? "none" : telemetry::fault_names(rig.last().faults)[0].c_str(),
              180 / arm::kPi * q4);
  EXPECT_EQ(rig.state(), core::ArmState::fault);
  EXPECT_TRUE(rig.last().faults & core::fault_mask(core::kFaultBitLimitUnexpected));
  EXPECT_LT(q4, arm::deg_to_rad(162.0)) << "J4 ran on towards its hard stop";
}

}  // namespace
