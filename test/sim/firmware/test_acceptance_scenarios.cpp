// The acceptance scenarios (docs/design.md) S4, S6, S8 and S9: the firmware ELF against the virtual arm.
// What the firmware says comes from its telemetry; whether the arm moved, and whether a limit
// switch closed, from the plant (true joint angles, the switch contacts).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "config/control_config.h"
#include "config/joints_config.h"
#include "config/modes_config.h"
#include "config/motion_config.h"
#include "core/faults.h"
#include "core/resolved_rate.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;
using test::command;
using test::distance_mm;
using test::kFirmware;
using test::message;
using test::PlantWatch;
using test::Rig;

constexpr double kDeg = arm::kPi / 180;

bool has_fault(const protocol::StateMsg& s, uint8_t bit) { return (s.faults & core::fault_mask(bit)) != 0; }

// A rig in running with its plant watched, at rest with the stick neutral
struct Running {
  Rig rig;
  PlantWatch watch;
  double t_running_s;
  double t_rest_s = -1;  // when the arm came to rest in running, -1: it did not within 2 s
  explicit Running(const plant::Joints& initial_q = test::kNearHome) : rig(kFirmware, initial_q) {
    t_running_s = rig.start(12.0);
    if (t_running_s < 0) return;
    // the steppers' rotors settle behind the last steps of the move to the ready pose (J1: 5
    // mrad in 0.3 s); at rest, no joint moves 0.05 mrad in 0.2 s (a creep of 0.25 mrad/s would)
    for (double t = t_running_s; t < t_running_s + 2.0 && t_rest_s < 0; t += 0.2) {
      const plant::Joints q = rig.sim.q();
      rig.run_to(t + 0.2);
      double moved = 0;
      for (int j = 0; j < 6; ++j) moved = std::max(moved, std::fabs(rig.sim.q()[j] - q[j]));
      if (moved < 5e-5) t_rest_s = rig.sim.time_s();
    }
    watch.reset(rig.sim.q());
    rig.sim.every(0.001, [this](const sim::ArmSimulator& s) { watch.sample(s); });
  }
  bool ok() const { return t_running_s > 0 && t_rest_s > 0; }
  int64_t steps_commanded() const {
    int64_t n = 0;
    for (const sim::StepperCounts& c : rig.sim.measurements().steps) n += c.commanded;
    return n;
  }
};

// The hand twist (base frame, frame-6 origin) that turns joint j alone at rate_rad_s from the
// plant's pose, by central differences of the host's double FK, as a streamed velocity command.
protocol::VelocityCmd joint_twist(const plant::Joints& q, int j, double rate_rad_s) {
  constexpr double h = 1e-6;
  plant::Joints qp = q, qm = q;
  qp[j] += h;
  qm[j] -= h;
  const armsim::TrajectoryRow a = armsim::trajectory_row(0, qp, 0, 0), b = armsim::trajectory_row(0, qm, 0, 0),
                              c = armsim::trajectory_row(0, q, 0, 0);
  // W = dR/dq R^T is the skew matrix of the joint's axis
  double w[3][3] = {};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) w[r][k] += (a.r[3 * r + i] - b.r[3 * r + i]) / (2 * h) * c.r[3 * k + i];
  const double axis[3] = {w[2][1], w[0][2], w[1][0]};
  protocol::VelocityCmd cmd{};
  for (int i = 0; i < 3; ++i) {
    cmd.v_mm_s[i] = (int16_t)std::lround((a.p[i] - b.p[i]) / (2 * h) * rate_rad_s * 1000);
    cmd.w_mrad_s[i] = (int16_t)std::lround(axis[i] * rate_rad_s * 1000);
  }
  return cmd;
}

// S4: every short press moves to the next mode of config::kModeCycle, and the last one back to
// the first; the telemetry shows each mode in turn and no other. The stick is neutral, so
// nothing moves: no step, no drive out of its park, and the gripper's servo still without a pulse
// (it gets one only when the stick first moves in the gripper mode: its first pulse moves it).
TEST(AcceptanceScenarios, S4ShortPressesCycleThroughEveryMode) {
  Running r;
  ASSERT_TRUE(r.ok()) << "running at " << r.t_running_s << " s, at rest at " << r.t_rest_s << " s";
  Rig& rig = r.rig;
  ASSERT_EQ(rig.last().mode, (uint8_t)config::kModeCycle[0]);
  const size_t first_frame = rig.telemetry.states().size();
  const int64_t steps_before = r.steps_commanded();
  const double gripper_before_us = rig.sim.gripper_pulse_us();
  const armsim::TrajectoryRow pose_before = rig.pose();
  double t = r.t_rest_s;
  for (uint8_t press = 1; press <= config::kModeCount; ++press) {
    rig.sim.set_button(true);
    rig.run_to(t += plant::kButtonPressS);
    rig.sim.set_button(false);
    rig.run_to(t += 0.5);
    EXPECT_EQ(rig.last().mode, (uint8_t)config::kModeCycle[press % config::kModeCount]) << "after press " << (int)press;
    EXPECT_EQ(rig.state(), core::ArmState::running);
  }
  // the modes the state frames reported, in order, each once
  std::vector<uint8_t> seen;
  for (size_t i = first_frame; i < rig.telemetry.states().size(); ++i) {
    const uint8_t m = rig.telemetry.states()[i].mode;
    if (seen.empty() || seen.back() != m) seen.push_back(m);
  }
  std::vector<uint8_t> cycle;
  for (uint8_t i = 0; i <= config::kModeCount; ++i) cycle.push_back((uint8_t)config::kModeCycle[i % config::kModeCount]);
  EXPECT_EQ(seen, cycle);
  // nothing moved
  const double hand_mm = distance_mm(rig.pose().p, pose_before.p);
  std::printf("S4: %.2f s of presses, hand moved %.3f mm, largest joint travel %.3f mrad\n", t - r.t_rest_s,
              hand_mm, 1000 * r.watch.largest_travel_rad());
  EXPECT_EQ(r.steps_commanded(), steps_before);
  EXPECT_EQ(gripper_before_us, 0);
  EXPECT_EQ(rig.sim.gripper_pulse_us(), 0);
  EXPECT_LE(hand_mm, 0.1);
  EXPECT_LE(r.watch.largest_travel_rad(), 1e-4);
}

