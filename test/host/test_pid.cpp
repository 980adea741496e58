// The DC joint PID (lib/control/pid.h) on a simulated joint: no derivative kick, anti-windup,
// bumpless start, output rate limit, stiction compensation, configuration checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "control/pid.h"

using namespace wmra;
using namespace wmra::control;

namespace {

constexpr int kUnits = 16;  // position units per ADC count
constexpr int kRateHz = 500;

// A DC joint: duty (fraction) -> speed with time constant tau, K counts/s at full duty, and a
// stiction band: below |duty| = stiction the joint does not move. Integrated finely.
struct Joint {
  double k = 400, tau = 0.05, stiction = 0.0;
  double pos = 500, vel = 0;
  bool blocked = false;
  void step(double duty, double dt) {
    const int n = 20;
    for (int i = 0; i < n; ++i) {
      const double drive = std::abs(duty) <= stiction ? 0.0 : duty;
      vel += (k * drive - vel) / tau * (dt / n);
      if (blocked) vel = 0;
      pos += vel * (dt / n);
    }
  }
  int32_t reading() const { return (int32_t)std::lround(pos * kUnits); }
};

PidConfig config() {
  // Kp 0.02 duty/count, Ki 0.1 /(count s), Kd 0.0001 duty s/count at 500 Hz, 16 units/count
  constexpr PidGainsResult g = pid_gains(Ratio{2, 100}, Ratio{1, 10}, Ratio{1, 10000}, kRateHz, kUnits);
  static_assert(g.ok, "gains fit");
  return PidConfig{g.gains, 32767, 32767, 0, 0};
}

double duty_fraction(int16_t d) { return d / 32767.0; }

}  // namespace

TEST(Pid, GainConversionAndConfigurationChecks) {
  constexpr PidGainsResult g = pid_gains(Ratio{2, 100}, Ratio{1, 10}, Ratio{1, 10000}, kRateHz, kUnits);
  EXPECT_EQ(g.gains.kp_q4, 655);  // 0.02 * 32768 * 16 / 16
  EXPECT_EQ(g.gains.ki_q8, 105);  // 0.1 / 500 * 32768 * 256 / 16
  EXPECT_EQ(g.gains.kd, 102);     // 0.0001 * 500 * 32768 / 16
  EXPECT_FALSE(pid_gains(Ratio{2, 1}, Ratio{0, 1}, Ratio{0, 1}, kRateHz, 1).ok);  // does not fit
  PidConfig c = config();
  EXPECT_EQ(pid_check(c), PidStatus::ok);
  c.gains.kp_q4 = -1;
  EXPECT_EQ(pid_check(c), PidStatus::gain_invalid);
  c = config();
  c.rate_q15 = 0;
  EXPECT_EQ(pid_check(c), PidStatus::limit_invalid);
  c = config();
  c.min_duty_q15 = c.out_max_q15;
  EXPECT_EQ(pid_check(c), PidStatus::limit_invalid);
  Pid unconfigured;
  EXPECT_EQ(unconfigured.update(1000, 0), 0);
}

// A setpoint step moves P (and I), not D: the output jump is exactly kp * step
TEST(Pid, NoDerivativeKickOnSetpointStep) {
  Pid pid;
  ASSERT_EQ(pid.configure(config()), PidStatus::ok);
  const int32_t m = 500 * kUnits;
  pid.start(m, m, 0);
  for (int i = 0; i < 10; ++i) pid.update(m, m);
  const int16_t before = pid.effort_q15();
  pid.update(m + 100, m);  // 100 units = 6.25 counts
  const int32_t jump = pid.effort_q15() - before;
  const double p_and_i = 100 * (config().gains.kp_q4 / 16.0 + config().gains.ki_q8 / 256.0);
  EXPECT_NEAR(jump, p_and_i, 1);
  // a measurement step of the same size does move D: -kd * 100 on top of -P
  pid.start(m, m, 0);
  pid.update(m, m);
  pid.update(m, m + 100);
  EXPECT_NEAR(pid.effort_q15(), -100 * (config().gains.kp_q4 / 16.0 + config().gains.ki_q8 / 256.0 + config().gains.kd), 2);
}

