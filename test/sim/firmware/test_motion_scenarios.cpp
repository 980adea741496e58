// The motion scenarios of docs/design.md against the firmware ELF in the simulator: S1 and S2 (the hand
// along an axis at full stick) and S3 (the wrist turning about a still frame-6 origin); S7 is
// test_singularity_scenario.cpp. The figures come from the plant's true joint angles
// (trajectory rows, 100 per second); the firmware's view from its telemetry.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "firmware_rig.h"
#include "turn_pose.h"
#include "armsim/firmware_telemetry.h"
#include "armsim/run.h"
#include "config/motion_config.h"
#include "config/joints_config.h"
#include "core/joint_map.h"
#include "core/resolved_rate.h"
#include "core/supervisor.h"

namespace {

using namespace wmra;
using armsim::TrajectoryRow;

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
// near the homing switches: start-up (`home` at test::kHomeAt_s, homing, the move to the ready
// pose at most at the stick's speed) ends in running at about 7.5 s
const std::string kInit = "init 1.45 0.3 -1.0 0.6 -1.45 0.05\n";
// The scenarios below are written in times from kLater_s on: run() shifts their events, at()
// its queries, by it (the start-up takes that much longer than the times were first set for)
constexpr double kLater_s = 2.5;
constexpr double kStickAt_s = 6.0;  // every scenario's first stick input, in running
constexpr double kHandSpeed_m_s = 0.15, kWristSpeed_rad_s = 0.8;

struct ScenarioRun {
  armsim::RunResult result;
  armsim::FirmwareTelemetry telemetry;
  const TrajectoryRow& at(double t_s) const {  // the row at t + kLater_s (rows every 10 ms from 0)
    const size_t i = (size_t)std::lround((t_s + kLater_s) * 100);
    return result.trajectory.at(i < result.trajectory.size() ? i : result.trajectory.size() - 1);
  }
};

// every event line's time kLater_s later
std::string later(const std::string& events) {
  std::string out;
  size_t at = 0;
  while (at < events.size()) {
    const size_t end = events.find('\n', at);
    const std::string line = events.substr(at, end == std::string::npos ? std::string::npos : end - at);
    at = end == std::string::npos ? events.size() : end + 1;
    if (line.empty()) continue;
    char* rest = nullptr;
    const double t = std::strtod(line.c_str(), &rest);
    char time[32];
    std::snprintf(time, sizeof time, "%.4f", t + kLater_s);
    out += time + std::string(rest) + "\n";
  }
  return out;
}

// init: the first scenario line (the true joint angles at power-up); eeprom: what the firmware
// finds there (empty: blank, so the ready pose is joints_config.h's)
void run(const std::string& events, ScenarioRun& r, const std::string& init = kInit, const std::vector<uint8_t>& eeprom = {},
         uint64_t noise_seed = 1, double stick_at_s = kStickAt_s) {
  armsim::RunOptions options;
  options.elf = kFirmware;
  options.plant.seed = noise_seed;
  options.telemetry = &r.telemetry;
  options.eeprom = eeprom;
  r.result = armsim::run_scenario(armsim::parse_scenario(init + test::home_event() + later(events)), options);
  ASSERT_TRUE(r.result.completed);
  ASSERT_EQ(r.at(stick_at_s).state, (int)core::ArmState::running) << "not running when the stick moves";
  for (int k = 0; k < 3; ++k) EXPECT_EQ(r.result.measurements.steps[k].lost, 0) << "stepper " << k;
  std::string faults;
  for (const std::string& f : r.result.faults) faults += f + " ";
  EXPECT_TRUE(r.result.faults.empty()) << "faults reported: " << faults;
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// the angle of the rotation that takes the hand's orientation at a to that at b: from the
// trace of Ra^T Rb
double turned_rad(const TrajectoryRow& a, const TrajectoryRow& b) {
  double trace = 0;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) trace += a.r[3 * k + i] * b.r[3 * k + i];
  return std::acos(std::max(-1.0, std::min(1.0, (trace - 1) / 2)));
}

// After the stick is let go at t_release (it falls in 150 ms, so the hand stops some 10-20 mm
// further along its way): how far the hand leaves its line (axis < 0: its place) within 1 s,
// and how far it still moves after 0.3 s (from where it is at 1 s). Reported, not gated.
void report_after_release(const ScenarioRun& r, double t_release, int axis) {
  double off_mm = 0, late_mm = 0;
  const TrajectoryRow& at_release = r.at(t_release);
  const TrajectoryRow& end = r.at(t_release + 1.0);
  for (double t = t_release; t <= t_release + 1.0; t += 0.01) {
    const TrajectoryRow& row = r.at(t);
    for (int k = 0; k < 3; ++k)
      if (k != axis) off_mm = std::max(off_mm, 1000 * std::fabs(row.p[k] - at_release.p[k]));
    if (t >= t_release + 0.3) late_mm = std::max(late_mm, 1000 * distance(row.p, end.p));
  }
  std::printf("after release: off its line %.2f mm, moving after 0.3 s %.2f mm\n", off_mm, late_mm);
  ::testing::Test::RecordProperty("after_release_off_mm", std::to_string(off_mm));
  ::testing::Test::RecordProperty("after_release_late_mm", std::to_string(late_mm));
}

// S1/S2: full stick along `axis` (0 x, 1 y, 2 z) from t0 to t0 + 2 s. After the stick's ramp
// (0.3 s) and the arm's (0.2 s) the hand moves at 0.15 m/s +-5 % (mean over the last 1.5 s), the
// other two coordinates stay within 5 mm and the orientation within 1 deg of the start.
void expect_straight_line(const ScenarioRun& r, double t0, int axis) {
  const TrajectoryRow& start = r.at(t0);
  const double t_ramped = t0 + 0.5, t_end = t0 + 2.0;
  const double v = (r.at(t_end).p[axis] - r.at(t_ramped).p[axis]) / (t_end - t_ramped);
  EXPECT_NEAR(v, kHandSpeed_m_s, 0.05 * kHandSpeed_m_s);
  double off_axis_mm = 0, turned_deg = 0;
  for (double t = t0; t <= t_end + 0.3; t += 0.01) {
    const TrajectoryRow& row = r.at(t);
    for (int k = 0; k < 3; ++k)
      if (k != axis) off_axis_mm = std::max(off_axis_mm, 1000 * std::fabs(row.p[k] - start.p[k]));
    turned_deg = std::max(turned_deg, turned_rad(start, row) * 180 / M_PI);
  }
  EXPECT_LE(off_axis_mm, 5.0);
  EXPECT_LE(turned_deg, 1.0);
  std::printf("hand %.4f m/s, off the axis %.2f mm, turned %.3f deg\n", v, off_axis_mm, turned_deg);
  ::testing::Test::RecordProperty("hand_speed_m_s", std::to_string(v));
  ::testing::Test::RecordProperty("off_axis_mm", std::to_string(off_axis_mm));
  ::testing::Test::RecordProperty("turned_deg", std::to_string(turned_deg));
}

// S1 and S2 start 0.14 m nearer the base than the ready pose (stick -Y for 1 s first), where the
// lines are within the arm's reach. From the ready pose itself, S1's 2 s at 0.15 m/s along +x
// stretch the arm into the elbow's singular band (|sin q3| 0.52 after 1.5 s, 0.23 after 1.75 s):
// J3 would need 0.88 rad/s after 1.5 s (its drive's plan there: 0.81) and 2.1 after 1.75 s (its
// limit: 1.0), and the firmware rightly slowed the hand to 0.138 m/s (slowed_by drive_load),
// 10 mm off the axis; S1 asks for the line from a non-singular pose. S2 from the ready pose
// has J2 lift arm and payload (69 % holding duty) at 99 % of the speed its drive plans, 96 % duty
// at speed and more than full duty while the stick ramps up, so J2 fell 16 mrad behind and the
// hand turned by 0.8-1.2 deg depending on the loop's timing. From 0.14 m nearer, both 0.3 m
// lines keep |sin q3| >= 0.84 and every joint within 62 % (S1) and 73 % (S2) of its speed limit
// and of its drive's planned speed.
constexpr const char* kPullIn = "6.0 joystick 0 -1\n7.0 joystick 0 0\n";  // in XY, 0.14 m towards the base

// Where the stick's first sample falls within the ticks moves with every change of the code, and
// the arm's path is chaotic in its start state: a DC joint that stops a count earlier or later
// (stiction, a self-locking worm, a pot read in counts) changes everything after it, so two
// builds that differ only in cycles, or two noise seeds, start S1 from poses a few mrad apart
// (a 185-cycle delay after the iteration made the plant's angles differ from 0.86 s on and by
// 5.5 mrad at 8 s). A line held at one start is one draw: S1, S2 and S3-R2 run at noise seeds 1..4 with
// the stick at 8 s, and at seed 1 with its start (and release) shifted by 2, 5 and 6 x 1.3 ms
// (the figures still from t0 = 8 s); every run must meet S1's and S2's figures (docs/design.md). Over seeds 1..32, S1 measured
// 3.46-4.57 mm off its axis; before the DC joints' friction compensation followed the motion and
// the stick's fall took 300 ms, 3.89-5.41 (four seeds over 5 mm), while seed 1 alone passed.
struct Start {
  int shift;
  uint64_t noise_seed;
};
constexpr Start kStarts[] = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {2, 1}, {5, 1}, {6, 1}};
constexpr double kShiftStep_s = 0.0013;