// Streams the velocity command that turns joint j at rate_rad_s, recomputed from the plant's pose
// every 50 ms (the firmware stops after kVelocityTimeout_ms without one), until t_end_s.
void stream_joint(Rig& rig, uint8_t& seq, int j, double rate_rad_s, double t_end_s) {
  static_assert(protocol::kVelocityTimeout_ms > 50, "a command every 50 ms keeps the stream fresh");
  while (rig.sim.time_s() < t_end_s - 1e-9) {
    rig.sim.send_serial(message(joint_twist(rig.sim.q(), j, rate_rad_s), seq++));
    rig.run_to(std::min(rig.sim.time_s() + 0.05, t_end_s));
  }
}

// S6: a stepper joint (J1, towards +90 deg) and a DC joint (J4, towards +160 deg) driven into
// their limits by the streamed velocity command stop inside their soft limits (3 deg inside
// the switches, motion_config.h), no switch closes, no limit_unexpected fault, the arm stays
// running, and driving back moves the joint away.
struct LimitCase {
  int joint;           // 0..5
  double rate_rad_s;   // towards q_max; the twist's hand speed stays within the 0.15 m/s clamp
  double drive_s;      // long enough to reach the soft stop at that rate, with the slow zone
};

class S6 : public ::testing::TestWithParam<LimitCase> {};

TEST_P(S6, DrivingIntoALimitStopsBeforeTheSwitch) {
  const LimitCase c = GetParam();
  Running r;
  ASSERT_TRUE(r.ok());
  Rig& rig = r.rig;
  const size_t first_frame = rig.telemetry.states().size();
  const double q_start = rig.sim.q()[c.joint];
  const double soft_max_rad = arm::q_max_rad(c.joint) - config::kSoftLimitMargin_deg * kDeg;
  uint8_t seq = 1;
  stream_joint(rig, seq, c.joint, c.rate_rad_s, r.t_rest_s + c.drive_s);
  const double q_stop = rig.sim.q()[c.joint];
  const double q_peak = r.watch.q_max[c.joint];
  // still pushing for another second: it stays stopped
  stream_joint(rig, seq, c.joint, c.rate_rad_s, rig.sim.time_s() + 1.0);
  const double q_pushed = rig.sim.q()[c.joint];
  std::printf("S6 J%d: from %.2f deg, stopped at %.3f deg (peak %.3f, after 1 s more push %.3f), soft limit %.1f, switch %.1f\n",
              c.joint + 1, q_start / kDeg, q_stop / kDeg, q_peak / kDeg, q_pushed / kDeg, soft_max_rad / kDeg,
              arm::q_max_rad(c.joint) / kDeg);
  // it got there, and no further than the soft limit (1 deg: the DC joint's PID, the homing's accuracy)
  EXPECT_GT(q_stop, soft_max_rad - 1.0 * kDeg);
  EXPECT_LT(r.watch.q_max[c.joint], soft_max_rad + 1.0 * kDeg);
  EXPECT_LT(std::fabs(q_pushed - q_stop), 1e-3) << "a joint at its soft limit moves no further";
  EXPECT_FALSE(r.watch.at_limit) << "a joint reached its switch's angle";
  EXPECT_FALSE(r.watch.switch_closed);
  bool slowed = false;
  for (size_t i = first_frame; i < rig.telemetry.states().size(); ++i) {
    const protocol::StateMsg& s = rig.telemetry.states()[i];
    EXPECT_EQ(s.state, (uint8_t)core::ArmState::running) << "at " << s.t_ms << " ms";
    EXPECT_FALSE(has_fault(s, core::kFaultBitLimitUnexpected)) << "at " << s.t_ms << " ms";
    EXPECT_EQ(s.switches & 0x3FF, 0) << "at " << s.t_ms << " ms";
    slowed |= (s.slowed_by & core::kSlowSoftLimit) != 0;
  }
  EXPECT_TRUE(slowed) << "telemetry never named the soft limit";
  // driving back for two seconds moves it away at more than half the commanded rate on average
  // (J1 with the arm far out speeds up at its lag's bound, about 0.1 rad/s^2: stop_config.h)
  constexpr double kBack_s = 2.0;
  stream_joint(rig, seq, c.joint, -c.rate_rad_s, rig.sim.time_s() + kBack_s);
  const double back_rad = q_pushed - rig.sim.q()[c.joint];
  std::printf("S6 J%d: driven back %.2f deg in %.0f s at %.2f rad/s\n", c.joint + 1, back_rad / kDeg, kBack_s, c.rate_rad_s);
  EXPECT_GT(back_rad, 0.5 * c.rate_rad_s * kBack_s);
  EXPECT_EQ(rig.state(), core::ArmState::running);
  size_t ok_replies = 0;
  for (const protocol::ReplyMsg& m : rig.telemetry.replies()) ok_replies += m.status == (uint8_t)protocol::ReplyStatus::ok;
  EXPECT_GE(ok_replies + 1, (size_t)(uint8_t)(seq - 1)) << "every velocity command accepted";
}

