// S13 (docs/design.md): J6 homes by the short way. Its zero switch closes once a turn, so the
// firmware keeps J6's angle at rest in EEPROM and homes to the switch of the turn that angle
// implies; without one, it takes J6 to be within half a turn of 0 and sweeps. Judged on the
// plant's true J6 angle, sampled every millisecond: where J6 ends, how far it rolled, that it
// never left its -360..360 deg range, and that the firmware's angle is the true one. Then what
// the EEPROM holds: the angle across a power cycle, a power loss during its write, how often it
// is written, records of another format or corrupt, a wrist turned while switched off, and J6's
// switch seen where its count says it cannot be.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdio>
#include <string>
#include <vector>

#include "core/faults.h"
#include "core/joint_map.h"
#include "drivers/eeprom_map.h"
#include "firmware_rig.h"
#include "protocol/frame.h"

namespace {

using namespace wmra;
using test::command;
using test::kFirmware;
using test::Rig;

constexpr double kDeg = M_PI / 180;
constexpr double kRange_deg = 360 + 0.06;  // J6's range, and a step of the count's rounding

// J6's angle at rest as the firmware records it (firmware/app/wrist_angle.cpp in the ring of
// firmware/core/record_ring.h): seq, the angle in Angle counts, CRC-16 over a format byte (1),
// seq and angle; little-endian, 8 bytes a slot from eeprom_map::kWristAngleRing
void put_j6_record(std::vector<uint8_t>& eeprom, double deg, int slot, uint16_t seq, uint8_t format = 1) {
  const int32_t angle = (int32_t)std::llround(deg * kDeg * core::kAngleCountsPerRad);
  uint8_t r[8] = {(uint8_t)seq, (uint8_t)(seq >> 8), (uint8_t)angle, (uint8_t)(angle >> 8), (uint8_t)(angle >> 16),
                  (uint8_t)(angle >> 24), 0, 0};
  uint16_t crc = protocol::crc16_update(protocol::kCrcInit, format);
  for (int i = 0; i < 6; ++i) crc = protocol::crc16_update(crc, r[i]);
  r[6] = (uint8_t)crc;
  r[7] = (uint8_t)(crc >> 8);
  std::copy(r, r + 8, eeprom.begin() + eeprom_map::kWristAngleRing + 8 * slot);
}
std::vector<uint8_t> blank_eeprom() { return std::vector<uint8_t>(eeprom_map::kBytes, 0xFF); }
std::vector<uint8_t> eeprom_with_j6(double deg) {
  std::vector<uint8_t> e = blank_eeprom();
  put_j6_record(e, deg, 0, 0);
  return e;
}
// settings whose stored pose 1 is the ready pose with J6 at j6_deg
std::vector<uint8_t> eeprom_with_pose_1(double j6_deg) {
  app::Settings settings{};
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0};
  for (int slot = 0; slot < 4; ++slot)
    for (int j = 0; j < 6; ++j)
      settings.pose_angle[slot][j] = (int32_t)std::llround((slot == 1 && j == 5 ? j6_deg : ready_deg[j]) * kDeg * core::kAngleCountsPerRad);
  settings.pose_valid = 0x03;
  std::vector<uint8_t> e = blank_eeprom();
  const std::vector<uint8_t> block = test::settings_block(settings);
  std::copy(block.begin(), block.end(), e.begin());
  return e;
}

double nearest_turn_deg(double deg) {
  const double z = 360 * std::floor(deg / 360 + 0.5);
  const double other = deg > z ? z + 360 : z - 360;
  return std::fabs(deg - z) == 180 && std::fabs(other) < std::fabs(z) ? other : z;
}

// The true J6 angle every millisecond: how far it rolled since mark(), its extremes since
// power-up and since mark()
struct J6Track {
  double last = 0, rolled = 0, mark_at = 0, farthest = 0, lowest = 0, highest = 0;
  void start(double deg) { last = mark_at = lowest = highest = deg; }
  void mark() {
    mark_at = last;
    rolled = farthest = 0;
  }
  void sample(double deg) {
    rolled += std::fabs(deg - last);
    last = deg;
    farthest = std::max(farthest, std::fabs(deg - mark_at));
    lowest = std::min(lowest, deg);
    highest = std::max(highest, deg);
  }
};