// a settings block with the ready pose start-up goes to
std::vector<uint8_t> settings_with_ready_pose(const double (&q_deg)[6]) {
  app::Settings settings{};
  const int16_t at_min = (int16_t)(config::kPotAtMin_mV * 1024L * 16 / config::kAdcRef_mV);
  const int16_t at_max = (int16_t)(config::kPotAtMax_mV * 1024L * 16 / config::kAdcRef_mV);
  for (int d = 0; d < 3; ++d) {
    settings.pot_at_min_counts_x16[d] = at_min;
    settings.pot_at_max_counts_x16[d] = at_max;
  }
  for (int j = 0; j < 6; ++j) settings.pose_angle[0][j] = (int32_t)std::llround(q_deg[j] * M_PI / 180 * core::kAngleCountsPerRad);
  settings.pose_valid = 1;
  return test::settings_block(settings);
}

// the stick at `stick` from t0 + the shift for 2 s, after `before` (from `init`, with `eeprom`)
void expect_straight_line_at_shifts(const std::string& before, const char* stick, int axis, int mode,
                                    const std::string& init = kInit, const std::vector<uint8_t>& eeprom = {}, double t0 = 8.0) {
  for (const Start& l : kStarts) {
    SCOPED_TRACE("stick shifted by " + std::to_string(l.shift) + " x 1.3 ms, noise seed " + std::to_string(l.noise_seed));
    char events[128];
    std::snprintf(events, sizeof events, "%.4f joystick %s\n%.4f joystick 0 0\n%.1f end\n", t0 + l.shift * kShiftStep_s, stick,
                  t0 + 2.0 + l.shift * kShiftStep_s, t0 + 3.0);
    ScenarioRun r;
    run(before + events, r, init, eeprom, l.noise_seed, before.empty() ? t0 : kStickAt_s);
    EXPECT_EQ(r.at(t0 + 1.0).mode, mode);
    std::printf("shift %d, seed %d: ", l.shift, (int)l.noise_seed);
    expect_straight_line(r, t0, axis);
    report_after_release(r, t0 + 2.0, axis);
  }
}

