// The per-tick speed ramp of the step driver (lib/control/step_rate.h), with a model of the
// driver's step ISR (lib/drivers/steppers.cpp: edges one Q8 interval apart, a count of steps
// left after which the channel stops, a new interval from the edge after the scheduled one):
// acceleration never above the limit, exact arrival without overshoot, reversals through rest,
// speeds below the slowest one a stop, garbage commands saturated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "control/step_rate.h"

using namespace wmra::control;

namespace {

constexpr uint32_t kTickHz = 250000;  // Timer5
constexpr uint16_t kLoopHz = 1000;
constexpr int64_t kMinLeadTicks = 2, kRetimeMarginTicks = 4;  // steppers.cpp
constexpr int64_t kTicksPerLoop_q8 = (int64_t)kTickHz / kLoopHz * 256;
using Rate = StepRate<kTickHz, kLoopHz>;
StepRateConstants constants(const StepRateConfig& c) { return step_rate_constants(kTickHz, kLoopHz, c); }

// The firmware's J1 and J6 ramps (firmware/config/joints_config.h) and the 20 kHz budget test's
constexpr StepRateConfig kJ1{1222, 12, 12500};
constexpr StepRateConfig kJ6{8149, 12, 12500};
constexpr StepRateConfig kFast{100000, 12, 12500};

// The driver with its ISR, in Q8 timer ticks. service() is steppers::service for one channel.
struct Channel {
  Rate rate;
  bool running = false;
  int8_t dir = 0;
  int64_t next_edge_q8 = 0;
  uint32_t interval_q8 = 0;
  uint32_t left = 0;
  int64_t now_q8 = 0;
  int64_t position = 0;             // steps made, as the motor sees them
  std::vector<int64_t> edge_times;  // of every step, Q8 ticks
  std::vector<int8_t> edge_dirs;

  // one control period of the ISR's edges, then the service
  void tick(uint8_t ticks = 1) {
    const int64_t end = now_q8 + ticks * kTicksPerLoop_q8;
    int32_t made = 0;
    while (running && next_edge_q8 < end) {
      made += dir;
      edge_times.push_back(next_edge_q8);
      edge_dirs.push_back(dir);
      if (--left == 0) {
        running = false;
      } else {
        next_edge_q8 += interval_q8;
      }
    }
    now_q8 = end;
    position += made;
    rate.count_steps(made);
    const StepPlan p = rate.plan(ticks, running ? dir : 0);
    uint32_t l = p.interval_q8 == 0 ? 1 : p.steps_left;
    if (running) {
      left = l;
      if (p.interval_q8 != 0 && (p.interval_q8 >> 8) != (interval_q8 >> 8) && (interval_q8 >> 8) > kTicksPerLoop_q8 / 256 &&
          next_edge_q8 >= now_q8 + (kRetimeMarginTicks << 8)) {  // the edge retimed
        next_edge_q8 += ((int64_t)(p.interval_q8 >> 8) - (int64_t)(interval_q8 >> 8)) << 8;
        if (next_edge_q8 < now_q8 + (kMinLeadTicks << 8)) next_edge_q8 = now_q8 + (kMinLeadTicks << 8);
      }
      if (p.interval_q8 != 0) interval_q8 = p.interval_q8;
    } else if (p.interval_q8 != 0) {
      running = true;
      dir = rate.speed_q8() > 0 ? 1 : -1;
      left = l;
      interval_q8 = p.interval_q8;
      next_edge_q8 = now_q8 + (p.interval_q8 >> 8 << 8);
    }
  }
};

double speed_steps_s(const Rate& r) { return r.speed_q8() / 256.0; }

TEST(StepRate, ConfigurationRefusesGarbage) {
  static_assert(step_rate_constants(kTickHz, kLoopHz, kJ1).status == RateStatus::ok, "J1");
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {0, 12, 12500}).status, RateStatus::accel_not_positive);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {-5, 12, 12500}).status, RateStatus::accel_not_positive);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {1000, 0, 12500}).status, RateStatus::min_interval_invalid);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {1000, 1, 12500}).status, RateStatus::min_interval_invalid);  // 250 kHz
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {1000, 12, 12}).status, RateStatus::max_interval_invalid);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {1000, 12, 65535}).status, RateStatus::max_interval_invalid);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {3, 12, 65000}).status, RateStatus::accel_too_low);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {2000000000, 12, 12500}).status, RateStatus::accel_too_high);
  // 20 steps/s from rest is a jump unless a >= 2 x 20^2
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {799, 12, 12500}).status, RateStatus::slowest_too_fast);
  EXPECT_EQ(step_rate_constants(kTickHz, kLoopHz, {800, 12, 12500}).status, RateStatus::ok);
  Rate r;
  EXPECT_EQ(r.configure(constants(kJ1)), RateStatus::ok);
  EXPECT_EQ(r.configure(constants(StepRateConfig{0, 12, 12500})), RateStatus::accel_not_positive);
  EXPECT_EQ(r.constants().dv_q8_per_tick, step_rate_constants(kTickHz, kLoopHz, kJ1).dv_q8_per_tick);  // kept
  Channel never;  // not configured: never steps
  never.rate.set_speed(1000);
  never.rate.move_to(500, 1000);
  for (int k = 0; k < 100; ++k) never.tick();
  EXPECT_EQ(never.position, 0);
}