// J1 from 70 deg: 0.15 rad/s keeps the hand (0.75 m out) near 0.11 m/s; J4 from 50 deg: 0.4
// rad/s moves the hand 0.26 m from the joint at about 0.1 m/s
INSTANTIATE_TEST_SUITE_P(AcceptanceScenarios, S6,
                         ::testing::Values(LimitCase{0, 0.15, 5.0}, LimitCase{3, 0.4, 8.0}),
                         [](const ::testing::TestParamInfo<LimitCase>& i) {
                           return "J" + std::to_string(i.param.joint + 1);
                         });

// A limit switch still closed when the arm is re-armed: the rule "motion into the switch stops
// at once" holds then too. J4's pot reads 10 deg low (a pot slipped on its shaft; here a
// calibration shifted by command), so its soft stop lies past its switch: driven up, J4 closes
// the switch (limit_unexpected), the person re-arms and pushes on the same way. The switch,
// closed when it was armed again, must still stop J4 (driving back off it stays allowed).
TEST(AcceptanceScenarios, SwitchClosedAtTheReArmStillStopsMotionIntoIt) {
  constexpr int kJ4 = 3;
  Running r;
  ASSERT_TRUE(r.ok());
  Rig& rig = r.rig;
  uint8_t seq = 1;
  const auto send = [&](protocol::MsgType type, std::vector<uint8_t> payload) {
    rig.sim.send_serial(command(type, seq++, payload));
    rig.run_to(rig.sim.time_s() + 0.05);
  };
  // J4's pot map 10 deg low: both ends' readings up by 10 deg of its span (drives off for it)
  const int16_t config_min = (int16_t)(config::kPotAtMin_mV * 1024L * 16 / config::kAdcRef_mV);
  const int16_t config_max = (int16_t)(config::kPotAtMax_mV * 1024L * 16 / config::kAdcRef_mV);
  const int16_t shift = (int16_t)((config_max - config_min) * 10 / (arm::q_max_deg[kJ4] - arm::q_min_deg[kJ4]));
  const int16_t at_min = (int16_t)(config_min + shift), at_max = (int16_t)(config_max + shift);
  send(protocol::MsgType::cmd_stop, {});
  send(protocol::MsgType::cmd_pot_calibration,
       {(uint8_t)(kJ4 + 1), (uint8_t)at_min, (uint8_t)(at_min >> 8), (uint8_t)at_max, (uint8_t)(at_max >> 8)});
  ASSERT_EQ(rig.telemetry.calibrations().size(), 1u) << "the calibration accepted";
  send(protocol::MsgType::cmd_rearm, {});
  ASSERT_GT(rig.run_until_state(core::ArmState::running, rig.sim.time_s() + 2.0), 0);
  const double switch_rad = arm::q_max_rad(kJ4);
  // up until the switch stops it
  const double t_up = rig.sim.time_s();
  while (rig.state() == core::ArmState::running && rig.sim.time_s() < t_up + 8.0)
    stream_joint(rig, seq, kJ4, 0.4, rig.sim.time_s() + 0.1);
  ASSERT_EQ(rig.state(), core::ArmState::fault);
  ASSERT_TRUE(has_fault(rig.last(), core::kFaultBitLimitUnexpected));
  rig.run_to(rig.sim.time_s() + 0.5);
  const double q_hit = rig.sim.q()[kJ4];
  ASSERT_TRUE(rig.sim.plant().limit_closed(kJ4, true)) << "J4 at " << q_hit / kDeg << " deg, on its switch";
  // re-armed on the switch, pushed on the same way for 2 s
  send(protocol::MsgType::cmd_rearm, {});
  ASSERT_GT(rig.run_until_state(core::ArmState::running, rig.sim.time_s() + 2.0), 0);
  r.watch.reset(rig.sim.q());
  const size_t first_frame = rig.telemetry.states().size();
  stream_joint(rig, seq, kJ4, 0.4, rig.sim.time_s() + 2.0);
  const auto faults_since = [&](size_t first) {
    uint16_t faults = 0;
    for (size_t i = first; i < rig.telemetry.states().size(); ++i) faults |= rig.telemetry.states()[i].faults;
    return faults;
  };
  const uint16_t faults_pushing = faults_since(first_frame);
  uint8_t slowed_pushing = 0;
  for (size_t i = first_frame; i < rig.telemetry.states().size(); ++i) slowed_pushing |= rig.telemetry.states()[i].slowed_by;
  const double q_pushed = r.watch.q_max[kJ4];
  // and then let go for 3 s (what the drive does against the stop)
  const size_t after_frame = rig.telemetry.states().size();
  rig.run_to(rig.sim.time_s() + 3.0);
  std::printf("switch closed at the re-arm: J4 stopped on its switch at %.2f deg (switch %.1f, hard stop %.1f), pushed on "
              "after the re-arm to %.2f deg, faults then 0x%x; let go 3 s: faults 0x%x, state %s\n",
              q_hit / kDeg, switch_rad / kDeg, switch_rad / kDeg + 3, q_pushed / kDeg, faults_pushing,
              faults_since(after_frame), core::to_string(rig.state()));
  EXPECT_LT(q_pushed, q_hit + 0.5 * kDeg) << "J4 driven on into its closed switch after the re-arm";
  EXPECT_NE(slowed_pushing & core::kSlowLimitSwitch, 0) << "the report says why the motion stopped";
  // a move to a pose from the switch is refused (it would not keep off it); driving back off it
  // is not blocked
  send(protocol::MsgType::cmd_goto_pose, {0});
  EXPECT_EQ(rig.telemetry.replies().back().status, (uint8_t)protocol::ReplyStatus::refused);
  const double q_before_back = rig.sim.q()[kJ4];
  stream_joint(rig, seq, kJ4, -0.4, rig.sim.time_s() + 1.0);
  const double back_rad = q_before_back - rig.sim.q()[kJ4];
  std::printf("then driven back off the switch %.2f deg in 1 s\n", back_rad / kDeg);
  EXPECT_GT(back_rad, 0.2);
  EXPECT_EQ(rig.state(), core::ArmState::running);
  EXPECT_FALSE(rig.sim.plant().limit_closed(kJ4, true));
}