// The joint is held for 3 s with a large error (saturated drive), then released: the integral
// never holds more than full output, and the overshoot after the release is far smaller than a
// PID that integrates through saturation
TEST(Pid, AntiWindupRecoversQuickly) {
  const PidConfig c = config();
  auto run = [&](bool anti_windup, bool hold = true) {
    Joint j;
    j.blocked = hold;
    Pid pid;
    EXPECT_EQ(pid.configure(c), PidStatus::ok);
    pid.start(j.reading(), j.reading(), 0);
    const int32_t target = 700 * kUnits;
    double naive_i = 0, overshoot = 0;
    int32_t m_prev = j.reading();
    for (int k = 0; k < 5 * kRateHz; ++k) {
      if (k == 3 * kRateHz) j.blocked = false;
      const int32_t m = j.reading();
      double duty;
      if (anti_windup) {
        duty = duty_fraction(pid.update(target, m));
        EXPECT_LE(std::abs(pid.integral_q23()), (int32_t)c.out_max_q15 << 8);
      } else {  // textbook PID in double, clamped output, integrating regardless
        const double e = (target - m) / 32768.0;
        naive_i += e * c.gains.ki_q8 / 256.0;
        const double u = e * c.gains.kp_q4 / 16.0 + naive_i - (m - m_prev) / 32768.0 * c.gains.kd;
        duty = std::max(-1.0, std::min(1.0, u));
      }
      m_prev = m;
      j.step(duty, 1.0 / kRateHz);
      overshoot = std::max(overshoot, j.pos - 700);
    }
    return overshoot;
  };
  const double with = run(true), without = run(false), fresh = run(true, false);
  std::printf("overshoot of a 200-count step: %.1f counts; after 3 s held: %.1f with anti-windup, %.1f without\n",
              fresh, with, without);
  EXPECT_LT(with, fresh + 3.0);  // the hold adds (almost) nothing
  EXPECT_GT(without, 10 * with + 50);
}

TEST(Pid, BumplessStart) {
  Pid pid;
  ASSERT_EQ(pid.configure(config()), PidStatus::ok);
  // taking over a joint driven at 30 % with an error of 40 counts: the first output is 30 %
  const int32_t sp = 540 * kUnits, m = 500 * kUnits;
  pid.start(sp, m, 9830);
  const int32_t one_sample_of_integral = (640 * config().gains.ki_q8 + 128) >> 8;
  EXPECT_NEAR(pid.update(sp, m), 9830 + one_sample_of_integral, 1);
  // from rest with no error: nothing moves
  pid.start(m, m, 0);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(pid.update(m, m), 0);
}

TEST(Pid, OutputRateLimit) {
  PidConfig c = config();
  c.rate_q15 = 300;  // 1 % per sample: 0 -> 100 % in 0.2 s at 500 Hz
  Pid pid;
  ASSERT_EQ(pid.configure(c), PidStatus::ok);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, 1023 * kUnits);
  int16_t prev = 0;
  int32_t sp = 0, m = 0;
  for (int i = 0; i < 20000; ++i) {
    if (i % 37 == 0) sp = pick(rng);
    if (i % 53 == 0) m = pick(rng);  // and jumps of the measurement
    pid.update(sp, m);
    EXPECT_LE(std::abs(pid.effort_q15() - prev), 300) << i;
    EXPECT_LE(std::abs(pid.effort_q15()), c.out_max_q15);
    prev = pid.effort_q15();
  }
}