TEST(StepRate, IntervalIsTheSpeedsReciprocal) {
  Rate r;
  ASSERT_EQ(r.configure(constants(kFast)), RateStatus::ok);
  const StepRateConstants& k = r.constants();
  double worst = 0;
  for (uint32_t v = (uint32_t)k.v_min_q8; v <= (uint32_t)k.v_max_q8; v += 1 + v / 1013) {
    const double exact = kTickHz * 65536.0 / v;
    worst = std::max(worst, (std::fabs(r.interval_q8(v) - exact) - 1) / exact);  // beyond the Q8 LSB
  }
  EXPECT_LT(worst, 4e-5);  // the reciprocal table's UQ16 entries: 2^-15 at worst
  EXPECT_EQ(r.interval_q8((uint32_t)k.v_max_q8), 12u << 8);
  EXPECT_EQ(r.interval_q8((uint32_t)k.v_min_q8), 12500u << 8);
}

// interval_q8 shifts by whole bytes and folds the remaining bits into its product's constant:
// exactly the table reciprocal scaled by one shift, floor(kTickHz 2^8 h 2^(-7-e)) for speed =
// M 2^(e-16), h = the table's 2^31 / M, at every speed from 1 step/s (2^8) to 2^24 - 1, for
// the firmware's range of intervals and the widest one (4 steps/s to 41,666).
TEST(StepRate, IntervalIsTheTablesReciprocalAtEverySpeed) {
  for (const StepRateConfig& c : {kFast, StepRateConfig{100000, 6, 65534}}) {
    Rate r;
    ASSERT_EQ(r.configure(constants(c)), RateStatus::ok);
    const StepRateConstants& k = r.constants();
    int64_t differences = 0;
    for (uint32_t v = 1u << 8; v < (1u << 24); ++v) {
      int e = 32;
      uint32_t m = v;
      while (!(m & 0x80000000u)) {
        m <<= 1;
        --e;
      }
      const uint64_t h = wmra::fx::half_reciprocal_uq16((uint16_t)(m >> 16));
      const uint64_t p = (((uint64_t)kTickHz << 8) * h) >> (e + 7);
      const uint32_t expected = (uint32_t)std::min<uint64_t>(std::max<uint64_t>(p, k.min_interval_q8), k.max_interval_q8);
      if (r.interval_q8(v) != expected) ++differences;
    }
    EXPECT_EQ(differences, 0) << "max interval " << c.max_interval_ticks;
    EXPECT_EQ(r.interval_q8(0), k.max_interval_q8) << "below 1 step/s: the slowest interval";
    EXPECT_EQ(r.interval_q8(255), k.max_interval_q8);
    EXPECT_EQ(r.interval_q8(1u << 24), k.min_interval_q8) << "beyond any top speed: the shortest";
    EXPECT_EQ(r.interval_q8(0xFFFFFFFFu), k.min_interval_q8);
  }
}