// S8, joystick: unplugged (both axes fall to 0 V) while the stick was full +X in XY. The stick
// must read neutral, so the arm stops as when the stick is let go: beside this run, a second one
// lets go of the stick at the same moment. The stick's output falls the same way in both (to
// within a permille per frame: it ramps down over kStickFall_ms), and the hand stops at the same
// place to within 3 mm (the DC joints settle by stick-slip after a stop, which makes two runs
// differ by a few mm: S1's matter). stick_invalid is reported from 5 ms after the unplugging, as
// a condition, not a latched fault. Plugged back in with the stick still deflected, the hand
// moves no more than the let-go run's (neutral throughout) until the stick has been neutral;
// then it drives again.
TEST(AcceptanceScenarios, S8JoystickUnpluggedStopsAndNeedsNeutral) {
  Running r, released;
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(released.ok());
  Rig& rig = r.rig;
  // (2 s: sideways at the ready pose, far out, J1 speeds up at its lag's bound, stop_config.h)
  const double t_unplug = std::max(r.t_rest_s, released.t_rest_s) + 2.0;
  for (Rig* each : {&rig, &released.rig}) {
    each->sim.set_joystick(1.0, 0.0);
    each->run_to(t_unplug - 0.1);
  }
  const armsim::TrajectoryRow before = rig.pose();
  rig.run_to(t_unplug);
  released.rig.run_to(t_unplug);
  const armsim::TrajectoryRow at_unplug = rig.pose(), at_release = released.rig.pose();
  const double speed_m_s = distance_mm(at_unplug.p, before.p) / 1000 / 0.1;
  EXPECT_GT(speed_m_s, 0.08) << "the hand was moving (J1's stop bounds it to about 0.1 m/s there)";
  const size_t first_frame = rig.telemetry.states().size(), first_released = released.rig.telemetry.states().size();
  rig.sim.set_joystick_unplugged(true);
  released.rig.sim.set_joystick(0.0, 0.0);
  rig.run_to(t_unplug + 1.0);
  released.rig.run_to(t_unplug + 1.0);
  const double unplugged_mm = distance_mm(rig.pose().p, at_unplug.p);
  const double released_mm = distance_mm(released.rig.pose().p, at_release.p);
  std::printf("S8 stick: %.3f m/s; the hand moved %.2f mm after the unplugging, %.2f mm after letting go\n", speed_m_s,
              unplugged_mm, released_mm);
  EXPECT_NEAR(unplugged_mm, released_mm, 3.0);
  const auto& frames = rig.telemetry.states();
  const auto& released_frames = released.rig.telemetry.states();
  ASSERT_GT(frames.size(), first_frame + 20);
  // each frame against the let-go run's nearest in time, within 2 ms (each run sends after its
  // first iteration in a period, and the runs' iterations differ in length). The stick's ramps
  // run in milliseconds, but each run sees the change at the end of its iteration under way:
  // they may start up to two ticks apart, two steps of the fall ramp; frames dt ms apart differ
  // by up to dt steps more.
  const int ramp_step_permille = (int)std::ceil(1000.0 / config::kStickFall_ms);
  size_t compared = 0, k = first_released;
  for (size_t i = first_frame; i < frames.size(); ++i) {
    const protocol::StateMsg& s = frames[i];
    while (k + 1 < released_frames.size() && released_frames[k + 1].t_ms <= s.t_ms) ++k;
    size_t nearest = k;
    if (k + 1 < released_frames.size() && released_frames[k + 1].t_ms - s.t_ms < s.t_ms - released_frames[k].t_ms) nearest = k + 1;
    const int dt_ms = std::abs((int)released_frames[nearest].t_ms - (int)s.t_ms);
    if (dt_ms <= 2) {
      EXPECT_NEAR(s.stick_permille[0], released_frames[nearest].stick_permille[0], (2 + dt_ms) * ramp_step_permille + 1)
          << "at " << s.t_ms << " ms";
      ++compared;
    }
    if (s.t_ms >= 1000 * t_unplug + 5) {
      EXPECT_TRUE(has_fault(s, core::kFaultBitStickInvalid)) << "at " << s.t_ms << " ms";
    }
    EXPECT_EQ(s.state, (uint8_t)core::ArmState::running) << "not a latched fault: running, nothing commanded";
  }
  EXPECT_GT(compared, 40u);
  // plugged back in, still at full +X: nothing moves that the let-go run does not
  rig.sim.set_joystick_unplugged(false);
  const armsim::TrajectoryRow replugged = rig.pose(), released_then = released.rig.pose();
  rig.run_to(t_unplug + 2.0);
  released.rig.run_to(t_unplug + 2.0);
  const double replug_mm = distance_mm(rig.pose().p, replugged.p);
  const double settle_mm = distance_mm(released.rig.pose().p, released_then.p);
  std::printf("S8 stick: plugged back in, deflected: %.3f mm in 1 s (the let-go run: %.3f mm)\n", replug_mm, settle_mm);
  EXPECT_LE(replug_mm, settle_mm + 1.0);
  EXPECT_EQ(rig.last().stick_permille[0], 0);
  // through neutral (for kStickNeutral_ms of control iterations: twice that time, as the loop
  // runs at 800 Hz, not yet the loop's 1 kHz): it drives again
  rig.sim.set_joystick(0.0, 0.0);
  const double t_neutral = t_unplug + 2.0 + 2 * config::kStickNeutral_ms / 1000.0;
  rig.run_to(t_neutral);
  EXPECT_FALSE(has_fault(rig.last(), core::kFaultBitStickInvalid));
  rig.sim.set_joystick(1.0, 0.0);
  const armsim::TrajectoryRow rearmed = rig.pose();
  rig.run_to(t_neutral + 1.0);
  EXPECT_GT(distance_mm(rig.pose().p, rearmed.p), 20.0) << "the stick drives again after neutral";
}