// S1 starts 0.36 m nearer the base than the ready pose (stick -Y for 2.4 s: 0.55 m from the base
// axis), S2 0.14 m nearer (kPullIn). Along the ready pose's azimuth +X turns J1, and beyond about
// 0.55 m of the base axis with the payload J1 slows the hand below 0.15 m/s so that its stop keeps
// the hand within the stop's 10 mm (config/stop_config.h: 0.133 m/s on S1's line from 0.14 m
// nearer, 0.77 to 0.85 m out): a limit of J1's torque, which S11 tests; S1 tests the line.
TEST(FirmwareMotion, S1FullStickInXYMovesTheHandAlongX) {
  expect_straight_line_at_shifts("6.0 joystick 0 -1\n8.4 joystick 0 0\n", "1 0", 0, 0, kInit, {}, 9.5);
}

TEST(FirmwareMotion, S2FullStickInXZMovesTheHandAlongZ) {
  expect_straight_line_at_shifts(std::string(kPullIn) + "7.5 button press\n", "0 1", 2, 1);
}

// S3: full stick in R1 (then R2): the wrist turns at 0.8 rad/s +-10 % (mean over 1 s after the
// ramps) while the frame-6 origin stays within 5 mm of where it was.
void expect_turn_in_place(const ScenarioRun& r, double t0, double t_end) {
  const double t_ramped = t0 + 0.5;
  const double w = turned_rad(r.at(t_ramped), r.at(t_end)) / (t_end - t_ramped);
  EXPECT_NEAR(w, kWristSpeed_rad_s, 0.1 * kWristSpeed_rad_s);
  double moved_mm = 0;
  for (double t = t0; t <= t_end + 0.3; t += 0.01) moved_mm = std::max(moved_mm, 1000 * distance(r.at(t).p, r.at(t0).p));
  EXPECT_LE(moved_mm, 5.0);
  std::printf("wrist %.4f rad/s, origin moved %.2f mm\n", w, moved_mm);
  ::testing::Test::RecordProperty("wrist_speed_rad_s", std::to_string(w));
  ::testing::Test::RecordProperty("origin_moved_mm", std::to_string(moved_mm));
}