// Per tick the speed changes by at most a dt, except the jump across the band below the slowest
// speed (rest <-> the slowest speed), which makes no steps, and the stop on a target (from the
// braking curve one step out, sqrt(2 a), with the tracking's lag: step_rate.h's `stoppable`).
void expect_acceleration_within_limit(const std::vector<double>& v, const StepRateConstants& k, uint8_t ticks) {
  const double dv = k.dv_q8_per_tick / 256.0 * ticks;
  const double v_min = k.v_min_q8 / 256.0;
  const double one_step = k.one_step_brake_q8 / 256.0;
  const double arrival = std::max(v_min, one_step) + 2 * dv + one_step;
  for (size_t n = 1; n < v.size(); ++n) {
    const double change = std::fabs(v[n] - v[n - 1]);
    const bool stop = v[n] == 0 && std::fabs(v[n - 1]) <= std::max(v_min + dv, arrival);
    const bool start = v[n - 1] == 0 && std::fabs(v[n]) == v_min;
    if (!stop && !start) {
      ASSERT_LE(change, dv + 1e-9) << "tick " << n << ": " << v[n - 1] << " -> " << v[n];
    }
  }
}

TEST(StepRate, AccelerationNeverAboveTheLimit) {
  std::mt19937 rng(7);
  for (const StepRateConfig& c : {kJ1, kJ6, kFast}) {
    for (uint8_t ticks : {1, 3}) {
      Channel ch;
      ASSERT_EQ(ch.rate.configure(constants(c)), RateStatus::ok);
      std::uniform_int_distribution<int32_t> speed(-25000, 25000), hold(1, 400);
      std::vector<double> v;
      for (int cmd = 0; cmd < 60; ++cmd) {
        const int32_t s = speed(rng);
        const bool move = cmd % 3 == 2;
        const int32_t target = (int32_t)ch.position + s / 4;
        for (int n = hold(rng); n > 0; --n) {
          if (move) {
            ch.rate.move_to(target, (uint32_t)std::abs(s));
          } else {
            ch.rate.set_speed(s);
          }
          ch.tick(ticks);
          v.push_back(speed_steps_s(ch.rate));
        }
      }
      expect_acceleration_within_limit(v, ch.rate.constants(), ticks);
      // and from the steps themselves: the step counts of neighbouring 20 ms windows differ by
      // at most a T^2, plus the counts' rounding (2) and the jump to the slowest speed
      const double window_s = 0.02;
      const int64_t window_q8 = (int64_t)(window_s * kTickHz * 256);
      std::vector<double> counts(ch.now_q8 / window_q8 + 1, 0.0);
      for (int64_t t : ch.edge_times) counts[t / window_q8] += 1;
      const double bound = c.accel_steps_s2 * window_s * window_s + 2 + ch.rate.constants().v_min_q8 / 256.0 * window_s;
      for (size_t w = 1; w + 1 < counts.size(); ++w) ASSERT_LE(std::fabs(counts[w] - counts[w - 1]), bound) << "window " << w;
    }
  }
}

TEST(StepRate, PositionMovesArriveExactlyWithoutOvershoot) {
  std::mt19937 rng(3);
  for (const StepRateConfig& c : {kJ1, kJ6, kFast}) {
    Channel ch;
    ASSERT_EQ(ch.rate.configure(constants(c)), RateStatus::ok);
    std::uniform_int_distribution<int32_t> dist(-30000, 30000);
    std::uniform_int_distribution<uint32_t> vmax(50, 30000);
    for (int m = 0; m < 12; ++m) {
      const int32_t target = (int32_t)ch.position + dist(rng) / (c.accel_steps_s2 < 5000 ? 10 : 1);
      const uint32_t v = vmax(rng);
      const int64_t from = ch.position;
      const int8_t sense = target > from ? 1 : -1;
      int n = 0;
      do {
        ch.rate.move_to(target, v);
        ch.tick();
        ASSERT_LE(sense * (ch.position - target), 0) << "overshoot";
        ASSERT_LT(++n, 200000);
      } while (ch.running || ch.position != target);
      EXPECT_EQ(ch.position, target);
      EXPECT_EQ(ch.rate.position_steps(), target);
      EXPECT_FALSE(ch.rate.moving());
    }
  }
}

