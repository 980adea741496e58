// The DC joint plausibility checks (lib/control/plausibility.h): they fire on a stall, a sign
// error, a jump of the reading and a rail, and stay silent on normal motion under the PID.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "control/pid.h"
#include "control/plausibility.h"

using namespace wmra;
using namespace wmra::control;

namespace {

constexpr int kUnits = 16, kRateHz = 500;

PlausibilityConfig monitor_config() {
  return PlausibilityConfig{
      29490,           // 90 % duty counts as saturated drive
      250,             // 0.5 s of it ...
      3 * kUnits,      // ... without 3 counts of progress (noise is 2 p-p): stall
      100,             // 0.2 s to coast out of a reversal (4 time constants)
      5 * kUnits,      // 5 counts against the drive: sign error
      3 * kUnits,      // 0.8 count/sample at full speed, 3 allowed
      8 * kUnits, 1015 * kUnits, 5};
}

// DC joint with ADC noise (+-1 count), a gravity-like load and an optional wrong sign / block
struct Joint {
  double k = 400, tau = 0.05, load = 0.08;
  double pos = 500, vel = 0;
  bool blocked = false;
  double sign = 1;
  std::mt19937 rng{5};
  void step(double duty) {
    const double dt = 1.0 / kRateHz;
    for (int i = 0; i < 10; ++i) {
      vel += (k * (sign * duty - load * std::cos(pos / 300)) - vel) / tau * (dt / 10);
      if (blocked) vel = 0;
      pos += vel * dt / 10;
    }
  }
  int32_t reading() {
    std::uniform_int_distribution<int> noise(-1, 1);
    return (int32_t)std::lround((pos + noise(rng)) * kUnits);
  }
};

Pid make_pid() {
  constexpr PidGainsResult g = pid_gains(Ratio{2, 100}, Ratio{1, 5}, Ratio{1, 10000}, kRateHz, kUnits);
  static_assert(g.ok, "");
  Pid pid;
  EXPECT_EQ(pid.configure(PidConfig{g.gains, 32767, 600, 2000, 50}), PidStatus::ok);
  return pid;
}

}  // namespace

TEST(Plausibility, SilentOnNormalMotion) {
  Joint j;
  Pid pid = make_pid();
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(monitor_config()), PlausibilityStatus::ok);
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> pick(100, 900);
  int32_t sp = j.reading();
  pid.start(sp, sp, 0);
  m.reset(sp);
  int16_t duty = 0;
  for (int k = 0; k < 60 * kRateHz; ++k) {  // a minute of moves, large and small, with holds
    if (k % (3 * kRateHz) == 0) sp = pick(rng) * kUnits;
    const int32_t r = j.reading();
    ASSERT_EQ(m.update(duty, r), 0) << k;
    duty = pid.update(sp, r);
    j.step(duty / 32767.0);
  }
}

TEST(Plausibility, StallUnderSaturatedDrive) {
  Joint j;
  j.blocked = true;
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(monitor_config()), PlausibilityStatus::ok);
  m.reset(j.reading());
  int fired_at = -1;
  for (int k = 0; k < kRateHz; ++k) {
    if (m.update(32767, j.reading()) & kFaultStall) {
      fired_at = k;
      break;
    }
  }
  EXPECT_EQ(fired_at, 250);  // the window opens at sample 0 and closes 250 samples later
  EXPECT_EQ(m.faults() & kFaultSignError, 0);
  // below the threshold (a joint held by a weak command) is not a stall
  PlausibilityMonitor weak;
  ASSERT_EQ(weak.configure(monitor_config()), PlausibilityStatus::ok);
  for (int k = 0; k < 5 * kRateHz; ++k) EXPECT_EQ(weak.update(20000, j.reading()), 0);
}

TEST(Plausibility, SignErrorWhenTheJointMovesAgainstTheDrive) {
  Joint j;
  j.sign = -1;  // motor wired the wrong way round
  Pid pid = make_pid();
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(monitor_config()), PlausibilityStatus::ok);
  const int32_t sp = 600 * kUnits;
  pid.start(j.reading(), j.reading(), 0);
  m.reset(j.reading());
  int16_t duty = 0;
  int fired_at = -1;
  for (int k = 0; k < 2 * kRateHz; ++k) {
    const int32_t r = j.reading();
    if (m.update(duty, r) & kFaultSignError) {
      fired_at = k;
      break;
    }
    duty = pid.update(sp, r);
    j.step(duty / 32767.0);
  }
  EXPECT_GT(fired_at, 0);
  EXPECT_LT(fired_at, kRateHz / 2);  // within half a second, before the joint runs far
}

TEST(Plausibility, ReversalAtSpeedIsNotASignError) {
  Joint j;
  j.load = 0;
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(monitor_config()), PlausibilityStatus::ok);
  m.reset(j.reading());
  for (int k = 0; k < 4 * kRateHz; ++k) {  // full drive, reversed every 0.5 s (bang-bang)
    const int16_t duty = (k / (kRateHz / 2)) % 2 ? -32767 : 32767;
    ASSERT_EQ(m.update(duty, j.reading()), 0) << k;
    j.step(duty / 32767.0);
  }
}