// R1's stick X turns about y5: mostly J5 and J6 (steppers)
TEST(FirmwareMotion, S3FullStickInR1TurnsTheWristAboutTheHand) {
  ScenarioRun r;
  run("6.0 button press\n6.4 button press\n6.8 joystick 1 0\n8.3 joystick 0 0\n8.8 end\n", r);
  EXPECT_EQ(r.at(7.5).mode, 2) << "R1";
  expect_turn_in_place(r, 6.8, 8.3);
  report_after_release(r, 8.3, -1);
}

// R2's stick Y turns about x5. At the ready pose the J4 axis is 0.36 m from the frame-6 origin
// and has to circle it at 0.8 rad/s: that needs qd = (0, 0.72, -0.40, -1.25, 0, -0.46) rad/s, with
// J2 lifting arm and payload at twice the speed its drive plans at that load, and J4 over its
// 1.6 rad/s after 0.25 rad (test_turn_reach.cpp). So S3's R2 starts from a pose where the turn is
// within the arm's reach (turn_pose.h: link 4 folded back, below 48 % of every limit), stored as
// the ready pose that start-up goes to; the stick's start is shifted as in S1 and S2.
TEST(FirmwareMotion, S3FullStickInR2TurnsTheWristAboutTheHand) {
  const double(&pose)[6] = test::kR2Pose_deg;
  // the DC joints at power-up where the pose has them, the steppers near their switches as in kInit
  char init[96];
  std::snprintf(init, sizeof init, "init 1.45 %.4f %.4f %.4f -1.45 0.05\n", pose[1] * M_PI / 180, pose[2] * M_PI / 180,
                pose[3] * M_PI / 180);
  for (const Start& l : kStarts) {
    SCOPED_TRACE("stick shifted by " + std::to_string(l.shift) + " x 1.3 ms, noise seed " + std::to_string(l.noise_seed));
    char events[160];
    // (from 7 s: J1's homing approach at 0.1 rad/s, then J5's 90 deg to the pose)
    std::snprintf(events, sizeof events, "7.0 button press\n7.4 button press\n7.8 button press\n%.4f joystick 0 1\n%.4f joystick 0 0\n10.2 end\n",
                  8.2 + l.shift * kShiftStep_s, 9.7 + l.shift * kShiftStep_s);
    ScenarioRun r;
    run(events, r, init, settings_with_ready_pose(pose), l.noise_seed, 7.0);
    for (int j = 0; j < 6; ++j) EXPECT_NEAR(r.at(8.2).q[j] * 180 / M_PI, pose[j], 1.0) << "at the stored pose: joint " << j + 1;
    EXPECT_EQ(r.at(8.5).mode, 3) << "R2";
    std::printf("shift %d, seed %d: ", l.shift, (int)l.noise_seed);
    expect_turn_in_place(r, 8.2, 9.7);
    report_after_release(r, 9.7, -1);
  }
}