TEST(StepRate, CruiseDistanceIsTheBrakingBoundOfTheMovesSpeed) {
  // from cruise_steps on, the move's speed c brakes in time after a tick (c (c + a dt) < 2 a d),
  // one step closer it does not: the ticks beyond it skip the braking products exactly where
  // they would have found braking possible
  for (const StepRateConfig& config : {kJ1, kJ6, kFast}) {
    const StepRateConstants k = constants(config);
    const uint64_t dv = std::min<uint64_t>(k.dv_q8_per_tick >> 8, (uint32_t)k.v_max_q8 >> 8);
    for (uint32_t speed = 1; speed <= ((uint32_t)k.v_max_q8 >> 8) + 10; speed += 7) {
      const MoveSpeed m = move_speed(k, speed);
      ASSERT_EQ(m.q8, speed_q8_of(k, speed));
      if (m.q8 == 0) continue;
      const uint64_t c = (uint32_t)m.q8 >> 8, need = c * (c + dv);
      EXPECT_LT(need, (uint64_t)k.two_a * m.cruise_steps) << speed;
      EXPECT_GE(need, (uint64_t)k.two_a * (m.cruise_steps - 1)) << speed;
    }
  }
}

TEST(StepRate, ArrivalSpeedIsSmall) {
  // the last interval before the target: the step rate braked to within a few a dt
  Channel ch;
  ASSERT_EQ(ch.rate.configure(constants(kFast)), RateStatus::ok);
  for (int n = 0; ch.running || ch.position != 20000; ++n) {
    ASSERT_LT(n, 5000) << "no arrival";
    ch.rate.move_to(20000, 20000);
    ch.tick();
  }
  const size_t n = ch.edge_times.size();
  ASSERT_GT(n, 2u);
  const double last_rate = kTickHz * 256.0 / (double)(ch.edge_times[n - 1] - ch.edge_times[n - 2]);
  // sqrt(2 a) is the braking curve's speed one step out
  EXPECT_LT(last_rate, 3 * std::sqrt(2.0 * kFast.accel_steps_s2) + 2 * kFast.accel_steps_s2 / 1000.0);
}

TEST(StepRate, ReversalOnlyThroughRest) {
  for (const StepRateConfig& c : {kJ1, kFast}) {
    Channel ch;
    ASSERT_EQ(ch.rate.configure(constants(c)), RateStatus::ok);
    std::vector<double> v;
    for (int n = 0; n < 4000; ++n) {
      ch.rate.set_speed(n < 1000 ? 1000 : -1000);
      ch.tick(n % 7 == 0 ? 5 : 1);
      v.push_back(speed_steps_s(ch.rate));
    }
    bool seen_rest = false, reversed = false;
    for (size_t n = 1; n < v.size(); ++n) {
      ASSERT_FALSE(v[n] < 0 && v[n - 1] > 0) << "speed changed sign without rest at " << n;
      if (v[n] == 0) seen_rest = true;
      if (v[n] < 0) reversed = seen_rest;
    }
    EXPECT_TRUE(reversed);
    // the steps: once negative, never positive again, and the direction changed only while stopped
    size_t first_negative = 0;
    while (first_negative < ch.edge_dirs.size() && ch.edge_dirs[first_negative] > 0) ++first_negative;
    ASSERT_LT(first_negative, ch.edge_dirs.size());
    for (size_t n = first_negative; n < ch.edge_dirs.size(); ++n) ASSERT_LT(ch.edge_dirs[n], 0);
    // and not sooner than the slowest interval after the last positive step (the channel stopped)
    EXPECT_GE(ch.edge_times[first_negative] - ch.edge_times[first_negative - 1], (int64_t)c.min_interval_ticks << 8);
  }
}