// S8, pot: J3's wiper open (0 V) while the arm holds still: the arm is held, j3_rail is
// reported, nothing moves or is driven, also with the stick deflected and through a re-arm
// while the wire is still open; with the wire mended, a re-arm brings it back to running.
TEST(AcceptanceScenarios, S8PotOpenWireStopsUntilRearmed) {
  Running r;
  ASSERT_TRUE(r.ok());
  Rig& rig = r.rig;
  const double t_open = r.t_rest_s;
  rig.sim.set_pot_fault(2, plant::PotFault::open);  // J3
  rig.run_to(t_open + 0.1);
  EXPECT_EQ(rig.state(), core::ArmState::fault);
  EXPECT_TRUE(has_fault(rig.last(), core::kFaultBitJ2 + 4 * 1 + 3)) << "j3_rail";
  EXPECT_TRUE(rig.sim.bridges_off());
  EXPECT_TRUE(rig.sim.drivers_enabled()) << "the steppers held";
  const int64_t steps = r.steps_commanded();
  const plant::Joints q_fault = rig.sim.q();
  r.watch.reset(q_fault);
  rig.sim.set_joystick(1.0, 0.0);
  rig.run_to(t_open + 1.0);
  rig.sim.set_joystick(0.0, 0.0);
  rig.run_to(t_open + 1.6);
  rig.sim.send_serial(command(protocol::MsgType::cmd_rearm, 1));  // the wire still open
  rig.run_to(t_open + 2.5);
  EXPECT_EQ(rig.state(), core::ArmState::fault);
  EXPECT_FALSE(r.watch.driven) << "an output came on while the pot was open";
  EXPECT_EQ(r.steps_commanded(), steps);
  // The worm-geared DC joints hold still with their bridges braking, the steppers on their
  // drivers' holding current, at rest on their last microstep.
  for (int j = 0; j < 6; ++j) {
    const bool stepper = j == 0 || j == 4 || j == 5;
    const double allowed_rad = stepper ? 2 * arm::kPi / plant::kFullStepsPerRev / plant::kMicrosteps / plant::kGearRatio[j] : 1e-4;
    std::printf("S8 pot: J%d travelled %.4f mrad in fault (allowed %.4f)\n", j + 1, 1000 * r.watch.travel_rad(j),
                1000 * allowed_rad);
    EXPECT_LE(r.watch.travel_rad(j), allowed_rad) << "J" << j + 1;
  }
  rig.sim.set_pot_fault(2, plant::PotFault::ok);
  rig.run_to(t_open + 2.6);
  rig.sim.send_serial(command(protocol::MsgType::cmd_rearm, 2));
  EXPECT_GT(rig.run_until_state(core::ArmState::running, t_open + 4.0), 0) << "re-arm with the wire mended";
}