// The effort's bounds (a speed governor): the effort stays within them, the integral does not
// wind up behind them, and a bound that falls below the effort takes it down at the rate limit.
TEST(Pid, EffortBoundsHoldTheEffortWithoutJumpOrWindup) {
  PidConfig c = config();
  c.rate_q15 = 300;
  Pid pid;
  ASSERT_EQ(pid.configure(c), PidStatus::ok);
  pid.set_effort_bounds(9000, 6000);
  Joint j;
  j.blocked = true;  // 2 s against a blocked joint, 200 counts short
  pid.start(j.reading(), j.reading(), 0);
  for (int k = 0; k < 2 * kRateHz; ++k) {
    pid.update(j.reading() + 200 * kUnits, j.reading());
    EXPECT_LE(pid.effort_q15(), 9000);
  }
  EXPECT_EQ(pid.effort_q15(), 9000);
  EXPECT_LE(pid.integral_q23(), 9000 * 256) << "held at the bound, not wound up to full output";
  // the bound falls below the effort: down at the rate limit, no step
  pid.set_effort_bounds(2000, 6000);
  int16_t prev = pid.effort_q15();
  for (int k = 0; k < 100; ++k) {
    pid.update(j.reading() + 200 * kUnits, j.reading());
    EXPECT_LE(prev - pid.effort_q15(), 300) << k;
    EXPECT_LE(pid.effort_q15(), prev);
    prev = pid.effort_q15();
  }
  EXPECT_EQ(pid.effort_q15(), 2000);
  // the error turns: the effort leaves the bound at once (the rate limit's pace) and is bounded
  // by the other side's 6000
  for (int k = 0; k < kRateHz; ++k) {
    pid.update(j.reading() - 200 * kUnits, j.reading());
    EXPECT_GE(pid.effort_q15(), -6000);
  }
  EXPECT_EQ(pid.effort_q15(), -6000);
  // bounds past out_max are out_max
  pid.set_effort_bounds(32767, 32767);
  for (int k = 0; k < kRateHz; ++k) pid.update(j.reading() - 200 * kUnits, j.reading());
  EXPECT_EQ(pid.effort_q15(), -c.out_max_q15);
}

// A joint that does not move below 12 % duty: without compensation the loop stops short of the
// setpoint (P alone cannot reach the stiction duty); with min_duty it gets there
TEST(Pid, StictionCompensation) {
  PidConfig c = config();
  c.gains.ki_q8 = 0;  // P-D only: the case where the dead zone hurts most
  c.min_duty_q15 = 3932;   // 12 %
  c.zero_band_q15 = 100;
  Pid pid;
  ASSERT_EQ(pid.configure(c), PidStatus::ok);
  // the map: 0 inside the band, then min_duty + e (1 - min/max), monotone, <= out_max
  int16_t prev = 0;
  for (int e = 0; e <= 32767; e += 7) {
    const int16_t d = pid.duty_for((int16_t)e);
    if (e < c.zero_band_q15) {
      EXPECT_EQ(d, 0);
    } else {
      EXPECT_GE(d, c.min_duty_q15);
      EXPECT_GE(d, prev);
    }
    EXPECT_EQ(pid.duty_for((int16_t)-e), -d);
    prev = d;
  }
  EXPECT_LE(pid.duty_for(32767), 32767);
  EXPECT_GE(pid.duty_for(32767), 32760);
  auto final_error = [&](int16_t min_duty) {
    PidConfig cc = c;
    cc.min_duty_q15 = min_duty;
    Pid p;
    EXPECT_EQ(p.configure(cc), PidStatus::ok);
    Joint j;
    j.stiction = 0.12;
    p.start(j.reading(), j.reading(), 0);
    for (int k = 0; k < 3 * kRateHz; ++k) j.step(duty_fraction(p.update(530 * kUnits, j.reading())), 1.0 / kRateHz);
    return std::abs(530 - j.pos);
  };
  const double without = final_error(0), with = final_error(3932);
  std::printf("steady error with a 12 %% stiction band: %.2f counts uncompensated, %.2f compensated\n", without, with);
  EXPECT_GT(without, 1.0);
  EXPECT_LT(with, without / 10);
}

// Following a ramped setpoint (as the joystick integrates one): small lag, no oscillation
TEST(Pid, TracksARampedSetpoint) {
  Pid pid;
  ASSERT_EQ(pid.configure(config()), PidStatus::ok);
  Joint j;
  pid.start(j.reading(), j.reading(), 0);
  double worst = 0;
  for (int k = 0; k < 4 * kRateHz; ++k) {
    const double sp = 500 + std::min(k, 2 * kRateHz) * (100.0 / kRateHz);  // 100 counts/s for 2 s
    j.step(duty_fraction(pid.update((int32_t)std::lround(sp * kUnits), j.reading())), 1.0 / kRateHz);
    if (k > kRateHz / 2) worst = std::max(worst, std::abs(sp - j.pos));
  }
  EXPECT_LT(worst, 12.0);
  EXPECT_NEAR(j.pos, 700, 0.5);
}