TEST(StepRate, SpeedsBelowTheSlowestAreAStop) {
  Channel ch;
  ASSERT_EQ(ch.rate.configure(constants(kJ6)), RateStatus::ok);
  const int32_t slowest = (ch.rate.constants().v_min_q8 + 255) / 256;  // 20 steps/s
  for (int n = 0; n < 2000; ++n) {
    ch.rate.set_speed(n % 2 ? slowest - 1 : -(slowest - 1));
    ch.tick();
  }
  EXPECT_EQ(ch.position, 0);
  EXPECT_FALSE(ch.rate.moving());
  // from speed: a command below the slowest brakes to rest
  for (int n = 0; n < 500; ++n) {
    ch.rate.set_speed(3000);
    ch.tick();
  }
  EXPECT_NEAR(speed_steps_s(ch.rate), 3000, 1);
  for (int n = 0; n < 1000; ++n) {
    ch.rate.set_speed(slowest - 1);
    ch.tick();
  }
  EXPECT_FALSE(ch.rate.moving());
  EXPECT_FALSE(ch.running);
  const int64_t at_rest = ch.position;
  for (int n = 0; n < 200; ++n) ch.tick();
  EXPECT_EQ(ch.position, at_rest);
  // and a position move slower than the slowest speed does not start
  ch.rate.move_to((int32_t)at_rest + 100, (uint32_t)slowest - 1);
  for (int n = 0; n < 200; ++n) ch.tick();
  EXPECT_EQ(ch.position, at_rest);
}

// plan() returns at once when the speed is already the wanted one: that is exact only because
// a speed other than 0 is never below the slowest speed (the band it jumps over). Random
// commands (speeds, moves, stops, halts; ticks of 1 to 6 periods) on the three ramps.
TEST(StepRate, ASpeedOtherThanZeroIsNeverBelowTheSlowest) {
  std::mt19937 rng(7);
  for (const StepRateConfig& c : {kJ1, kJ6, kFast}) {
    Channel ch;
    ASSERT_EQ(ch.rate.configure(constants(c)), RateStatus::ok);
    const int32_t v_min_q8 = ch.rate.constants().v_min_q8, top = ch.rate.constants().v_max_q8 / 256;
    int held = 0;
    for (int n = 0; n < 100000; ++n) {
      switch (rng() % 16) {
        case 0: ch.rate.set_speed((int32_t)(rng() % (2 * top + 1)) - top); break;
        case 1: ch.rate.set_speed((int32_t)(rng() % 81) - 40); break;  // around the slowest speed
        case 2: ch.rate.move_to((int32_t)ch.position + (int32_t)(rng() % 2001) - 1000, rng() % (uint32_t)(top + 1)); break;
        case 3: ch.rate.stop(); break;
        case 4:
          if (rng() % 8 == 0) ch.rate.halt();
          break;
        default: break;
      }
      ch.tick(rng() % 5 == 0 ? (uint8_t)(1 + rng() % 6) : 1);
      const int32_t v = ch.rate.speed_q8();
      ASSERT_TRUE(v == 0 || v >= v_min_q8 || v <= -v_min_q8) << "speed " << v << " Q8 at tick " << n;
      held += v != 0;
    }
    EXPECT_GT(held, 20000) << "moving often enough to test it";
  }
}

// drives_off() keeps the homing of a ramp stopped this slowly (firmware/app/arm_control.cpp)
TEST(StepRate, StopsWithinAStepUpToTheOneStepBrakingSpeed) {
  Channel ch;
  ASSERT_EQ(ch.rate.configure(constants(kJ1)), RateStatus::ok);
  const double one_step_brake = std::sqrt(2.0 * kJ1.accel_steps_s2);  // 49.4 steps/s
  EXPECT_TRUE(ch.rate.stops_within_a_step());
  bool seen_true_moving = false, seen_false = false;
  for (int n = 0; n < 300; ++n) {
    ch.rate.set_speed(-1000);
    ch.tick();
    const double v = std::fabs(speed_steps_s(ch.rate));
    EXPECT_EQ(ch.rate.stops_within_a_step(), v <= one_step_brake + 1.0 / 256) << v;
    seen_true_moving |= ch.rate.stops_within_a_step() && ch.rate.moving();
    seen_false |= !ch.rate.stops_within_a_step();
  }
  EXPECT_TRUE(seen_true_moving) << "a slow speed on the way up";
  EXPECT_TRUE(seen_false);
}