// S8, pot, every DC joint (J2 and J4 run their servos in the other tick from J3's): an open and
// a shorted wiper each stop the arm within 0.1 s, with that joint's rail or jump fault, and
// nothing driven.
TEST(AcceptanceScenarios, S8EveryPotFaultStopsTheArm) {
  for (int d = 0; d < 3; ++d) {
    for (plant::PotFault fault : {plant::PotFault::open, plant::PotFault::shorted}) {
      SCOPED_TRACE("J" + std::to_string(d + 2) + (fault == plant::PotFault::open ? " open" : " shorted"));
      Running r;
      ASSERT_TRUE(r.ok());
      Rig& rig = r.rig;
      const double t_fault = rig.sim.time_s();
      rig.sim.set_pot_fault(d + 1, fault);  // the plant's joint index
      rig.run_to(t_fault + 0.1);
      EXPECT_EQ(rig.state(), core::ArmState::fault);
      EXPECT_TRUE(has_fault(rig.last(), core::kFaultBitJ2 + 4 * d + 3) || has_fault(rig.last(), core::kFaultBitJ2 + 4 * d + 2))
          << "its rail or jump";
      EXPECT_TRUE(rig.sim.bridges_off());
      EXPECT_TRUE(rig.sim.drivers_enabled()) << "the steppers held";
    }
  }
}

// S9: 1 MiB of random bytes (fixed seed) into the serial link, 91 s at 115200 baud, while
// the arm runs at rest with the stick neutral; the same length of time without them beside it.
// No reset, running throughout, state frames throughout, no step, the hand and the joints as
// still as in the quiet run (and physically still: 0.1 mm, 0.1 mrad), the link still answers.
TEST(AcceptanceScenarios, S9SerialGarbageNeverMovesNorResets) {
  constexpr size_t kBytes = 1 << 20;
  std::vector<uint8_t> garbage(kBytes);
  std::mt19937 random(20240901);
  for (uint8_t& b : garbage) b = (uint8_t)random();
  const double flood_s = kBytes * 10.0 / 115200;

  Running quiet;
  ASSERT_TRUE(quiet.ok());
  const armsim::TrajectoryRow quiet_start = quiet.rig.pose();
  quiet.rig.run_to(quiet.t_rest_s + flood_s + 0.5);
  const double quiet_mm = distance_mm(quiet.rig.pose().p, quiet_start.p);

  Running r;
  ASSERT_TRUE(r.ok());
  Rig& rig = r.rig;
  const size_t first_frame = rig.telemetry.states().size();
  const armsim::TrajectoryRow start = rig.pose();
  const int64_t steps = r.steps_commanded();
  rig.sim.send_serial(garbage);
  rig.run_to(r.t_rest_s + flood_s + 0.5);
  const sim::Measurements m = rig.sim.measurements();
  const double hand_mm = distance_mm(rig.pose().p, start.p);
  std::printf("S9: %.1f s of garbage, %llu bytes in, %llu dropped; hand %.4f mm (quiet run %.4f mm), joints %.4f mrad "
              "(quiet %.4f)\n",
              flood_s, (unsigned long long)m.uart_rx_bytes, (unsigned long long)m.uart_rx_dropped, hand_mm, quiet_mm,
              1000 * r.watch.largest_travel_rad(), 1000 * quiet.watch.largest_travel_rad());
  EXPECT_TRUE(m.resets.empty());
  EXPECT_EQ(rig.telemetry.boots().size(), 1u);
  EXPECT_EQ(r.steps_commanded(), steps);
  EXPECT_FALSE(r.watch.switch_closed);
  EXPECT_LE(hand_mm, 0.1);
  EXPECT_LE(r.watch.largest_travel_rad(), 1e-4);
  EXPECT_LE(std::fabs(hand_mm - quiet_mm), 0.05);
  // state frames all the way through, all running, their gaps as in the quiet run
  uint32_t widest_gap_ms = 0, quiet_gap_ms = 0;
  for (size_t i = first_frame + 1; i < rig.telemetry.states().size(); ++i) {
    const protocol::StateMsg& s = rig.telemetry.states()[i];
    EXPECT_EQ(s.state, (uint8_t)core::ArmState::running) << "at " << s.t_ms << " ms";
    widest_gap_ms = std::max(widest_gap_ms, s.t_ms - rig.telemetry.states()[i - 1].t_ms);
  }
  for (size_t i = 1; i < quiet.rig.telemetry.states().size(); ++i)
    quiet_gap_ms = std::max(quiet_gap_ms, quiet.rig.telemetry.states()[i].t_ms - quiet.rig.telemetry.states()[i - 1].t_ms);
  EXPECT_LE(widest_gap_ms, quiet_gap_ms + 5);
  EXPECT_EQ(rig.telemetry.stream().parser().crc_errors(), 0) << "the firmware's own frames stay intact";
  EXPECT_EQ(rig.telemetry.stream().seq_gaps(), 0u);
  EXPECT_GT(rig.last().rx_crc_errors + rig.last().rx_framing_errors, 1000) << "the firmware counted the garbage";
  EXPECT_GE(rig.last().t_ms, (uint32_t)(1000 * (r.t_rest_s + flood_s)));
  // the link still answers: a mode command after the flood
  const size_t replies = rig.telemetry.replies().size();
  const uint8_t xz[] = {(uint8_t)config::Mode::xz};
  rig.sim.send_serial(command(protocol::MsgType::cmd_mode, 7, {xz[0]}));
  rig.run_to(rig.sim.time_s() + 0.1);
  ASSERT_GT(rig.telemetry.replies().size(), replies);
  EXPECT_EQ(rig.telemetry.replies().back().command_seq, 7);
  EXPECT_EQ(rig.telemetry.replies().back().status, (uint8_t)protocol::ReplyStatus::ok);
  EXPECT_EQ(rig.last().mode, (uint8_t)config::Mode::xz);
}

