// Seed 0's closed-loop stepper controller (lib/control/seed0_stepper_controller.h): the PD
// command, the rule base, saturation, the firmware's deadband / near-target gain / minimum
// speed / reversal, 32-bit arithmetic where the original overflowed, the gain estimate, and the
// thesis's 250-count step (Cardozo's thesis, section 4.3 and chapter 7).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "control/seed0_stepper_controller.h"
#include "control/step_ramp.h"

using namespace wmra;
using namespace wmra::control;

namespace {

// joint 1 of Appendix A: kp 13, kd 2 (= K_D/dt = 0.02/0.01), alpha dt 50, V_S 1000,
// deadband 1, near 10 with kp 2, V_MIN 25
Seed0Config joint1(Seed0Variant v, int32_t kp = 13) {
  return Seed0Config{v, kp * 256, seed0_kd_q8(Ratio{2, 100}, 10), seed0_accel_per_period(5000, 10), 1000, 1, 10, 2 * 256, 25};
}

// The thesis's single-motor simulation: the motor follows V_C (steps/s) exactly, the encoder
// reads 0.75 count per half-step (6000 ppr encoder, 8000 half-steps per turn), dt = 10 ms.
struct StepRun {
  double settle_s = -1;   // first time |e| <= 1 count and V_C = 0 for good
  int32_t overshoot = 0;  // counts past the target
  int32_t final_error = 0;
  int32_t peak_speed = 0;
  double accel_end_s = -1;  // V_C first reaches V_S
  double reach_s = -1;      // the error first within 1 count
};
StepRun step_response(const Seed0Config& cfg, int32_t target_counts, int periods = 120) {
  Seed0StepperController c;
  EXPECT_EQ(c.configure(cfg), Seed0Status::ok);
  double steps = 0;
  StepRun r;
  int32_t v = 0;
  for (int k = 0; k < periods; ++k) {
    const int32_t counts = (int32_t)std::floor(steps * 0.75);
    v = c.update(target_counts, counts);
    steps += v * 0.01;
    r.peak_speed = std::max(r.peak_speed, std::abs(v));
    if (r.accel_end_s < 0 && std::abs(v) >= cfg.v_s) r.accel_end_s = (k + 1) * 0.01;
    const int32_t after = (int32_t)std::floor(steps * 0.75);
    r.overshoot = std::max(r.overshoot, (after - target_counts) * (target_counts > 0 ? 1 : -1));
    const bool settled = std::abs(target_counts - after) <= 1 && v == 0;
    if (r.reach_s < 0 && std::abs(target_counts - after) <= 1) r.reach_s = (k + 1) * 0.01;
    if (settled && r.settle_s < 0) r.settle_s = (k + 1) * 0.01;
    if (!settled) r.settle_s = -1;
    r.final_error = target_counts - after;
  }
  return r;
}

}  // namespace

TEST(Seed0Controller, PdCommandInTheLinearRegion) {
  Seed0Config cfg = joint1(Seed0Variant::thesis);
  cfg.accel_per_period = 1000000;  // rule base and saturation out of the way
  cfg.v_s = 1000000;
  Seed0StepperController c;
  ASSERT_EQ(c.configure(cfg), Seed0Status::ok);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(-2000, 2000);
  int32_t e_prev = 0;
  for (int i = 0; i < 1000; ++i) {
    const int32_t e = pick(rng);
    const int32_t pos = pick(rng) * 10;
    const int32_t v = c.update(pos + e, pos);
    // K_P e + K_D (e - e_prev)/dt = 13 e + 2 (e - e_prev), exactly (integer gains)
    EXPECT_EQ(v, 13 * e + 2 * (e - e_prev)) << i;
    e_prev = e;
  }
}

TEST(Seed0Controller, RuleBaseLimitsTheChangeAndSaturationTheSpeed) {
  Seed0StepperController c;
  ASSERT_EQ(c.configure(joint1(Seed0Variant::thesis)), Seed0Status::ok);
  int32_t prev = 0;
  for (int k = 0; k < 40; ++k) {  // a large error: V_PD >= V_MAX every period
    const int32_t v = c.update(5000, 0);
    EXPECT_EQ(v, std::min(1000, prev + 50)) << k;  // V_C(k-1) + alpha dt until V_S
    prev = v;
  }
  for (int k = 0; k < 40; ++k) {  // and braking: at most alpha dt per period
    const int32_t v = c.update(-5000, 0);
    EXPECT_EQ(v, std::max(-1000, prev - 50)) << k;
    prev = v;
  }
}