TEST(StepRate, GarbageCommandsSaturate) {
  Channel ch;
  ASSERT_EQ(ch.rate.configure(constants(kFast)), RateStatus::ok);
  const double v_max = kTickHz / 12.0;
  for (int32_t s : {INT32_MAX, INT32_MIN, INT32_MIN + 1, 2000000000}) {
    for (int n = 0; n < 400; ++n) {
      ch.rate.set_speed(s);
      ch.tick();
      ASSERT_LE(std::fabs(speed_steps_s(ch.rate)), std::floor(v_max) + 1e-9);
    }
  }
  // a move to the far end at any speed: the top speed, the target clamped to +-2^30
  ch.rate.move_to(INT32_MAX, UINT32_MAX);
  for (int n = 0; n < 400; ++n) ch.tick();
  EXPECT_NEAR(speed_steps_s(ch.rate), std::floor(v_max), 1);
  for (size_t n = 1; n < ch.edge_times.size(); ++n) ASSERT_GE(ch.edge_times[n] - ch.edge_times[n - 1], 12 << 8);
  ch.rate.halt();
  EXPECT_FALSE(ch.rate.moving());
  EXPECT_TRUE(ch.rate.set_position(INT32_MAX));
  EXPECT_EQ(ch.rate.position_steps(), Rate::kPositionLimit);
  ch.tick();  // the scheduled edge, if any
  ch.rate.set_speed(1000);  // no further at the count's limit
  const int32_t p = ch.rate.position_steps();
  for (int n = 0; n < 100; ++n) ch.tick();
  EXPECT_LE(ch.rate.position_steps(), p + 1);
}

TEST(StepRate, PositionOnlySetAtRest) {
  Channel ch;
  ASSERT_EQ(ch.rate.configure(constants(kJ6)), RateStatus::ok);
  ch.rate.set_speed(2000);
  for (int n = 0; n < 50; ++n) ch.tick();
  EXPECT_FALSE(ch.rate.set_position(123));
  ch.rate.stop();
  while (ch.rate.moving() || ch.running) ch.tick();
  EXPECT_TRUE(ch.rate.set_position(123));
  EXPECT_EQ(ch.rate.position_steps(), 123);
}

}  // namespace

// Another acceleration limit while the ramp runs (J1's follows the pose): the speed carries on,
// the ramp then changes speed at the new limit (and never above it), and constants of other
// intervals (another ramp's) or refused ones are ignored.
TEST(StepRate, AccelerationChangedWhileRunning) {
  const StepRateConfig j1x6{kJ1.accel_steps_s2 * 6, kJ1.min_interval_ticks, kJ1.max_interval_ticks};
  Channel ch;
  ASSERT_EQ(ch.rate.configure(constants(kJ1)), RateStatus::ok);
  for (int n = 0; n < 2000; ++n) {
    ch.rate.set_speed(1500);
    ch.tick();
  }
  ASSERT_NEAR(speed_steps_s(ch.rate), 1500, 1);
  ch.rate.set_acceleration(constants(j1x6));
  EXPECT_NEAR(speed_steps_s(ch.rate), 1500, 1) << "the speed carries on";
  std::vector<double> v;
  int ticks_to_rest = 0;
  for (; ticks_to_rest < 5000 && ch.rate.speed_q8() != 0; ++ticks_to_rest) {
    ch.rate.set_speed(0);
    ch.tick();
    v.push_back(speed_steps_s(ch.rate));
  }
  expect_acceleration_within_limit(v, ch.rate.constants(), 1);
  // 1500 steps/s at 6 x 1222 steps/s^2: 0.2 s (at kJ1's own, 1.2 s)
  EXPECT_NEAR(ticks_to_rest, 1500.0 / j1x6.accel_steps_s2 * kLoopHz, 10);
  StepRateConfig other = j1x6;
  other.min_interval_ticks = 20;
  ch.rate.set_acceleration(constants(other));
  EXPECT_EQ(ch.rate.constants().min_interval_q8, constants(kJ1).min_interval_q8) << "another ramp's intervals";
  ch.rate.set_acceleration(constants(StepRateConfig{0, 12, 12500}));
  EXPECT_EQ(ch.rate.constants().two_a, constants(j1x6).two_a) << "refused constants";
}