// Velocity feedforward: the setpoint's speed as effort (speed / the joint's speed at full duty)
// removes most of the lag that the loop otherwise needs to build its effort (what is left is
// the joint's 50 ms time constant at the ramp's start), and still ends on the target.
TEST(Pid, FeedforwardRemovesTheLagOfARamp) {
  constexpr double kSpeed_counts_s = 100;
  double worst[2] = {0, 0};
  double end[2] = {0, 0};
  for (int with_ff = 0; with_ff < 2; ++with_ff) {
    Pid pid;
    ASSERT_EQ(pid.configure(config()), PidStatus::ok);
    Joint j;
    pid.start(j.reading(), j.reading(), 0);
    for (int k = 0; k < 4 * kRateHz; ++k) {
      const bool ramping = k < 2 * kRateHz;
      const double sp = 500 + std::min(k, 2 * kRateHz) * (kSpeed_counts_s / kRateHz);
      const int16_t ff = with_ff && ramping ? (int16_t)std::lround(kSpeed_counts_s / j.k * 32767) : 0;
      j.step(duty_fraction(pid.update((int32_t)std::lround(sp * kUnits), j.reading(), ff)), 1.0 / kRateHz);
      if (ramping) worst[with_ff] = std::max(worst[with_ff], std::abs(sp - j.pos));
    }
    end[with_ff] = j.pos;
  }
  std::printf("lag on a 100 counts/s ramp: %.2f counts without feedforward, %.2f with\n", worst[0], worst[1]);
  EXPECT_LT(worst[1], worst[0] / 3);
  EXPECT_NEAR(end[1], 700, 0.5);
}

namespace {

// An update that spans two sample periods (the caller overran) integrates twice as much, allows
// twice the output's change and sees the measurement's change as over two periods: the same as
// two updates with the same inputs, to within the derivative's rounding.
TEST(Pid, AnUpdateOverTwoSamplesIsTwoSamples) {
  PidConfig c = config();
  c.rate_q15 = 300;  // the rate limit counts too
  Pid once, twice;
  ASSERT_EQ(once.configure(c), PidStatus::ok);
  ASSERT_EQ(twice.configure(c), PidStatus::ok);
  int32_t m = 0;
  for (int k = 0; k < 200; ++k) {
    const int32_t setpoint = 4000 + 20 * k;
    m += 14;  // a joint moving steadily
    int16_t a = 0;
    for (int s = 0; s < 2; ++s) a = once.update(setpoint, m - 7 + 7 * s, 0);
    const int16_t b = twice.update(setpoint, m, 0, 2);
    ASSERT_NEAR(b, a, 64) << "after " << k << " double samples";
    EXPECT_NEAR(twice.integral_q23(), once.integral_q23(), 64 * 256) << k;
  }
}

// duty_moving is friction + floor(slope x effort / 2^15) in the motion's direction, negated for a
// negative motion, over every effort and the slopes' range (its shift by 15 is taken as a
// byte pick after one left shift: bits 15..30 of the product). Red with a wrong bit taken.
TEST(Pid, DutyMovingIsTheFrictionPlusTheSlopedEffort) {
  for (int32_t slope = 16384; slope <= 32768; slope += 1021) {
    for (int32_t effort = -32767; effort <= 32767; effort += 7) {
      for (bool negative : {false, true}) {
        const int64_t a = negative ? -effort : effort;
        const int64_t floor_product = (int64_t)std::floor((double)(slope * a) / 32768.0);
        const int64_t d = 2883 + floor_product;
        const int16_t want = (int16_t)(negative ? -d : d);
        ASSERT_EQ(Pid::duty_moving((int16_t)effort, negative, 2883, (uint16_t)slope), want)
            << "slope " << slope << " effort " << effort << (negative ? " negative" : "");
      }
    }
  }
}

}  // namespace