// Seed 0, 7.5-7.6: a 250-count step with alpha = 5000 steps/s^2, V_S = 1000, K_D = 0.02.
// K_P = 13: alpha-limited acceleration to V_S at 0.2 s, braking at alpha, at the target about
// 0.5 s after the step, without overshoot; K_P = 15 brakes late and overshoots (the thesis
// reports overshoot and a reversal).
TEST(Seed0Controller, ReproducesTheThesisStepResponse) {
  const StepRun r13 = step_response(joint1(Seed0Variant::thesis, 13), 250);
  std::printf("K_P 13: at V_S at %.2f s, within 1 count at %.2f s, at rest at %.2f s, overshoot %d, final error %d\n",
              r13.accel_end_s, r13.reach_s, r13.settle_s, r13.overshoot, r13.final_error);
  EXPECT_NEAR(r13.accel_end_s, 0.20, 0.005);
  EXPECT_EQ(r13.peak_speed, 1000);
  EXPECT_GT(r13.reach_s, 0.45);  // the thesis: zero error from 0.52 s
  EXPECT_LT(r13.reach_s, 0.60);
  EXPECT_LE(r13.overshoot, 1);
  const StepRun r15 = step_response(joint1(Seed0Variant::thesis, 15), 250);
  std::printf("K_P 15: overshoot %d counts\n", r15.overshoot);
  EXPECT_GT(r15.overshoot, r13.overshoot + 2);
}

TEST(Seed0Controller, FirmwareDeadbandNearTargetGainAndMinimumSpeed) {
  Seed0StepperController c;
  ASSERT_EQ(c.configure(joint1(Seed0Variant::firmware)), Seed0Status::ok);
  // |e| <= 1: zero
  EXPECT_EQ(c.update(101, 100), 0);
  EXPECT_EQ(c.update(99, 100), 0);
  // 1 < |e| <= 10: 2 e = 14 < V_MIN, raised to 25
  EXPECT_EQ(c.update(107, 100), 25);
  // rate limited from 25: 13 * 30 + 2 * 23 = 436 -> 25 + 50
  EXPECT_EQ(c.update(130, 100), 75);
  // back inside the deadband: the zero is still rate-limited (75 -> 25) as in the original
  EXPECT_EQ(c.update(100, 100), 25);
  EXPECT_EQ(c.update(100, 100), 0);
  // the thesis variant has no deadband and no minimum speed: 2 e -> 13 * 5 + 2 * 5
  Seed0StepperController t;
  ASSERT_EQ(t.configure(joint1(Seed0Variant::thesis)), Seed0Status::ok);
  t.reset(100, 100);
  EXPECT_EQ(t.update(105, 100), 50);  // 75 asked, 50 allowed
  // the firmware variant settles within the deadband at the 250-count step, creeping at V_MIN
  const StepRun fw = step_response(joint1(Seed0Variant::firmware), 250, 200);
  EXPECT_LE(std::abs(fw.final_error), 1);
  EXPECT_GT(fw.settle_s, 0);
}

TEST(Seed0Controller, FirmwareReversalGivesOnePeriodAtRest) {
  Seed0StepperController c;
  ASSERT_EQ(c.configure(joint1(Seed0Variant::firmware)), Seed0Status::ok);
  EXPECT_EQ(c.update(200, 100), 50);
  EXPECT_EQ(c.update(200, 100), 100);
  // the error changes sign: braking through 0 at alpha dt, then one period at 0 when the sign
  // of the command flips, then the rule base starts again from 0
  int32_t v = 0, zeros = 0, prev = 100;
  for (int k = 0; k < 10; ++k) {
    v = c.update(0, 100);
    if (v == 0) ++zeros;
    EXPECT_LE(std::abs(v - prev), 50);
    if (prev > 0) {
      EXPECT_GE(v, 0);  // never straight from positive to negative
    }
    prev = v;
  }
  EXPECT_EQ(zeros, 2);  // one where the rule base passes 0, one forced by the sign change
  EXPECT_LT(v, 0);
}