// A rig from J6 at start_deg (the other joints near their switches), with this EEPROM, its J6
// tracked
struct J6Rig {
  Rig rig;
  J6Track track;
  J6Rig(double start_deg, const std::vector<uint8_t>& eeprom) : rig(kFirmware, at(start_deg)) {
    if (!eeprom.empty()) rig.sim.set_eeprom(eeprom);
    track.start(start_deg);
    rig.sim.every(0.001, [this](const sim::ArmSimulator& s) { track.sample(s.q()[5] / kDeg); });
  }
  J6Rig(const plant::Joints& q, const std::vector<uint8_t>& eeprom) : rig(kFirmware, q) {
    rig.sim.set_eeprom(eeprom);
    track.start(q[5] / kDeg);
    rig.sim.every(0.001, [this](const sim::ArmSimulator& s) { track.sample(s.q()[5] / kDeg); });
  }
  static plant::Joints at(double j6_deg) {
    plant::Joints q = test::kNearHome;
    q[5] = j6_deg * kDeg;
    return q;
  }
  double true_deg() const { return rig.sim.q()[5] / kDeg; }
  double firmware_deg() const { return rig.last().q_mrad[5] * 0.001 / kDeg; }
  // runs until one of the states, at most max_s from now; whether it came
  bool run_until(std::initializer_list<core::ArmState> states, double max_s) {
    const double end = rig.sim.time_s() + max_s;
    while (rig.sim.time_s() < end) {
      rig.run_to(rig.sim.time_s() + 0.01);
      for (core::ArmState s : states)
        if (rig.state() == s) return true;
    }
    return false;
  }
};

struct Homing {
  bool recorded = false;         // the boot frame: J6's angle was recorded
  double believed_deg = 0;       // the firmware's J6 while it waits to home (its recorded angle)
  double rolled_deg = 0;         // the true J6's roll while it homed
  double farthest_deg = 0;       // and its largest turn from where it started
  double homed_deg = 0;          // the true J6 where the homing ended
  double ready_rolled_deg = 0;   // the roll of the move to the ready pose
  double end_deg = 0, firmware_end_deg = 0;  // true and the firmware's J6 once running
  double lowest_deg = 0, highest_deg = 0;    // the true J6's extremes from power-up on
  core::ArmState state = core::ArmState::boot;
  uint32_t faults = 0;
};

// Powered up with J6 at start_deg and this EEPROM, asked to home (the host's `home`), run until
// running or a fault
Homing home(J6Rig& r, double max_s = 90) {
  Homing h;
  if (r.rig.ask_home(r.rig.sim.time_s() + 10.0) < 0) return h;
  if (!r.rig.telemetry.boots().empty()) h.recorded = r.rig.telemetry.boots()[0].j6_angle_recorded();
  h.believed_deg = r.firmware_deg();
  r.track.mark();
  r.run_until({core::ArmState::homing}, 1.0);
  r.run_until({core::ArmState::to_ready, core::ArmState::running, core::ArmState::fault}, max_s);
  h.rolled_deg = r.track.rolled;
  h.farthest_deg = r.track.farthest;
  h.homed_deg = r.true_deg();
  r.track.mark();
  r.run_until({core::ArmState::running, core::ArmState::fault}, 20);
  h.ready_rolled_deg = r.track.rolled;
  r.rig.run_to(r.rig.sim.time_s() + 0.5);
  h.end_deg = r.true_deg();
  h.firmware_end_deg = r.firmware_deg();
  h.lowest_deg = r.track.lowest;
  h.highest_deg = r.track.highest;
  h.state = r.rig.state();
  h.faults = r.rig.last().faults;
  return h;
}

void print(const char* what, double start_deg, const Homing& h) {
  std::printf("S13 %s from %7.1f deg: boot %s, believed %7.1f; homing rolled %6.1f deg (farthest %6.1f) to %7.2f; "
              "ready move %5.1f; end true %7.2f firmware %7.2f; range %7.1f..%6.1f; %s\n",
              what, start_deg, h.recorded ? "recorded" : "none", h.believed_deg, h.rolled_deg, h.farthest_deg, h.homed_deg,
              h.ready_rolled_deg, h.end_deg, h.firmware_end_deg, h.lowest_deg, h.highest_deg, core::to_string(h.state));
}

// the ready pose's J6 (0) at the turn J6 homed to; at +-360 deg the soft stop inside it
double ready_j6_deg(double zero_deg) { return zero_deg > 0 ? 357 : zero_deg < 0 ? -357 : 0; }