// R2 at the ready pose, out of the arm's reach: the firmware slows the turn and says so, and no
// joint goes faster than its limit. (Before the DC servos' speed governor J4, catching up a lag
// while J2 slowed the turn, reached 1.736 rad/s against its 1.6.) The origin is not held: J2, at
// full duty, falls behind its reference while that accelerates (22-24 mm, reported).
TEST(FirmwareMotion, R2AtTheReadyPoseIsSlowedWithinTheJointLimits) {
  ScenarioRun r;
  run("6.0 button press\n6.4 button press\n6.8 button press\n7.2 joystick 0 1\n8.7 joystick 0 0\n9.2 end\n", r);
  EXPECT_EQ(r.at(7.5).mode, 3) << "R2";
  int slowed = 0, frames = 0;
  for (const protocol::StateMsg& m : r.telemetry.states()) {
    if (m.t_ms < (7.4 + kLater_s) * 1000 || m.t_ms > (8.7 + kLater_s) * 1000) continue;
    ++frames;
    if (m.slowed_by & (core::kSlowDriveLoad | core::kSlowJointSpeed | core::kSlowTracking)) ++slowed;
  }
  EXPECT_GT(frames, 50);
  EXPECT_EQ(slowed, frames) << "the turn slowed, and said so: the drives' load, the joint speed limits, a lagging joint";
  double fastest[6] = {0, 0, 0, 0, 0, 0};
  for (double t = 7.2; t < 9.0; t += 0.01)
    for (int j = 0; j < 6; ++j) fastest[j] = std::max(fastest[j], std::fabs(r.at(t + 0.01).q[j] - r.at(t).q[j]) / 0.01);
  for (int j = 0; j < 6; ++j) {
    std::printf("J%d fastest %.3f rad/s (limit %.2f)\n", j + 1, fastest[j], config::kJointSpeedLimit_crad_s[j] / 100.0);
    EXPECT_LE(fastest[j], 1.05 * config::kJointSpeedLimit_crad_s[j] / 100.0) << "joint " << j + 1;
  }
  double moved_mm = 0;
  for (double t = 7.2; t <= 9.0; t += 0.01) moved_mm = std::max(moved_mm, 1000 * distance(r.at(t).p, r.at(7.2).p));
  std::printf("wrist %.4f rad/s, origin moved %.2f mm\n", turned_rad(r.at(7.7), r.at(8.7)), moved_mm);
  ::testing::Test::RecordProperty("origin_moved_mm", std::to_string(moved_mm));
}

}  // namespace


// Nothing moves that nobody asked to move: once the hand has come to rest after the stick's
// release, no stepper takes a step and no joint turns, for seconds, after motions in each
// mode. (The drift correction's references creep at ~1 mrad/s at rest, about a count of a DC
// pot; a stepper that corrects every step follows them a step forth and back every 50 ms.)
TEST(FirmwareMotion, NothingMovesAtRestAfterTheStick) {
  test::Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0) << "never running";
  double t = t_running + 1.0;
  rig.run_to(t);
  struct Push {
    int presses;  // short presses before it: to the next mode
    double x, y;
  };
  for (const Push& p : {Push{0, 0.6, 0}, Push{0, 0, -1}, Push{0, 0.3, 0.3}, Push{1, 0, 0.6}, Push{1, 0.5, 0}}) {
    for (int i = 0; i < p.presses; ++i) {
      rig.sim.set_button(true);
      rig.run_to(t += plant::kButtonPressS);
      rig.sim.set_button(false);
      rig.run_to(t += 0.3);
    }
    rig.sim.set_joystick(p.x, p.y);
    rig.run_to(t += 2.0);
    rig.sim.set_joystick(0, 0);
    rig.run_to(t += 1.0);  // at rest within 0.7 s of the release (SPEC 5)
    const sim::Measurements before = rig.sim.measurements();
    const plant::Joints q_before = rig.pose().q;
    double moved_rad[6] = {};
    const double t_rest = t;
    for (; t < t_rest + 3.0;) {
      rig.run_to(t += 0.01);
      for (int j = 0; j < 6; ++j) moved_rad[j] = std::max(moved_rad[j], std::fabs(rig.pose().q[j] - q_before[j]));
    }
    const sim::Measurements after = rig.sim.measurements();
    std::printf("at rest after mode %u stick %.1f %.1f: steps J1 %lld J5 %lld J6 %lld; largest turn %.2f %.2f %.2f %.2f %.2f %.2f mrad\n",
                (unsigned)rig.last().mode, p.x, p.y, (long long)(after.steps[0].commanded - before.steps[0].commanded),
                (long long)(after.steps[1].commanded - before.steps[1].commanded),
                (long long)(after.steps[2].commanded - before.steps[2].commanded), 1000 * moved_rad[0], 1000 * moved_rad[1],
                1000 * moved_rad[2], 1000 * moved_rad[3], 1000 * moved_rad[4], 1000 * moved_rad[5]);
    for (int s = 0; s < 3; ++s) EXPECT_EQ(after.steps[s].commanded, before.steps[s].commanded) << "stepper " << s;
    for (int j = 0; j < 6; ++j) EXPECT_LT(moved_rad[j], 1e-3) << "J" << j + 1;
  }
  EXPECT_EQ(rig.state(), core::ArmState::running);
}