TEST(Plausibility, JumpAndRail) {
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(monitor_config()), PlausibilityStatus::ok);
  m.reset(500 * kUnits);
  EXPECT_EQ(m.update(0, 500 * kUnits), 0);
  EXPECT_EQ(m.update(0, 503 * kUnits), 0);         // 3 counts: the fastest plausible change
  EXPECT_EQ(m.update(0, 507 * kUnits), kFaultJump);  // 4 counts in one sample
  m.reset(500 * kUnits);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(m.update(0, 2 * kUnits), 0);  // at the rail, not yet latched ...
  EXPECT_EQ(m.update(0, 2 * kUnits), kFaultRail);                    // ... 5 samples in a row
  EXPECT_EQ(m.update(0, 500 * kUnits), kFaultRail);                  // latched
  m.reset(500 * kUnits);
  for (int k = 0; k < 20; ++k) EXPECT_EQ(m.update(0, k % 4 ? 500 * kUnits : 1020 * kUnits), k < 4 ? 0 : m.faults());
  PlausibilityConfig bad = monitor_config();
  bad.max_step = 0;
  EXPECT_EQ(plausibility_check(bad), PlausibilityStatus::invalid);
}

namespace {

// Samples that span two periods (the caller overran): the stall window is a time, and the joint
// may move twice the largest step before it counts as a jump.
TEST(Plausibility, SamplesOverTwoPeriodsCountTwice) {
  const PlausibilityConfig c = monitor_config();
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(c), PlausibilityStatus::ok);
  m.reset(500 * kUnits);
  ASSERT_EQ(m.update(0, 500 * kUnits), 0);
  EXPECT_EQ(m.update(0, 500 * kUnits + 2 * c.max_step, 2), 0) << "twice the step over two periods";
  EXPECT_EQ(m.update(0, 500 * kUnits + 5 * c.max_step, 2), kFaultJump) << "more than that is a jump";
  PlausibilityMonitor stalled;
  ASSERT_EQ(stalled.configure(c), PlausibilityStatus::ok);
  stalled.reset(500 * kUnits);
  int samples = 0;
  while (!(stalled.update(32767, 500 * kUnits, 2) & kFaultStall) && samples < 1000) ++samples;
  EXPECT_EQ(samples, c.stall_samples / 2) << "the stall window counts periods, not updates";
}

}  // namespace

// The motion checks at half the readings' rate (the firmware's: with the servo, every second
// tick, motion_samples = 2): every reading is still checked at the rails and for a jump at once,
// and the stall and the sign error take the same time.
TEST(Plausibility, MotionChecksEverySecondSampleKeepTheReadingsChecksAndTheirTimes) {
  const PlausibilityConfig c = monitor_config();
  PlausibilityMonitor m;
  ASSERT_EQ(m.configure(c), PlausibilityStatus::ok);
  m.reset(500 * kUnits);
  EXPECT_EQ(m.update(0, 500 * kUnits, 1, 2), 0);
  EXPECT_EQ(m.update(0, 500 * kUnits + 4 * c.max_step, 1, 0), kFaultJump) << "a jump between the motion checks";
  m.reset(500 * kUnits);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(m.update(0, 2 * kUnits, 1, k % 2 ? 2 : 0), 0);
  EXPECT_EQ(m.update(0, 2 * kUnits, 1, 0), kFaultRail) << "five readings at the rail, the last between the motion checks";

  // a blocked joint under saturated drive: the stall after stall_samples samples either way
  Joint blocked;
  blocked.blocked = true;
  PlausibilityMonitor stalled;
  ASSERT_EQ(stalled.configure(c), PlausibilityStatus::ok);
  stalled.reset(blocked.reading());
  int stalled_at = -1;
  for (int k = 1; k < kRateHz && stalled_at < 0; ++k)
    if (stalled.update(32767, blocked.reading(), 1, k % 2 ? 0 : 2) & kFaultStall) stalled_at = k;
  EXPECT_EQ(stalled_at, c.stall_samples + 2) << "the window opens at the first motion check (sample 2)";

  // the motion checks judge the duty they are given: a reversed one between them is not theirs
  PlausibilityMonitor judged;
  ASSERT_EQ(judged.configure(c), PlausibilityStatus::ok);
  judged.reset(blocked.reading());
  uint8_t faults = 0;
  for (int k = 1; k <= c.stall_samples + 2; ++k) faults = judged.update(k % 2 ? -32767 : 32767, blocked.reading(), 1, k % 2 ? 0 : 2);
  EXPECT_TRUE(faults & kFaultStall);

  // a motor wired the wrong way round: the sign error as soon as with every sample's checks
  int at[2] = {-1, -1};
  for (int every_second = 0; every_second < 2; ++every_second) {
    Joint j;
    j.sign = -1;
    j.load = 0;
    PlausibilityMonitor s;
    ASSERT_EQ(s.configure(c), PlausibilityStatus::ok);
    s.reset(j.reading());
    for (int k = 1; k < kRateHz && at[every_second] < 0; ++k) {
      const uint8_t motion = every_second ? (k % 2 ? 0 : 2) : 1;
      if (s.update(32767, j.reading(), 1, motion) & kFaultSignError) at[every_second] = k;
      j.step(1.0);
    }
  }
  EXPECT_GT(at[0], c.sign_grace_samples);
  EXPECT_GE(at[1], at[0]);
  EXPECT_LE(at[1], at[0] + 3) << "the grace counts samples, not motion checks";
}
