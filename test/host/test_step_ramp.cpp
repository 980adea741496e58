// The step-interval ramp (lib/control/step_ramp.h): acceleration measured from the generated
// intervals never above the limit, exact step counts, reversals only through rest, the
// minimum interval, and the relation to seed 2's eq. 4.16.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "control/step_ramp.h"

using namespace wmra::control;

namespace {

constexpr uint32_t kF = 2000000;  // Timer5 at prescaler 8
using Ramp = StepRamp<kF>;

struct Edge {
  double interval_s;  // exact (Q16.16) interval before this step
  uint16_t ticks;     // what the timer got
  int dir;
};

// Runs the ramp for up to max_steps, calling command(step_index) before each step; stops early
// at rest when stop_at_rest. Gaps at rest (next() == 0) are recorded as interval 0.
template <class Command>
std::vector<Edge> run(Ramp& r, int max_steps, Command command, bool stop_at_rest = true) {
  std::vector<Edge> out;
  for (int i = 0; i < max_steps; ++i) {
    command(i);
    const Ramp::Step s = r.next();
    if (s.interval_ticks == 0) {
      if (stop_at_rest) break;
      out.push_back(Edge{0, 0, 0});
      continue;
    }
    out.push_back(Edge{r.last_interval_q16() / 65536.0 / kF, s.interval_ticks, s.dir});
  }
  return out;
}

// Acceleration between consecutive steps: the mean speed of a step (dir / interval) is the
// speed at its midpoint; rest (a gap, or the start) is speed 0 at the edge. Returns the
// largest |a| measured, with each pair's allowance for the Q16 rounding of both intervals.
struct AccelCheck {
  double worst_ratio = 0;  // max over pairs of |a| / (limit + rounding allowance)
  double worst_accel = 0;
};
AccelCheck measure(const std::vector<Edge>& edges, double limit) {
  AccelCheck c;
  double v_prev = 0, tau_prev = 0;  // at rest: speed 0 at the previous edge (tau_prev = 0)
  for (const Edge& e : edges) {
    if (e.interval_s == 0) {  // rest: the previous step must brake to zero
      if (tau_prev > 0) {
        const double a = std::abs(v_prev) / (tau_prev / 2);
        c.worst_accel = std::max(c.worst_accel, a);
        c.worst_ratio = std::max(c.worst_ratio, a / limit);
      }
      v_prev = 0;
      tau_prev = 0;
      continue;
    }
    const double v = e.dir / e.interval_s;
    const double dt = (tau_prev + e.interval_s) / 2;
    const double a = std::abs(v - v_prev) / dt;
    // each interval is exact to half a Q16 LSB: the speed to |v| lsb / tau
    const double lsb = 0.5 / 65536.0 / kF;
    const double allowance = (std::abs(v) * lsb / e.interval_s + (tau_prev > 0 ? std::abs(v_prev) * lsb / tau_prev : 0)) / dt;
    c.worst_accel = std::max(c.worst_accel, a);
    c.worst_ratio = std::max(c.worst_ratio, a / (limit + allowance));
    v_prev = v;
    tau_prev = e.interval_s;
  }
  if (tau_prev > 0) {  // ends moving: nothing to check
  }
  return c;
}

}  // namespace

TEST(StepRamp, LevelTableEntriesAreRoundedDifferencesOfRoots) {
  const uint32_t* t = ramp_detail::level_table();
  for (int n = 0; n <= 256; ++n) {
    const double exact = 1.0 / (std::sqrt(n + 1.0) + std::sqrt((double)n)) * 4294967296.0;
    EXPECT_EQ(t[n], (uint32_t)std::min(4294967295.0, std::floor(exact + 0.5))) << n;
  }
}

TEST(StepRamp, ReciprocalSquareRootTableEntries) {
  const uint16_t* t = rsqrt_table();
  for (int i = 0; i <= 192; ++i) {
    const double exact = 65536.0 / std::sqrt(1.0 + i / 64.0);
    EXPECT_EQ(t[i], (uint16_t)std::min(65535.0, std::floor(exact + 0.5))) << i;
  }
}

TEST(StepRamp, ReciprocalSquareRootAccuracy) {
  double worst = 0;
  for (uint64_t x = 1; x < (1ull << 32); x += 1 + x / 1013) {
    uint8_t s;
    const uint16_t r = rsqrt_normalised((uint32_t)x, s);
    worst = std::max(worst, std::abs(r * std::ldexp(1.0, s - 31) * std::sqrt((double)x) - 1));
  }
  std::printf("table reciprocal square root: worst relative error %.2e\n", worst);
  EXPECT_LT(worst, 7e-5);
}

