// The DC joint's servo (firmware/core/dc_servo.h) against a simple model of a worm-geared joint
// that lifts a load: how it closes the error to a standing reference up and down.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/dc_servo.h"

namespace {

using namespace wmra;

constexpr int32_t kUnitsPerCount = 16;
constexpr int16_t kMinDuty_q15 = 3604;  // 11 %: the worm's stiction

// J3's numbers: the pole-placement gains of joints_config.h at 1 kHz, the loop's duty shaping
core::DcServoConfig config() {
  core::DcServoConfig c{};
  c.use_relay = false;
  c.pid = control::PidConfig{
      control::pid_gains(Ratio{8799, 100000}, Ratio{24367, 100000}, Ratio{8551, 1000000}, 1000, kUnitsPerCount).gains, 32767,
      32767 / 50, kMinDuty_q15, 327};
  c.relay = control::RelayConfig{2 * kUnitsPerCount, 0, 19660};
  c.checks = control::PlausibilityConfig{31128, 300, 2 * kUnitsPerCount, 200, 8 * kUnitsPerCount, 12 * kUnitsPerCount,
                                         20 * kUnitsPerCount, 1003 * kUnitsPerCount, 5};
  c.park_units = kUnitsPerCount;
  c.park_ticks = 50;
  c.unpark_ticks = 10;
  c.moving_friction_q15 = 2884;  // 8.8 %: the worm's Coulomb friction
  return c;
}

// A worm-geared joint lifting a load of `hold` (duty): it moves up only above hold + stiction,
// down below -stiction, and stands otherwise (the worm does not back-drive); its speed follows
// the free duty with a 60 ms time constant; full free duty is `full` units a tick.
struct WormJoint {
  double hold, full, x, v = 0;
  int32_t read() const { return (int32_t)std::lround(x / kUnitsPerCount) * kUnitsPerCount; }  // a pot count
  void step(int16_t duty_q15) {
    const double u = duty_q15 / 32768.0, stiction = kMinDuty_q15 / 32768.0;
    const double free = u > hold + stiction ? u - hold - stiction : u < -stiction ? u + stiction : 0;
    if (free == 0) v = 0;  // the worm holds
    else v += (free * full - v) / 60.0;
    x += v;
  }
};

// a standing reference 4 counts above a joint that stands: the holding effort in the lifting
// direction gets it there at once (with the integral alone, 0.6 of duty takes most of a second)
TEST(DcServo, AStandingReferenceAheadGetsTheHoldingEffort) {
  int with_holding = 0;
  for (int16_t passed : {(int16_t)24000, (int16_t)0}) {
    WormJoint joint{0.6, 3.0, 5000};
    core::DcServo servo;
    ASSERT_TRUE(servo.configure(config()));
    servo.rest(joint.read());
    const int32_t reference = joint.read() + 4 * kUnitsPerCount;
    int reached = -1;
    for (int k = 0; k < 2000 && reached < 0; ++k) {
      joint.step(servo.update(reference, joint.read(), 0, passed));
      if (std::abs(joint.read() - reference) <= kUnitsPerCount) reached = k;
    }
    if (passed) {
      EXPECT_GE(reached, 0);
      EXPECT_LE(reached, 300) << "ms to within a count";
      with_holding = reached;
    } else {
      EXPECT_TRUE(reached < 0 || reached > 2 * with_holding) << "the integral alone was as quick: the test shows nothing";
    }
  }
}

// A jammed joint under a speed bound: the servo's effort is held at the bound (well below the
// stall check's 95 %), yet the checks raise a stall: the drive at its bound is saturated. (Before,
// the bound hid every stall: J3 sat at 39 % duty against a jammed joint, no fault.) Also when it
// jams after moving three counts: the moving friction's map then applies, whose duty at the
// bound is below duty_for's (a drive bound from duty_for: no fault).
TEST(DcServo, AJammedJointUnderASpeedBoundStalls) {
  const core::DcServoConfig c = config();
  for (int16_t moved_counts : {(int16_t)0, (int16_t)3}) {
    core::DcServo servo;
    ASSERT_TRUE(servo.configure(c));
    servo.set_effort_bounds(10340, 10340);  // J3's bound: its 1 rad/s of 3.56 at full duty, no load
    const int16_t start = 5000 * kUnitsPerCount / 16;
    servo.rest(start);
    servo.reset_checks(start);
    // moving up a count a tick (the reference further ahead), then jammed
    for (int16_t k = 1; k <= moved_counts; ++k) {
      servo.check((int16_t)(start + k * kUnitsPerCount));
      servo.update((int16_t)(start + 200), (int16_t)(start + k * kUnitsPerCount), 2000);
    }
    const int16_t at = (int16_t)(start + moved_counts * kUnitsPerCount);
    uint8_t faults = 0;
    int16_t largest = 0;
    int stalled_at = -1;
    for (int k = 0; k < 1000 && stalled_at < 0; ++k) {
      faults = servo.check(at);
      if (faults & control::kFaultStall) stalled_at = k;
      const int16_t duty = servo.update((int16_t)(at + 200), at, 2000);  // a moving reference ahead
      largest = duty > largest ? duty : largest;
    }
    EXPECT_LT(largest, c.checks.drive_threshold_q15) << "the bound kept the duty below the stall threshold";
    EXPECT_GE(stalled_at, c.checks.stall_samples) << "moved " << moved_counts << " counts";
    EXPECT_LE(stalled_at, c.checks.stall_samples + 100) << "ms to the stall fault, moved " << moved_counts << " counts";
    EXPECT_FALSE(faults & control::kFaultSignError);
  }
}

// lowering needs no holding effort (the worm takes the load): a standing reference below gets
// none: it ends at the reference, not held above it
TEST(DcServo, AStandingReferenceBelowGetsNoHoldingEffort) {
  WormJoint joint{0.6, 3.0, 5000};
  core::DcServo servo;
  ASSERT_TRUE(servo.configure(config()));
  servo.rest(joint.read());
  const int32_t reference = joint.read() - 4 * kUnitsPerCount;
  for (int k = 0; k < 500; ++k) joint.step(servo.update(reference, joint.read(), 0, 24000));
  EXPECT_LE(std::abs(joint.read() - reference), kUnitsPerCount);
}

// A reference lowering the joint with a small feedforward (the load helps a worm down: S1's J2
// and J4): the PID's P on a reading a fraction of a count ahead outweighs it. Mapped through the
// motion's direction, the duty stays along the reference while the joint is less than a count
// ahead (it slows, the worm does not stop it dead); ahead by more, it falls below the friction's.
TEST(DcServo, AMovingReferenceKeepsAJointLessThanACountAheadMoving) {
  core::DcServo servo;
  ASSERT_TRUE(servo.configure(config()));
  const int32_t reading = 5000;
  servo.rest(reading);
  const int16_t feedforward_q15 = -700;  // 2 % effort downwards
  // the reference half a count above the reading, going down by a unit a tick until a count below
  for (int32_t reference = reading + kUnitsPerCount / 2; reference > reading - kUnitsPerCount; --reference) {
    const int16_t duty = servo.update(reference, reading, feedforward_q15, 0);
    EXPECT_LT(duty, 0) << "reference " << reference - reading << " units from the reading";
  }
  // the joint two counts ahead: the PID's duty, against the motion
  const core::DcServoConfig c = config();
  core::DcServo ahead;
  ASSERT_TRUE(ahead.configure(config()));
  ahead.rest(reading);
  int16_t duty = 0;
  for (int k = 0; k < 10; ++k) duty = ahead.update(reading + 2 * kUnitsPerCount - k, reading, feedforward_q15, 0);
  EXPECT_GT(duty, -c.moving_friction_q15) << "ahead by more than park_units, the duty falls below the friction's: the joint stops";
}

// A moving reference that the joint runs ahead of: the PID's effort turns from pushing along
// the motion to braking it. The worm's friction opposes the motion whatever the effort's sign,
// so the duty passes through the friction's without a step (pid.h's duty_moving); mapped
// through the effort's sign it jumped by twice the stiction's duty (22 %) where the effort
// crossed 0, and the worm stopped the joint dead (S1's 4 Hz ringing).
TEST(DcServo, AMovingReferencesDutyTurnsWithoutAStepWhereItsEffortCrossesZero) {
  const core::DcServoConfig c = config();
  core::DcServo servo;
  ASSERT_TRUE(servo.configure(c));
  const int16_t reading = 5000;
  servo.rest(reading);
  const int16_t feedforward_q15 = -700;  // downwards
  int16_t last = 0, largest_step = 0;
  bool pushed = false, braked = false;
  // the reference from a count below the reading (the joint behind) to four above (ahead)
  for (int16_t reference = reading - kUnitsPerCount; reference < reading + 4 * kUnitsPerCount; ++reference) {
    const int16_t duty = servo.update(reference, reading, feedforward_q15, 0);
    if (pushed) largest_step = std::max<int16_t>(largest_step, (int16_t)std::abs(duty - last));
    pushed = pushed || duty <= -c.moving_friction_q15;
    braked = braked || duty > 0;
    last = duty;
  }
  EXPECT_TRUE(pushed && braked) << "the sweep took the duty from pushing down to pushing up";
  // (mapped through the effort's sign, the duty reversed where the effort crossed 0: 29 %)
  EXPECT_LT(largest_step, kMinDuty_q15) << "Q15 duty: no step of the stiction's or more";
}

// A reference that starts lifting a joint at rest, with the pot's noise flipping the reading by
// a count every sample (a count's worth of noise at a count boundary): the PID's D kicks by
// several times full effort at each flip, which the effort's rate limit chops to a rate step,
// down and up in turn, so an effort ramping up from 0 stood still and the joint never started.
// The worm holds the load up to the holding effort, so the servo may start there: the effort
// then alternates about it, whose duty here is 5 % above the load's and the stiction's, and the
// joint lifts a count in 141 ms (without: not within 300 ms).
TEST(DcServo, ALiftingReferenceStartsTheJointFromItsHoldingEffortThroughNoise) {
  constexpr int16_t kHolding_q15 = 24000;  // effort for WormJoint's 0.6 duty
  WormJoint joint{0.6, 3.0, 5000 + kUnitsPerCount / 2};  // at a count boundary
  core::DcServo servo;
  ASSERT_TRUE(servo.configure(config()));
  servo.rest(joint.read());
  const double start = joint.x;
  int32_t reference = joint.read();
  int moved_ms = -1;
  for (int k = 0; k < 300 && moved_ms < 0; ++k) {
    reference += 1;  // 1/16 count a tick upwards
    const int32_t reading = joint.read() + (k % 2 ? kUnitsPerCount : 0);
    joint.step(servo.update(reference, reading, kHolding_q15 + 1000, kHolding_q15));
    if (joint.x - start >= kUnitsPerCount) moved_ms = k;
  }
  EXPECT_GE(moved_ms, 0) << "the joint never started";
  EXPECT_LE(moved_ms, 200) << "ms until the joint lifted a count";
}

// A reference that starts lowering a joint at rest (the worm takes the load): the joint breaks
// away at the static friction's duty, and once moving its speed is the duty's excess over the
// Coulomb friction's. Until the pot showed two counts, the breakaway's map (the stiction's duty
// plus the effort) kept 2.2 % duty more than the motion's, 80-100 mrad/s at J3 and J4: the
// lowering joints ran at twice their references' speed in S1's stick ramp.
TEST(DcServo, ALoweringJointBreaksAwayAtTheStictionsDutyNotOnTopOfIt) {
  const core::DcServoConfig c = config();
  core::DcServo servo;
  ASSERT_TRUE(servo.configure(c));
  const int16_t reading = 5000;
  servo.rest(reading);
  // 2 % effort downwards, the reference a unit below the reading (within the count)
  const int16_t duty = servo.update(reading - 1, reading, -700, 0);
  EXPECT_EQ(duty, -kMinDuty_q15) << "a small effort's duty is the stiction's, enough to break away and no more";
  // an effort against the motion (the joint ahead): below the stiction's, the joint stays
  core::DcServo ahead;
  ASSERT_TRUE(ahead.configure(c));
  ahead.rest(reading);
  EXPECT_GT(ahead.update(reading + 2 * kUnitsPerCount, reading, -700, 0), -kMinDuty_q15);
}

// Lifting, the breakaway's duty is the stiction's plus the load's (duty_for of the holding
// effort), and the least effort on the moving map that reaches it (set_breakaway's reciprocal
// and its correction, exact): a start whose effort is just past the load's gets exactly that duty.
TEST(DcServo, ALiftingJointBreaksAwayAtTheStictionsAndTheLoadsDuty) {
  const core::DcServoConfig c = config();
  control::Pid pid;
  ASSERT_EQ(pid.configure(c.pid), control::PidStatus::ok);
  for (int16_t holding = 100; holding <= 4000; holding = (int16_t)(holding + 97)) {
    core::DcServo servo;
    ASSERT_TRUE(servo.configure(c));
    const int16_t reading = 5000;
    servo.rest(reading);
    // a reference moving up a unit ahead, its feedforward the load's and a slow speed's (as
    // run_dc_servo's): the effort starts at the holding effort and ramps up by its rate (655)
    const int16_t duty = servo.update(reading + 1, reading, (int16_t)(holding + 700), holding);
    EXPECT_EQ(duty, control::Pid::duty_moving(holding, false, kMinDuty_q15, pid.moving_slope_q15(kMinDuty_q15)))
        << "holding " << holding;
  }
}

}  // namespace