void expect_homed_to(const Homing& h, double zero_deg, const std::string& what) {
  ASSERT_EQ(h.state, core::ArmState::running) << what;
  EXPECT_NEAR(h.homed_deg, zero_deg, 2.5) << what << ": on the cam of the turn " << zero_deg;
  EXPECT_NEAR(h.end_deg, ready_j6_deg(zero_deg), 0.3) << what << ": the ready pose's J6";
  EXPECT_NEAR(h.firmware_end_deg, h.end_deg, 0.3) << what << ": the firmware knows the true angle";
  EXPECT_GE(h.lowest_deg, -kRange_deg) << what;
  EXPECT_LE(h.highest_deg, kRange_deg) << what;
}

const double kStarts_deg[] = {-350, -200, -100, -10, 0, 10, 100, 200, 350};

// With J6's angle recorded (as a previous run left it): from anywhere in its range J6 homes to
// the turn that angle implies, rolling at most 190 deg. (Before the record, J6 homed
// to the first switch below it: from -10 deg it rolled 348 deg to the true -360 while the
// firmware said 0.)
TEST(S13WristHoming, FromARecordedAngleAcrossTheRange) {
  double largest = 0;
  for (double start : kStarts_deg) {
    J6Rig r(start, eeprom_with_j6(start));
    const Homing h = home(r);
    print("recorded", start, h);
    const std::string what = "from " + std::to_string(start);
    EXPECT_TRUE(h.recorded) << what;
    EXPECT_NEAR(h.believed_deg, start, 0.1) << what << ": the count starts at the recorded angle";
    expect_homed_to(h, nearest_turn_deg(start), what);
    EXPECT_LE(h.rolled_deg + h.ready_rolled_deg, 190) << what;
    largest = std::max(largest, h.rolled_deg + h.ready_rolled_deg);
  }
  std::printf("S13 recorded angle: the largest roll %.1f deg\n", largest);
}

// Without a recorded angle (a new board): J6 within half a turn of 0 homes to 0; from 20 deg off,
// at most about 120 deg of roll in all.
TEST(S13WristHoming, WithoutARecordedAngleFromWithinHalfATurn) {
  double largest = 0;
  for (double start : {-170.0, -100.0, -20.0, -10.0, 0.0, 10.0, 20.0, 100.0, 170.0}) {
    J6Rig r(start, {});
    const Homing h = home(r);
    print("none", start, h);
    const std::string what = "from " + std::to_string(start);
    EXPECT_FALSE(h.recorded) << what;
    expect_homed_to(h, 0, what);
    EXPECT_GT(h.lowest_deg, -358.0) << what;
    EXPECT_LT(h.highest_deg, 358.0) << what;
    if (std::fabs(start) <= 20) {
      EXPECT_LE(h.rolled_deg + h.ready_rolled_deg, 120) << what;
    }
    largest = std::max(largest, h.rolled_deg + h.ready_rolled_deg);
  }
  std::printf("S13 no recorded angle: the largest roll %.1f deg\n", largest);
}

// Beyond half a turn without a recorded angle the firmware cannot tell the turn (the guide has
// the installer set J6 near 0 before the first power-up): it homes to the turn it meets first,
// and never turns J6 beyond its range doing so.
TEST(S13WristHoming, WithoutARecordedAngleBeyondHalfATurnStaysInRange) {
  for (double start : {-350.0, -200.0, 200.0, 350.0}) {
    J6Rig r(start, {});
    const Homing h = home(r);
    print("none, beyond half a turn", start, h);
    EXPECT_GE(h.lowest_deg, -kRange_deg) << start;
    EXPECT_LE(h.highest_deg, kRange_deg) << start;
  }
}

// The angle carried from one run to the next: a run homes J6 near 0, goes to a pose with J6 at
// 200 deg and rests; switched off there, the next power-up finds the angle and homes J6 to 360
// deg, 160 deg away (not to 0, 200 deg the other way, nor to the first switch below).
TEST(S13WristHoming, TheAngleRecordedInOneRunHomesTheNext) {
  J6Rig first(10, eeprom_with_pose_1(200));
  const Homing h1 = home(first);
  ASSERT_EQ(h1.state, core::ArmState::running);
  first.rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));
  first.rig.run_to(first.rig.sim.time_s() + 8.0);  // 200 deg at half J6's speed limit, then its rest
  ASSERT_NEAR(first.true_deg(), 200, 0.5);
  J6Rig second(first.rig.sim.q(), first.rig.sim.eeprom());
  const Homing h2 = home(second);
  print("carried", 200, h2);
  EXPECT_TRUE(h2.recorded);
  EXPECT_NEAR(h2.believed_deg, 200, 0.1);
  expect_homed_to(h2, 360, "carried from 200");
  EXPECT_LE(h2.rolled_deg, 190);
}