TEST(StepRamp, ConfigurationRefusesGarbage) {
  static_assert(step_ramp_constants(kF, StepRampConfig{50000, 100}).status == RampStatus::ok,
                "usable at compile time");
  EXPECT_EQ(step_ramp_constants(kF, {0, 100}).status, RampStatus::accel_not_positive);
  EXPECT_EQ(step_ramp_constants(kF, {-5000, 100}).status, RampStatus::accel_not_positive);
  EXPECT_EQ(step_ramp_constants(kF, {1000, 100}).status, RampStatus::accel_too_low);  // sqrt(2/a) = 89k ticks
  EXPECT_EQ(step_ramp_constants(kF, {2000, 100}).status, RampStatus::ok);
  EXPECT_EQ(step_ramp_constants(kF, {50000, 0}).status, RampStatus::min_interval_invalid);
  EXPECT_EQ(step_ramp_constants(kF, {50000, 65535}).status, RampStatus::min_interval_invalid);
  EXPECT_EQ(step_ramp_constants(1000, {2000000000, 1}).status, RampStatus::accel_too_high);
  EXPECT_EQ(step_ramp_constants(kF, {2000, 1}).status, RampStatus::speed_range_too_wide);

  Ramp r;
  EXPECT_EQ(r.configure({50000, 100}), RampStatus::ok);
  EXPECT_EQ(r.configure({0, 100}), RampStatus::accel_not_positive);
  EXPECT_EQ(r.constants().status, RampStatus::ok);  // kept the good limits
  Ramp never;  // not configured: never steps
  never.set_speed(1000);
  EXPECT_EQ(never.next().interval_ticks, 0);
}