// A flood of commands: 250 as fast as the line takes them, speed_scale setting the scale the
// arm already has (so nothing moves), every 10th get_calibration, each with a reply. The
// replies (10 bytes for 8 in) and the state frames outrun the line, the transmit buffer fills
// and the firmware drops frames: each one dropped must show as a frame missing by seq
// (docs/telemetry.md), so the frames missing by number are the replies that did not come plus
// the state frames missing by time. A calibration frame that finds the buffer full is sent
// later: it leaves no gap. The arm stays running and still, no fault, no reset, nothing
// refused, no tick overrun, and the link answers after.
TEST(AcceptanceScenarios, ACommandFloodDropsFramesEachMissingBySeq) {
  constexpr int kCommands = 250;  // their seqs 0..249: one each, in order
  Running r;
  ASSERT_TRUE(r.ok());
  Rig& rig = r.rig;
  const protocol::StateMsg before = rig.last();
  const size_t first_state = rig.telemetry.states().size(), first_reply = rig.telemetry.replies().size();
  const size_t first_calibration = rig.telemetry.calibrations().size();
  const uint64_t missing_before = rig.telemetry.stream().missing_frames();
  const uint64_t rx_dropped_before = rig.sim.measurements().uart_rx_dropped;
  const int64_t steps = r.steps_commanded();
  const armsim::TrajectoryRow start = rig.pose();
  // one command every 0.75 ms (its 8 bytes take 0.69 ms on the line): back to back, simavr's
  // receive FIFO overflows in a long burst (132 of these 2,000 bytes dropped, uart_rx_dropped)
  constexpr double kCommandEvery_s = 0.75e-3;
  const double t_flood_s = rig.sim.time_s();
  for (int k = 0; k < kCommands; ++k) {
    rig.sim.send_serial(k % 10 == 9 ? command(protocol::MsgType::cmd_get_calibration, (uint8_t)k)
                                    : command(protocol::MsgType::cmd_speed_scale, (uint8_t)k, {before.speed_scale_pct}));
    rig.run_to(t_flood_s + (k + 1) * kCommandEvery_s);
  }
  rig.run_to(rig.sim.time_s() + 0.5);

  const std::vector<protocol::ReplyMsg>& replies = rig.telemetry.replies();
  const int replied = (int)(replies.size() - first_reply);
  for (size_t i = first_reply; i < replies.size(); ++i) {
    EXPECT_EQ(replies[i].command_type, (uint8_t)(replies[i].command_seq % 10 == 9 ? protocol::MsgType::cmd_get_calibration
                                                                                  : protocol::MsgType::cmd_speed_scale));
    EXPECT_EQ(replies[i].status, (uint8_t)protocol::ReplyStatus::ok) << "command " << (int)replies[i].command_seq;
    if (i > first_reply) {
      EXPECT_GT(replies[i].command_seq, replies[i - 1].command_seq) << "in order, each once";
    }
  }
  // state frames missing by time: each is due 20 ms after the one before (sent at the first
  // iteration at or past that, a ms or two late at rest)
  const std::vector<protocol::StateMsg>& states = rig.telemetry.states();
  uint64_t states_missing = 0;
  for (size_t i = first_state; i < states.size(); ++i) {
    const uint32_t dt_ms = states[i].t_ms - states[i - 1].t_ms;
    states_missing += (dt_ms + protocol::kStatePeriod_ms / 2) / protocol::kStatePeriod_ms - 1;
    EXPECT_EQ(states[i].state, (uint8_t)core::ArmState::running) << "at " << states[i].t_ms << " ms";
    EXPECT_FALSE(has_fault(states[i], core::kFaultBitLoopOverrun)) << "a tick overrun, at " << states[i].t_ms << " ms";
  }
  const uint64_t missing_by_seq = rig.telemetry.stream().missing_frames() - missing_before;
  const size_t calibrations = rig.telemetry.calibrations().size() - first_calibration;
  std::printf("command flood: %d commands, %d replies, %zu calibration frames, %llu state frames missing by time, "
              "%llu frames missing by seq\n",
              kCommands, replied, calibrations, (unsigned long long)states_missing, (unsigned long long)missing_by_seq);
  // one for each get_calibration, or one for several while it waited for room
  EXPECT_GE(calibrations, 1u);
  EXPECT_LE(calibrations, (size_t)kCommands / 10);
  EXPECT_LT(replied, kCommands) << "the flood outran the line: replies were dropped";
  EXPECT_EQ(rig.sim.measurements().uart_rx_dropped, rx_dropped_before) << "every command reached the firmware";
  EXPECT_EQ(missing_by_seq, (uint64_t)(kCommands - replied) + states_missing) << "each frame dropped is a gap";
  // nothing else happened
  EXPECT_TRUE(rig.sim.measurements().resets.empty());
  EXPECT_EQ(rig.telemetry.boots().size(), 1u);
  EXPECT_EQ(rig.last().faults, 0u);
  EXPECT_EQ(rig.last().mode, before.mode);
  EXPECT_EQ(rig.last().speed_scale_pct, before.speed_scale_pct);
  EXPECT_EQ(rig.last().rx_crc_errors, before.rx_crc_errors);
  EXPECT_EQ(rig.last().rx_rejected, before.rx_rejected);
  EXPECT_EQ(r.steps_commanded(), steps);
  EXPECT_LE(distance_mm(rig.pose().p, start.p), 0.1);
  EXPECT_LE(r.watch.largest_travel_rad(), 1e-4);
  // the link still answers
  rig.sim.send_serial(command(protocol::MsgType::cmd_stop, 7));
  rig.run_to(rig.sim.time_s() + 0.1);
  ASSERT_GT(rig.telemetry.replies().size(), first_reply + replied);
  EXPECT_EQ(rig.telemetry.replies().back().command_seq, 7);
  EXPECT_EQ(rig.state(), core::ArmState::stopped);
}