// Edges and cams at power-up: J6 resting exactly at the zero cam's edge, on it, at the cam of
// +-360 deg, with a recorded angle and without
TEST(S13WristHoming, J6RestingOnTheSwitchAtPowerUp) {
  for (double start : {2.0, -2.0, 0.5, 358.0, -359.0}) {
    for (bool recorded : {true, false}) {
      if (!recorded && std::fabs(start) > 180) continue;
      J6Rig r(start, recorded ? eeprom_with_j6(start) : std::vector<uint8_t>{});
      const Homing h = home(r);
      print(recorded ? "on the switch, recorded" : "on the switch, none", start, h);
      const std::string what = "from " + std::to_string(start) + (recorded ? " recorded" : " none");
      expect_homed_to(h, nearest_turn_deg(start), what);
      EXPECT_LE(h.rolled_deg, recorded ? 20 : 80) << what;
    }
  }
}

// The safety button while J6 rolls to its turn; released, re-armed and asked again, the homing
// goes on from where J6 stopped: to the same turn, its roll in all as if uninterrupted.
TEST(S13WristHoming, AStopDuringTheHomingThenHomeAgain) {
  J6Rig r(-200, eeprom_with_j6(-200));
  ASSERT_GT(r.rig.ask_home(10.0), 0);
  r.track.mark();
  r.rig.run_to(r.rig.sim.time_s() + 4.0);
  ASSERT_EQ(r.rig.state(), core::ArmState::homing);
  const double at_stop = r.true_deg();
  r.rig.sim.set_estop(true);
  r.rig.run_to(r.rig.sim.time_s() + 1.0);
  EXPECT_EQ(r.rig.state(), core::ArmState::stopped);
  EXPECT_NEAR(r.true_deg(), at_stop, 3.0) << "J6 held where it stopped";
  r.rig.sim.set_estop(false);
  r.rig.run_to(r.rig.sim.time_s() + 0.5);
  r.rig.press_button(test::kLongPress_s);  // the re-arm
  const double rolled_before = r.track.rolled;
  const Homing h = home(r);
  const double in_all = rolled_before + h.rolled_deg + h.ready_rolled_deg;
  std::printf("S13 a stop during the homing from -200 deg at %.1f deg: in all %.1f deg rolled\n", at_stop, in_all);
  expect_homed_to(h, -360, "after the stop");
  EXPECT_LE(in_all, 190);
}

// A stored angle of another format (another firmware's meaning of it) counts as none: the boot
// frame says so and J6 sweeps from within half a turn.
TEST(S13WristHoming, ARecordOfAnotherFormatIsNoAngle) {
  std::vector<uint8_t> e = blank_eeprom();
  put_j6_record(e, 10, 0, 0, 2);
  J6Rig r(10, e);
  const Homing h = home(r);
  print("another format", 10, h);
  EXPECT_FALSE(h.recorded);
  expect_homed_to(h, 0, "another format");
}

// The wrist turned by hand while switched off (or a power loss while it rolled), a corrupt newest
// record leaving an older angle: the switch is not where the angle says, J6 stops within its
// range (homing_failed), the angle is forgotten, and the next power-up, J6 set near 0 as the
// guide says, sweeps and homes.
TEST(S13WristHoming, AWrongAngleStopsJ6AndIsForgotten) {
  struct Case {
    const char* what;
    double recorded_deg, true_deg;
    bool corrupt_newer;  // the right angle recorded after, then corrupted
  };
  const Case cases[] = {{"turned +220 deg by hand", 100, 320, false},
                        {"turned +470 deg by hand", -170, 300, false},
                        {"turned -250 deg by hand", 100, -150, false},
                        {"turned 90 deg by hand", 0, 90, false},
                        {"the newest record corrupt", 10, 150, true}};
  for (const Case& c : cases) {
    std::vector<uint8_t> e = eeprom_with_j6(c.recorded_deg);
    if (c.corrupt_newer) {
      put_j6_record(e, c.true_deg, 1, 1);
      e[eeprom_map::kWristAngleRing + 8 + 3] ^= 0x04;
    }
    J6Rig r(c.true_deg, e);
    const Homing h = home(r, 40);
    print(c.what, c.true_deg, h);
    EXPECT_TRUE(h.recorded) << c.what;
    EXPECT_NEAR(h.believed_deg, c.recorded_deg, 0.1) << c.what;
    EXPECT_EQ(h.state, core::ArmState::fault) << c.what;
    EXPECT_TRUE(h.faults & core::fault_mask(core::kFaultBitHomingFailed)) << c.what;
    EXPECT_GE(h.lowest_deg, -kRange_deg) << c.what;
    EXPECT_LE(h.highest_deg, kRange_deg) << c.what;
    EXPECT_LE(h.rolled_deg, 190) << c.what;
    // again without switching off: J6 does not move
    const double stood = r.true_deg();
    r.rig.press_button(test::kLongPress_s);  // the re-arm
    const Homing again = home(r, 10);
    EXPECT_EQ(again.state, core::ArmState::fault) << c.what;
    EXPECT_NEAR(r.true_deg(), stood, 0.05) << c.what << ": J6 not moved again";
    // switched off, J6 set near 0 by hand: the angle is forgotten, the sweep homes
    r.rig.run_to(r.rig.sim.time_s() + 0.5);  // the record's bytes written
    J6Rig next(8, r.rig.sim.eeprom());
    const Homing after = home(next);
    EXPECT_FALSE(after.recorded) << c.what;
    expect_homed_to(after, 0, std::string(c.what) + ", the power-up after");
  }
}