// The evaluated profile against (1) in double, with a_eff = 31a/32, at every level a ramp
// to 20 kHz at the lowest usable acceleration reaches (107k levels)
TEST(StepRamp, ProfileMatchesConstantAccelerationFormula) {
  Ramp r;
  ASSERT_EQ(r.configure({2000, 100}), RampStatus::ok);
  const double c = kF * std::sqrt(2.0 / (2000 * 31.0 / 32.0));
  double worst = 0;
  for (uint32_t n = 0; n < 110000; ++n) {
    const double exact = c / (std::sqrt(n + 1.0) + std::sqrt((double)n));
    const double got = r.interval_at_level(n) / 65536.0;
    worst = std::max(worst, std::abs(got / exact - 1));
    if (n > 0) {
      ASSERT_LE(r.interval_at_level(n), r.interval_at_level(n - 1)) << n;  // monotone
    }
  }
  std::printf("profile vs exact, worst relative error over 110,000 levels: %.2e\n", worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(StepRamp, SpeedToIntervalConversion) {
  double worst = 0;
  for (uint32_t v = Ramp::kMinSpeedStepsPerS; v < 2000000; v += 1 + v / 97) {
    const double got = Ramp::interval_for_speed_unclamped(v) / 65536.0;
    worst = std::max(worst, std::abs(got * v / kF - 1));
  }
  EXPECT_LT(worst, 5e-5);  // the speed is cut to 16 significant bits
  EXPECT_EQ(Ramp::interval_for_speed_unclamped(Ramp::kMinSpeedStepsPerS - 1), 0xFFFFFFFFu);
  EXPECT_LE(Ramp::interval_for_speed_unclamped(Ramp::kMinSpeedStepsPerS) >> 16, 65534u);
}

// Random speed commands (seeded) at random moments, positive and negative, for several
// accelerations: the acceleration between every pair of steps stays within the limit
TEST(StepRamp, AccelerationNeverAboveTheLimit) {
  std::mt19937 rng(20261201);
  for (int32_t accel : {2000, 8000, 50000, 400000}) {
    Ramp r;
    ASSERT_EQ(r.configure({accel, 100}), RampStatus::ok);
    std::uniform_int_distribution<int> pick_speed(-21000, 21000), pick_len(1, 3000);
    int next_change = 0;
    const auto edges = run(r, 400000, [&](int i) {
      if (i == next_change) {
        int v = pick_speed(rng);
        if (rng() % 5 == 0) v = 0;
        if (rng() % 7 == 0) v = v / 300;  // slow creep, below the first ramp step
        r.set_speed(v);
        next_change = i + pick_len(rng);
      }
    }, false);
    const AccelCheck c = measure(edges, accel);
    std::printf("a = %d: worst measured %.0f steps/s^2 (%.4f of the limit with rounding allowance)\n", accel,
                c.worst_accel, c.worst_ratio);
    EXPECT_LE(c.worst_ratio, 1.0) << accel;
  }
}

TEST(StepRamp, FirstAndLastStepsAreConstantAcceleration) {
  Ramp r;
  ASSERT_EQ(r.configure({50000, 100}), RampStatus::ok);
  const double a_eff = 50000 * 31.0 / 32.0;
  r.set_speed(5000);
  const Ramp::Step first = r.next();
  EXPECT_NEAR(r.last_interval_q16() / 65536.0 / kF, std::sqrt(2 / a_eff), 1e-7);
  EXPECT_EQ(first.dir, 1);
  for (int i = 0; i < 50; ++i) r.next();
  r.stop();
  uint32_t last = 0;
  while (r.next().interval_ticks) last = r.last_interval_q16();
  EXPECT_NEAR(last / 65536.0 / kF, std::sqrt(2 / a_eff), 1e-7);  // braked through tau(0)
  EXPECT_EQ(r.level(), 0u);
  EXPECT_FALSE(r.running());
}

// Exact positioning: from rest and from motion in either direction, to targets near and far,
// the ramp stops on the target step, at rest, within the acceleration limit
TEST(StepRamp, ExactStepCountToTarget) {
  std::mt19937 rng(7);
  Ramp r;
  ASSERT_EQ(r.configure({30000, 120}), RampStatus::ok);
  std::uniform_int_distribution<int> pick_target(-40000, 40000), pick_lead(0, 3000);
  for (int trial = 0; trial < 60; ++trial) {
    // some motion first, so that the move starts at speed (possibly away from the target)
    const int lead = pick_lead(rng);
    r.set_speed(trial % 2 ? 9000 : -9000);
    int32_t counted = r.position_steps();
    std::vector<Edge> edges;
    for (int i = 0; i < lead; ++i) {
      const Ramp::Step s = r.next();
      counted += s.dir;
      edges.push_back(Edge{r.last_interval_q16() / 65536.0 / kF, s.interval_ticks, s.dir});
    }
    const int32_t target = trial < 5 ? r.position_steps() + trial : pick_target(rng);  // includes 0..4 steps away
    r.move_to(target, 16000);
    int guard = 0;
    for (;;) {
      const Ramp::Step s = r.next();
      if (s.interval_ticks == 0) break;
      counted += s.dir;
      edges.push_back(Edge{r.last_interval_q16() / 65536.0 / kF, s.interval_ticks, s.dir});
      ASSERT_LT(++guard, 1000000);
    }
    edges.push_back(Edge{0, 0, 0});
    EXPECT_EQ(r.position_steps(), target) << trial;
    EXPECT_EQ(counted, target) << trial;  // the returned steps add up to the count
    EXPECT_EQ(r.level(), 0u);
    EXPECT_LE(measure(edges, 30000).worst_ratio, 1.0) << trial;
    EXPECT_FALSE(r.wants_step());
  }
}

// A reversal is a brake to level 0 and a start from it: no step in the new direction before
// the level is 0, and the acceleration across the reversal is within the limit
TEST(StepRamp, ReversalOnlyThroughZeroSpeed) {
  Ramp r;
  ASSERT_EQ(r.configure({40000, 100}), RampStatus::ok);
  r.set_speed(15000);
  std::vector<Edge> edges;
  for (int i = 0; i < 5000; ++i) {
    const Ramp::Step s = r.next();
    edges.push_back(Edge{r.last_interval_q16() / 65536.0 / kF, s.interval_ticks, s.dir});
  }
  const uint32_t level_before = r.level();
  ASSERT_GT(level_before, 2000u);
  r.set_speed(-15000);
  int positive_after = 0;
  for (int i = 0; i < 10000; ++i) {
    const uint32_t level = r.level();
    const Ramp::Step s = r.next();
    if (s.dir < 0) {
      EXPECT_TRUE(level == 0 || r.direction() < 0);
    }
    if (s.dir > 0) {
      ++positive_after;
      EXPECT_EQ(r.level(), level - 1);  // every forward step after the command is a braking step
    }
    edges.push_back(Edge{r.last_interval_q16() / 65536.0 / kF, s.interval_ticks, s.dir});
  }
  EXPECT_EQ((uint32_t)positive_after, level_before);  // braking from level L takes L steps
  EXPECT_LE(measure(edges, 40000).worst_ratio, 1.0);
}

TEST(StepRamp, NeverShorterThanTheMinimumInterval) {
  for (uint16_t min_ticks : {100, 137, 400}) {
    Ramp r;
    ASSERT_EQ(r.configure({200000, min_ticks}), RampStatus::ok);
    r.set_speed(1000000);  // far above what the motor allows
    uint32_t shortest = 0xFFFFFFFFu;
    uint16_t shortest_ticks = 0xFFFF;
    for (int i = 0; i < 60000; ++i) {
      const Ramp::Step s = r.next();
      shortest = std::min(shortest, r.last_interval_q16());
      shortest_ticks = std::min(shortest_ticks, s.interval_ticks);
    }
    EXPECT_EQ(shortest, (uint32_t)min_ticks << 16);  // reached, never passed
    EXPECT_EQ(shortest_ticks, min_ticks);
  }
}

// The whole ticks handed to the timer add up to the exact (Q16.16) sum within one tick, and
// at a steady speed the mean interval is F / speed
TEST(StepRamp, TimerTicksTrackTheExactProfile) {
  Ramp r;
  ASSERT_EQ(r.configure({50000, 80}), RampStatus::ok);
  r.set_speed(-17321);
  double exact = 0;
  uint64_t ticks = 0;
  double worst = 0;
  for (int i = 0; i < 40000; ++i) {
    const Ramp::Step s = r.next();
    exact += r.last_interval_q16() / 65536.0;
    ticks += s.interval_ticks;
    worst = std::max(worst, std::abs(exact - (double)ticks));
  }
  EXPECT_LT(worst, 1.0);
  uint64_t steady = 0;
  for (int i = 0; i < 17321; ++i) steady += r.next().interval_ticks;
  EXPECT_NEAR((double)steady / 17321, (double)kF / 17321, 0.01);
  EXPECT_EQ(r.direction(), -1);
}

// The same check on what the timer really does (integer tick edges), over windows of 2 ms:
// the 1-tick quantisation adds at most 2 ticks of timing error per window
TEST(StepRamp, WindowedAccelerationFromIntegerEdges) {
  Ramp r;
  const int32_t accel = 60000;
  ASSERT_EQ(r.configure({accel, 100}), RampStatus::ok);
  std::vector<uint64_t> t;  // edge times in ticks
  uint64_t now = 0;
  r.set_speed(20000);
  for (int i = 0; i < 20000; ++i) {
    if (i == 12000) r.set_speed(-20000);
    const Ramp::Step s = r.next();
    now += s.interval_ticks;
    t.push_back(now);
  }
  double worst = 0;
  const uint64_t window = kF / 500;  // 2 ms
  size_t i0 = 0;
  while (true) {
    size_t i1 = i0, i2;
    while (i1 < t.size() && t[i1] - t[i0] < window) ++i1;
    i2 = i1;
    while (i2 < t.size() && t[i2] - t[i1] < window) ++i2;
    if (i2 >= t.size()) break;
    const double v1 = (double)(i1 - i0) / ((t[i1] - t[i0]) / (double)kF);
    const double v2 = (double)(i2 - i1) / ((t[i2] - t[i1]) / (double)kF);
    const double dt = (t[i2] - t[i0]) / 2.0 / kF;
    // speeds are unsigned here: skip windows that contain the reversal
    if (t[i0] > 0 && (i0 > 12000 || i2 < 12000)) {  // skip the reversal
      const double tol = (v1 * 2.0 / (t[i1] - t[i0]) + v2 * 2.0 / (t[i2] - t[i1])) / dt;
      worst = std::max(worst, std::abs(v2 - v1) / (accel + tol));
    }
    i0 = i1;
  }
  EXPECT_LE(worst, 1.0);
}

// Seed 2, eq. 4.16: k_{i+1} = [-w + sqrt(w^2 + 4 w' a_s)] / (2 t0 w'), w = a_s / (k_i t0).
// (a) From the same interval, its next interval and the exact profile's agree in the first
// order: with q = w' (k t0)^2 they differ by q^2 / 2 (4.16: 1 - q + 2q^2, exact: 1 - q + 1.5q^2),
// and this ramp's step follows the exact one to 1.5 % of q (its interpolation).
// (b) From rest 4.16 gives 1/sqrt(w'), not sqrt(2/w'): its first step runs at twice the limit.
// (c) Measured like above, it then accelerates at 2 k_{i+1} / (k_i + k_{i+1}) of w'.
TEST(StepRamp, Seed2Equation416IsTheFirstOrderOfThisProfile) {
  Ramp r;
  ASSERT_EQ(r.configure({50000, 50}), RampStatus::ok);
  const double a = 50000 * 31.0 / 32.0;
  const double c = std::sqrt(2 / a);
  auto eq416 = [&](double tau_prev) {
    const double w = tau_prev > 0 ? 1.0 / tau_prev : 0.0;
    return (-w + std::sqrt(w * w + 4 * a)) / (2 * a);
  };
  auto exact = [&](double n) { return c / (std::sqrt(n + 1) + std::sqrt(n)); };
  for (uint32_t n : {20u, 300u, 1000u, 5000u, 20000u}) {
    const double tau = exact(n), next = exact(n + 1.0);
    const double q = a * tau * tau;
    EXPECT_NEAR((eq416(tau) / next - 1) / (q * q), 0.5, 0.05) << n;  // (a)
    const double ours_step = (r.interval_at_level(n) - (double)r.interval_at_level(n + 1)) / 65536.0 / kF;
    EXPECT_NEAR(ours_step / (tau - next), 1.0, 0.015) << n;
  }
  EXPECT_NEAR(eq416(0), 1 / std::sqrt(a), 1e-12);  // (b)
  EXPECT_NEAR(r.interval_at_level(0) / 65536.0 / kF, c, 1e-7);
  double tau = eq416(0), v = 1 / tau;
  const double first = v / (tau / 2) / a;
  EXPECT_NEAR(first, 2.0, 1e-9);
  for (int i = 0; i < 200; ++i) {  // (c)
    const double next = eq416(tau);
    const double measured = (1 / next - v) / ((tau + next) / 2);
    EXPECT_NEAR(measured / a, 2 * next / (tau + next), 1e-9);
    v = 1 / next;
    tau = next;
  }
}

TEST(StepRamp, RestAndHaltSemantics) {
  Ramp r;
  ASSERT_EQ(r.configure({50000, 100}), RampStatus::ok);
  EXPECT_FALSE(r.wants_step());
  EXPECT_EQ(r.next().interval_ticks, 0);
  r.set_speed(Ramp::kMinSpeedStepsPerS - 1);  // too slow for 16 bits: a stop
  EXPECT_FALSE(r.wants_step());
  r.set_speed(-40);  // creep below the first ramp step: one step per 25 ms, no ramp
  EXPECT_TRUE(r.wants_step());
  const Ramp::Step s = r.next();
  EXPECT_EQ(s.dir, -1);
  EXPECT_EQ(s.interval_ticks, 50000);
  EXPECT_EQ(r.level(), 0u);
  r.set_speed(10000);
  for (int i = 0; i < 300; ++i) r.next();
  EXPECT_FALSE(r.set_position(0));  // only at rest
  r.halt();
  EXPECT_EQ(r.next().interval_ticks, 0);
  EXPECT_EQ(r.level(), 0u);
  EXPECT_TRUE(r.set_position(1234));
  EXPECT_EQ(r.position_steps(), 1234);
}

// A creep slower than the longest interval is a stop, so no step waits longer than that for the
// next command (a position loop at rest asks for a few steps/s; the stick's next command must
// not queue behind a 262 ms interval).
TEST(StepRamp, LongestIntervalBoundsTheWaitForTheNextCommand) {
  Ramp r;
  StepRampConfig c{50000, 100};
  c.max_interval_ticks = 20000;  // 100 steps/s
  ASSERT_EQ(r.configure(c), RampStatus::ok);
  r.set_speed(99);
  EXPECT_FALSE(r.wants_step());
  r.set_speed(-101);
  ASSERT_TRUE(r.wants_step());
  const Ramp::Step s = r.next();
  EXPECT_EQ(s.dir, -1);
  EXPECT_LE(s.interval_ticks, 20000);
  c.max_interval_ticks = 99;  // below the shortest
  EXPECT_EQ(r.configure(c), RampStatus::max_interval_invalid);
}