// The same flood while the stick drives the hand in XY (issue 30, finding 9: one overran a
// tick): no tick overruns, no state frame from the flood's first byte to 0.5 s after its last
// reports loop_overrun (reported for 500 ms after each). (Each command put the whole report
// together for its reply, ~2,500 cycles: 24 of the 25 state frames reported overruns.)
TEST(AcceptanceScenarios, ACommandFloodWhileTheStickDrivesOverrunsNoTick) {
  Running r;
  ASSERT_TRUE(r.ok());
  Rig& rig = r.rig;
  rig.sim.set_joystick(0.7, 0.3);
  rig.run_to(rig.sim.time_s() + 0.5);
  const size_t first_state = rig.telemetry.states().size();
  const uint8_t scale_pct = rig.last().speed_scale_pct;
  const double t_flood_s = rig.sim.time_s();
  for (int k = 0; k < 250; ++k) {
    rig.sim.send_serial(k % 10 == 9 ? command(protocol::MsgType::cmd_get_calibration, (uint8_t)k)
                                    : command(protocol::MsgType::cmd_speed_scale, (uint8_t)k, {scale_pct}));
    rig.run_to(t_flood_s + (k + 1) * 0.75e-3);
  }
  rig.run_to(rig.sim.time_s() + 0.5);
  rig.sim.set_joystick(0.0, 0.0);
  const std::vector<protocol::StateMsg>& states = rig.telemetry.states();
  size_t overrun = 0;
  for (size_t i = first_state; i < states.size(); ++i) {
    overrun += has_fault(states[i], core::kFaultBitLoopOverrun);
    EXPECT_EQ(states[i].state, (uint8_t)core::ArmState::running) << "at " << states[i].t_ms << " ms";
  }
  std::printf("command flood while the stick drives: %zu state frames, %zu of them with loop_overrun\n",
              states.size() - first_state, overrun);
  EXPECT_GE(states.size() - first_state, 20u);  // (the replies outrun the line: frames are dropped)
  EXPECT_EQ(overrun, 0u);
}

}  // namespace