// The original's 16-bit product overflows for |e| > ~2,520 counts at kp 13: 3000 * 13 = 39000
// wraps to -26536 and drives the joint away from the target. Here it saturates at +V_S.
TEST(Seed0Controller, NoSixteenBitOverflow) {
  EXPECT_LT((int16_t)(3000 * 13), 0);  // what the PIC computed
  for (Seed0Variant variant : {Seed0Variant::thesis, Seed0Variant::firmware}) {
    Seed0StepperController c;
    ASSERT_EQ(c.configure(joint1(variant)), Seed0Status::ok);
    int32_t v = 0;
    for (int k = 0; k < 30; ++k) {
      v = c.update(3000 + k, 0);
      EXPECT_GT(v, 0);
    }
    EXPECT_EQ(v, 1000);
    c.reset(0, 0);
    for (int k = 0; k < 30; ++k) v = c.update(-2000000000, 2000000000);  // beyond int32 difference
    EXPECT_EQ(v, -1000);
  }
}

// Cardozo's thesis, section 4.3: K_P = 2 alpha (1 + K_D) / V_S; with it the PD reaches V_S exactly at the
// braking distance V_S^2 / (2 alpha) (4.8 = 4.10)
TEST(Seed0Controller, GainEstimateFromSymmetricBraking) {
  EXPECT_EQ(seed0_kp_q8(5000, 1000, Ratio{2, 100}), 2611);  // 10.2 in Q8
  EXPECT_EQ(seed0_kp_q8(5000, 1000, Ratio{0, 1}), 2560);    // 2 alpha / V_S = 10 (4.12)
  EXPECT_EQ(seed0_kd_q8(Ratio{2, 100}, 10), 512);           // the firmware's kd = 2
  EXPECT_EQ(seed0_accel_per_period(5000, 10), 50);          // alfa_max = 50
  const double kp = seed0_kp_q8(5000, 1000, Ratio{2, 100}) / 256.0, kd = 0.02, vs = 1000, alpha = 5000;
  const double e0_braking = vs * vs / (2 * alpha);  // 4.8
  const double e0_pd = vs * (1 + kd) / kp;          // 4.10
  EXPECT_NEAR(e0_pd / e0_braking, 1.0, 1e-3);
  // the thesis's printed 4.11, (1 + K_D)/K_P = 2 alpha / V_S, would give K_P = 0.102: wrong
  EXPECT_GT(std::abs((1 + kd) / (2 * alpha / vs) - kp), 10.0);
}

TEST(Seed0Controller, RefusesBadConfiguration) {
  Seed0Config c = joint1(Seed0Variant::firmware);
  c.accel_per_period = 0;
  EXPECT_EQ(seed0_check(c), Seed0Status::accel_not_positive);
  c = joint1(Seed0Variant::firmware);
  c.kp_q8 = -1;
  EXPECT_EQ(seed0_check(c), Seed0Status::gain_invalid);
  c = joint1(Seed0Variant::firmware);
  c.v_min = 2000;
  EXPECT_EQ(seed0_check(c), Seed0Status::speed_invalid);
  c = joint1(Seed0Variant::firmware);
  c.near_counts = 0;
  EXPECT_EQ(seed0_check(c), Seed0Status::band_invalid);
  Seed0StepperController unconfigured;
  EXPECT_EQ(unconfigured.update(1000, 0), 0);
}

// With the step generator in the loop (the firmware's arrangement): V_C -> StepRamp (its limit
// above alpha), steps counted exactly, encoder behind 0.1 deg of backlash... here a plain
// 0.75 count/step: the joint reaches the target and the step count matches the motion.
TEST(Seed0Controller, DrivesTheStepRampToTheTarget) {
  Seed0StepperController c;
  ASSERT_EQ(c.configure(joint1(Seed0Variant::firmware)), Seed0Status::ok);
  StepRamp<2000000> ramp;
  ASSERT_EQ(ramp.configure({6000, 500}), RampStatus::ok);
  uint64_t now = 0, next_edge = 0;
  bool running = false;
  for (int k = 0; k < 150; ++k) {
    const int32_t counts = (int32_t)std::floor(ramp.position_steps() * 0.75);
    ramp.set_speed(c.update(-400, counts));
    const uint64_t end = now + 20000;  // 10 ms of 2 MHz ticks
    if (!running && ramp.wants_step()) {
      const auto s = ramp.next();
      running = s.interval_ticks != 0;
      next_edge = now + s.interval_ticks;
    }
    while (running && next_edge <= end) {
      const auto s = ramp.next();
      running = s.interval_ticks != 0;
      next_edge += s.interval_ticks;
    }
    now = end;
  }
  EXPECT_NEAR(std::floor(ramp.position_steps() * 0.75), -400, 1);
}