int ring_bytes_differing(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int n = 0;
  for (int i = eeprom_map::kWristAngleRing; i < eeprom_map::kWristAngleRing + eeprom_map::kWristAngleRingBytes; ++i) n += a[i] != b[i];
  return n;
}

// A power loss while J6's angle is being written (a byte a tick once J6 has rested 1 s):
// the next power-up has the angle recorded before, not a half-written one; with the write done,
// the new one.
TEST(S13WristHoming, APowerLossDuringTheAnglesWriteKeepsTheAngleBefore) {
  J6Rig r(5, eeprom_with_pose_1(90));
  ASSERT_EQ(home(r).state, core::ArmState::running);
  r.rig.run_to(r.rig.sim.time_s() + 2.0);  // J6's rest at the ready pose recorded
  r.rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));
  const std::vector<uint8_t> before = r.rig.sim.eeprom();
  double t = r.rig.sim.time_s();
  const double t_end = t + 8;
  while (ring_bytes_differing(r.rig.sim.eeprom(), before) == 0 && t < t_end) r.rig.run_to(t += 0.001);
  ASSERT_LT(t, t_end) << "J6's angle was written";
  r.rig.run_to(t + 0.004);
  const std::vector<uint8_t> part = r.rig.sim.eeprom();
  r.rig.run_to(t + 1.0);
  const std::vector<uint8_t> whole = r.rig.sim.eeprom();
  const int written = ring_bytes_differing(part, before), to_write = ring_bytes_differing(whole, before);
  std::printf("S13 power loss during the angle's write: %d of its %d bytes written\n", written, to_write);
  EXPECT_GE(written, 1);
  EXPECT_LT(written, to_write) << "the power lost in the middle of the write";
  EXPECT_NEAR(r.true_deg(), 90, 0.5);

  J6Rig lost(r.rig.sim.q(), part);
  lost.rig.run_until_state(core::ArmState::wait_home, 5.0);
  EXPECT_TRUE(lost.rig.telemetry.boots()[0].j6_angle_recorded());
  // (recorded within the rest's band, kJ6RestBand_mdeg: J6's tracking dithers a step or two)
  EXPECT_NEAR(lost.firmware_deg(), 0, 0.5) << "the angle recorded before: J6 at the ready pose";
  J6Rig kept(r.rig.sim.q(), whole);
  kept.rig.run_until_state(core::ArmState::wait_home, 5.0);
  EXPECT_NEAR(kept.firmware_deg(), 90, 0.5) << "the new angle";
  const Homing h = home(kept);
  expect_homed_to(h, 0, "from the new angle");
}

// How often the angle is written: a session of stick use in every mode (pushes of 1.5 s, rests
// of 2.5 s), a long rest, and 30 s of pushes without a pause of 1 s. One record at most per
// rest, none while J6 stands or keeps moving; every write in the ring.
TEST(S13WristHoming, TheAngleIsWrittenOncePerRestNeverInALoop) {
  J6Rig r(0, {});
  ASSERT_EQ(home(r).state, core::ArmState::running);
  r.rig.run_to(r.rig.sim.time_s() + 2.0);
  std::vector<uint8_t> last = r.rig.sim.eeprom();
  long writes = 0, ring_writes = 0;
  r.rig.sim.every(0.001, [&](const sim::ArmSimulator& s) {
    const std::vector<uint8_t> now = s.eeprom();
    for (size_t i = 0; i < now.size(); ++i) {
      if (now[i] == last[i]) continue;
      ++writes;
      ring_writes += (int)i >= eeprom_map::kWristAngleRing;
    }
    last = now;
  });
  // the writes while drive(n) sets the inputs every 50 ms, n = 0, 1, ...
  const auto writes_over = [&](int periods, const std::function<void(int)>& drive) {
    const long at = writes;
    const double t0 = r.rig.sim.time_s();
    for (int n = 0; n < periods; ++n) {
      drive(n);
      r.rig.run_to(t0 + 0.05 * (n + 1));
    }
    return writes - at;
  };
  // 3 minutes of use: each mode in turn, the stick pushed each way for 1.5 s, then 2.5 s of rest
  int rests = 0;
  const double pushes[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  const long use = writes_over(3600, [&](int n) {
    const int k = n / 80, in = n % 80;
    if (in == 0) {
      if (k % 4 == 0) r.rig.sim.send_serial(command(protocol::MsgType::cmd_mode, (uint8_t)k, {(uint8_t)((k / 4) % 4)}));
      ++rests;
    }
    const double* p = pushes[k % 4];
    r.rig.sim.set_joystick(in < 30 ? 0.6 * p[0] : 0, in < 30 ? 0.6 * p[1] : 0);
  });
  const long standing = writes_over(1200, [&](int) { r.rig.sim.set_joystick(0, 0); });
  const long moving = writes_over(600, [&](int n) { r.rig.sim.set_joystick(0, n % 32 < 16 ? 0.5 : -0.5); });
  r.rig.sim.set_joystick(0, 0);
  r.rig.run_to(r.rig.sim.time_s() + 3.0);
  std::printf("S13 EEPROM writes: 3 min of stick use (%d rests) %ld bytes (%.1f a minute, %.1f records a minute), "
              "60 s standing %ld, 30 s moving without a rest %ld; all of them in J6's ring: %s\n",
              rests, use, use / 3.0, use / 3.0 / 8.0, standing, moving, writes == ring_writes ? "yes" : "NO");
  EXPECT_EQ(r.rig.state(), core::ArmState::running);
  EXPECT_GT(use, 0) << "J6 moved and rested";
  EXPECT_LE(use, rests * 8L) << "at most a record (8 bytes) per rest";
  EXPECT_EQ(standing, 0);
  EXPECT_EQ(moving, 0);
  EXPECT_EQ(writes, ring_writes) << "no settings written";
}

// J6 knocked while it stands (its rotor turned 5 electrical periods, 36 deg, its steps lost):
// the next time its zero switch closes, the count is 36 deg from a whole turn: position_lost,
// the arm stops. Re-armed and homed, J6's count is its angle again. (Before the watch, the
// firmware went on 36 deg off, its soft stops with it.)
TEST(S13WristHoming, J6SeenOffItsCountIsAPositionLost) {
  J6Rig r(5, eeprom_with_pose_1(-90));
  ASSERT_EQ(home(r).state, core::ArmState::running);
  r.rig.run_to(r.rig.sim.time_s() + 1.0);
  r.rig.sim.slip_stepper(5, 5);
  r.rig.run_to(r.rig.sim.time_s() + 1.0);
  EXPECT_EQ(r.rig.state(), core::ArmState::running) << "off the cam: nothing seen yet";
  r.rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));  // J6 to -90: past true 0
  r.run_until({core::ArmState::fault}, 8.0);
  std::printf("S13 J6 knocked 36 deg, then rolled past its switch: state %s, faults 0x%x, J6 true %.1f firmware %.1f\n",
              core::to_string(r.rig.state()), r.rig.last().faults, r.true_deg(), r.firmware_deg());
  ASSERT_EQ(r.rig.state(), core::ArmState::fault);
  EXPECT_TRUE(r.rig.last().faults & core::fault_mask(core::kFaultBitPositionLost));
  r.rig.run_to(r.rig.sim.time_s() + 0.5);
  r.rig.press_button(test::kLongPress_s);  // the re-arm: the steppers are not homed
  const Homing h = home(r);
  print("after the lost position", r.true_deg(), h);
  ASSERT_EQ(h.state, core::ArmState::running);
  EXPECT_NEAR(h.firmware_end_deg, h.end_deg, 0.3) << "the count is J6's angle again";
  EXPECT_NEAR(h.end_deg, 0, 0.3);
}

}  // namespace
