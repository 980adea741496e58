// J6's homing (firmware/core/wrist_homing.h) against a model of J6: a ramp with the firmware's
// acceleration, the zero cam +-2 deg about every whole turn and the switch's filter delay.
// Judged on the model's true angle: where J6 ends, what its count says there, how far it rolled
// and that it never left its +-360 deg range, with each belief the count can have.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <deque>

#include "core/ready_roll.h"
#include "core/wrist_homing.h"

namespace wmra {
namespace core {
namespace {

constexpr int32_t kTurn = 6400;  // J6's steps a turn (200 x 1/32, direct drive)
constexpr double kStepsPerDeg = kTurn / 360.0;
int32_t steps_of_deg(double deg) { return (int32_t)std::lround(deg * kStepsPerDeg); }
double deg_of(double steps) { return steps / kStepsPerDeg; }

constexpr double kAccel_steps_s2 = 4.0 * kTurn / (2 * M_PI);  // 4 rad/s^2
constexpr int kSwitchDelay_ms = 33;  // the simulator's RC filter (47 ms x ln 2); the firmware corrects 94
constexpr int kFirmwareDelay_ms = 94;

WristHomingConfig config() {
  const int32_t fast = (int32_t)std::lround(0.25 * kTurn / (2 * M_PI)), slow = (int32_t)std::lround(0.05 * kTurn / (2 * M_PI));
  return WristHomingConfig{kTurn,
                           kTurn,
                           steps_of_deg(2),
                           steps_of_deg(4),
                           steps_of_deg(1.5),
                           fast,
                           slow,
                           fast * kFirmwareDelay_ms / 1000,
                           slow * kFirmwareDelay_ms / 1000,
                           2 * kFirmwareDelay_ms,
                           -1,
                           {steps_of_deg(-30), steps_of_deg(90), steps_of_deg(-178), steps_of_deg(178)}};
}

// J6 and its drive: the ramp's interface as homing uses it, a speed within the acceleration
// limit each 1 ms tick, a move that stops on its target; the true angle is the count plus an
// offset the count does not know
struct Wrist {
  double x;             // the count, continuous (steps)
  double offset;        // true angle - count (steps)
  double v = 0;         // steps/s
  double want = 0;      // a speed command
  bool has_target = false;
  double target = 0;
  double target_speed = 0;
  double travel = 0, lowest = 0, highest = 0;  // steps rolled, the true angle's extremes
  bool stuck_open = false, stuck_closed = false;
  std::deque<bool> line;  // the switch as the firmware sees it, kSwitchDelay_ms late

  Wrist(double true_deg, double count_deg)
      : x(steps_of_deg(count_deg)), offset(true_deg * kStepsPerDeg - steps_of_deg(count_deg)) {
    lowest = highest = true_steps();
    line.assign(kSwitchDelay_ms, contact());
  }
  double true_steps() const { return x + offset; }
  bool contact() const {
    if (stuck_open) return false;
    if (stuck_closed) return true;
    const double t = true_steps();
    return std::fabs(t - kTurn * std::floor(t / kTurn + 0.5)) <= 2 * kStepsPerDeg;
  }
  // the ramp's interface
  int32_t position_steps() const { return (int32_t)std::lround(x); }
  void set_speed(int32_t s) {
    want = s;
    has_target = false;
  }
  void move_to(int32_t t, uint32_t speed) {
    has_target = true;
    target = t;
    target_speed = speed;
  }
  void stop() {
    want = 0;
    has_target = false;
  }
  bool set_position(int32_t steps) {
    if (v != 0) return false;
    offset += x - steps;
    x = steps;
    return true;
  }
  bool moving() const { return v != 0; }

  // one 1 ms tick
  void tick() {
    const double dt = 1e-3, dv = kAccel_steps_s2 * dt;
    double w = want;
    if (has_target) {
      const double d = target - x;
      if (std::fabs(d) < 0.5 && std::fabs(v) <= 2 * dv) {
        x = target;
        v = 0;
        w = 0;
      } else {
        w = (d > 0 ? 1 : -1) * std::min(target_speed, std::sqrt(2 * kAccel_steps_s2 * std::fabs(d)));
      }
    }
    v = w > v ? std::min(w, v + dv) : std::max(w, v - dv);
    if (std::fabs(v) < 1e-9) v = 0;
    double step = v * dt;
    if (has_target && (target - x) * step > 0 && std::fabs(step) > std::fabs(target - x)) step = target - x;
    x += step;
    travel += std::fabs(step);
    lowest = std::min(lowest, true_steps());
    highest = std::max(highest, true_steps());
    line.push_back(contact());
    line.pop_front();
  }
  bool seen_closed() const { return line.front(); }
  double error_deg() const { return deg_of(-offset); }
};

struct Result {
  bool done = false, failed = false, contradiction = false;
  double rolled_deg = 0, lowest_deg = 0, highest_deg = 0, end_deg = 0, count_error_deg = 0;
};

Result home(Wrist& w, WristBelief belief, WristHoming* kept = nullptr, double max_s = 200) {
  WristHoming local;
  WristHoming& h = kept ? *kept : local;
  if (!kept) h.configure(config());
  h.set_belief(belief);
  h.restart();
  Result r;
  for (int t = 0; t < max_s * 1000 && !h.done() && !h.failed(); ++t) {
    h.update(w.seen_closed(), w.moving(), 1, w);
    w.tick();
  }
  for (int t = 0; t < 500; ++t) w.tick();  // whatever is left of a stop
  r.done = h.done();
  r.failed = h.failed();
  r.contradiction = h.take_contradiction();
  r.rolled_deg = deg_of(w.travel);
  r.lowest_deg = deg_of(w.lowest);
  r.highest_deg = deg_of(w.highest);
  r.end_deg = deg_of(w.true_steps());
  r.count_error_deg = w.error_deg();
  return r;
}

// the whole turn nearest deg, half a turn from two: the one nearer 0
double nearest_turn_deg(double deg) {
  const double z = 360 * std::floor(deg / 360 + 0.5);
  const double other = deg > z ? z + 360 : z - 360;
  return std::fabs(deg - z) == 180 && std::fabs(other) < std::fabs(z) ? other : z;
}
// J6's range, and a step of the count's rounding
constexpr double kRangeDeg = 360 + 360.0 / kTurn;

// With J6's angle recorded, from any start within its range the homing rolls J6 at most
// 190 deg, ends on the switch of the turn that angle implies and knows the true angle.
TEST(WristHoming, FromARecordedAngleRollsAtMost190DegToItsTurn) {
  double largest = 0;
  for (double start = -360; start <= 360; start += 7.5) {
    Wrist w(start, start);
    const Result r = home(w, WristBelief::exact);
    ASSERT_TRUE(r.done) << "from " << start;
    const double zero = nearest_turn_deg(start) > 360 ? 360 : nearest_turn_deg(start) < -360 ? -360 : nearest_turn_deg(start);
    EXPECT_NEAR(r.end_deg, zero, 2.0) << "on the turn's cam, from " << start;
    EXPECT_NEAR(r.count_error_deg, 0, 0.25) << "the count is the true angle, from " << start;
    EXPECT_LE(r.rolled_deg, 190) << "from " << start;
    EXPECT_GE(r.lowest_deg, -kRangeDeg) << "from " << start;
    EXPECT_LE(r.highest_deg, kRangeDeg) << "from " << start;
    largest = std::max(largest, r.rolled_deg);
  }
  std::printf("recorded angle: the largest roll %.1f deg\n", largest);
  EXPECT_GT(largest, 170) << "a start half a turn from a switch rolls nearly half a turn";
}

// Without a recorded angle J6 is taken to be within half a turn of 0: the sweeps find 0's switch
// from anywhere in (-180, 180) deg, and a J6 near 0 rolls little.
TEST(WristHoming, WithoutARecordedAngleSweepsToZero) {
  double largest = 0, largest_within_20 = 0;
  for (double start = -179; start <= 179; start += 4.75) {
    Wrist w(start, 0);
    const Result r = home(w, WristBelief::within_half_turn);
    ASSERT_TRUE(r.done) << "from " << start;
    EXPECT_NEAR(r.end_deg, 0, 2.0) << "on 0's cam, from " << start;
    EXPECT_NEAR(r.count_error_deg, 0, 0.25) << "from " << start;
    EXPECT_GT(r.lowest_deg, -358.0) << "from " << start;
    EXPECT_LT(r.highest_deg, 358.0) << "from " << start;
    largest = std::max(largest, r.rolled_deg);
    if (std::fabs(start) <= 20) largest_within_20 = std::max(largest_within_20, r.rolled_deg);
  }
  std::printf("no recorded angle: the largest roll %.1f deg, within 20 deg of 0 %.1f deg\n", largest, largest_within_20);
  EXPECT_LE(largest_within_20, 120) << "from 20 deg off, at most about 120 deg in all";
}

// J6 at rest on its cam, at its very edge or anywhere on it, with each belief. (At the very
// edge the switch may read open: a count without an angle then sweeps, its first leg 30 deg.)
TEST(WristHoming, StartingOnTheCamHomesWithAShortRoll) {
  for (double start : {-2.0, -1.99, -1.0, 0.0, 0.5, 1.99, 2.0, 358.0, 359.0, 360.0, -358.0, -360.0}) {
    for (WristBelief b : {WristBelief::exact, WristBelief::within_half_turn}) {
      Wrist w(start, start);
      const Result r = home(w, b);
      ASSERT_TRUE(r.done) << "from " << start << " belief " << (int)b;
      EXPECT_NEAR(r.count_error_deg, 0, 0.25) << "from " << start << " belief " << (int)b;
      const bool edge = std::fabs(std::fabs(start - nearest_turn_deg(start)) - 2) < 0.05;
      EXPECT_LE(r.rolled_deg, b == WristBelief::within_half_turn && edge ? 80 : 20) << "from " << start << " belief " << (int)b;
      EXPECT_GE(r.lowest_deg, -kRangeDeg);
      EXPECT_LE(r.highest_deg, kRangeDeg);
    }
  }
}

// A recorded angle that is wrong (the wrist turned by hand while unpowered, a power loss while
// it rolled): the switch is not where the count says, J6 stops, the homing fails and says the
// count is contradicted once; the next homing does not move J6. J6 never leaves its range.
TEST(WristHoming, AWrongRecordedAngleStopsJ6WithinItsRange) {
  int contradicted = 0, runs = 0, whole_turns = 0;
  double largest = 0;
  for (double start = -355; start <= 355; start += 23) {
    for (double off : {-360.0, -250.0, -181.0, -90.0, -20.0, -6.0, 5.0, 20.0, 90.0, 181.0, 250.0, 360.0}) {
      const double believed = start + off;
      if (believed < -360 || believed > 360) continue;
      ++runs;
      Wrist w(start, believed);
      WristHoming h;
      h.configure(config());
      const Result r = home(w, WristBelief::exact, &h);
      largest = std::max(largest, r.rolled_deg);
      EXPECT_GE(r.lowest_deg, -kRangeDeg) << start << " believed " << believed;
      EXPECT_LE(r.highest_deg, kRangeDeg) << start << " believed " << believed;
      EXPECT_LE(r.rolled_deg, 190) << start << " believed " << believed;
      if (std::fabs(off) == 360) {
        // a whole turn off: the switch cannot tell (docs/arm-guide.md)
        ++whole_turns;
        EXPECT_TRUE(r.done);
        EXPECT_NEAR(std::fabs(r.count_error_deg), 360, 0.25) << start << " believed " << believed;
        continue;
      }
      ASSERT_TRUE(r.failed);
      EXPECT_TRUE(r.contradiction) << start << " believed " << believed;
      EXPECT_EQ(h.belief(), WristBelief::contradicted);
      ++contradicted;
      const double at = w.true_steps();
      const Result again = home(w, h.belief(), &h);
      EXPECT_TRUE(again.failed);
      EXPECT_FALSE(again.contradiction) << "said once";
      EXPECT_EQ(w.true_steps(), at) << "J6 not moved again";
    }
  }
  std::printf("wrong recorded angles: %d of %d contradicted (%d more a whole turn off, homed a turn off), the largest roll %.1f deg\n",
              contradicted, runs - whole_turns, whole_turns, largest);
  EXPECT_EQ(contradicted, runs - whole_turns);
}

// A few degrees off within the tolerance still homes, to the right turn
TEST(WristHoming, ARecordedAngleOffByLessThanTheToleranceHomes) {
  for (double start : {-300.0, -170.0, -40.0, 0.0, 35.0, 190.0, 350.0}) {
    for (double off : {-1.4, -0.5, 0.5, 1.4}) {
      Wrist w(start, start + off);
      const Result r = home(w, WristBelief::exact);
      ASSERT_TRUE(r.done) << start << " off " << off;
      EXPECT_NEAR(r.count_error_deg, 0, 0.25) << start << " off " << off;
    }
  }
}

// A broken switch: never closed, or always closed. The homing fails within J6's range (without
// an angle, from where that is taken to be: within half a turn of 0).
TEST(WristHoming, ABrokenSwitchFailsWithinTheRange) {
  for (double start : {-300.0, -100.0, 0.0, 100.0, 300.0}) {
    for (WristBelief b : {WristBelief::exact, WristBelief::within_half_turn}) {
      if (b == WristBelief::within_half_turn && std::fabs(start) >= 180) continue;
      for (bool closed : {false, true}) {
        Wrist w(start, b == WristBelief::exact ? start : 0);
        (closed ? w.stuck_closed : w.stuck_open) = true;
        w.line.assign(kSwitchDelay_ms, closed);
        const Result r = home(w, b);
        EXPECT_TRUE(r.failed) << start << " belief " << (int)b << " closed " << closed;
        EXPECT_GE(r.lowest_deg, -kRangeDeg);
        EXPECT_LE(r.highest_deg, kRangeDeg);
      }
    }
  }
}

// J6 lost steps while it ran (its switch closed where the count said it could not): the count
// is within half a turn, the sweep from where J6 stands finds the nearest switch and its turn.
TEST(WristHoming, AfterALostPositionTheSweepFindsTheTurn) {
  for (double start : {-340.0, -200.0, -20.0, 60.0, 250.0, 345.0}) {
    for (double off : {-40.0, -8.0, 8.0, 40.0}) {
      if (start + off < -360 || start + off > 360) continue;
      Wrist w(start, start + off);
      const Result r = home(w, WristBelief::within_half_turn);
      ASSERT_TRUE(r.done) << start << " off " << off;
      EXPECT_NEAR(r.count_error_deg, 0, 0.25) << start << " off " << off;
      EXPECT_GE(r.lowest_deg, -kRangeDeg);
      EXPECT_LE(r.highest_deg, kRangeDeg);
    }
  }
}

// The move to the ready pose after homing: J6 to the ready angle's turn nearest where it
// stands, at a soft stop where that turn is just beyond it (core/ready_roll.h)
TEST(ReadyRoll, TheReadyAnglesTurnNearestJ6) {
  const int32_t soft = steps_of_deg(357), slack = steps_of_deg(5);
  const auto roll = [&](double ready, double present) {
    return deg_of(ready_roll(steps_of_deg(ready), steps_of_deg(present), kTurn, -soft, soft, slack));
  };
  EXPECT_NEAR(roll(0, 1.7), 0, 0.1);
  EXPECT_NEAR(roll(0, -358.3), -357, 0.1) << "homed at -360: to the soft stop, not a turn back";
  EXPECT_NEAR(roll(0, 358.3), 357, 0.1);
  EXPECT_NEAR(roll(90, 358.3), 90, 0.1) << "450 is far beyond the soft stop: the turn inside";
  EXPECT_NEAR(roll(-90, 358.3), 270, 0.1);
  EXPECT_NEAR(roll(30, -140), 30, 0.1);
  EXPECT_NEAR(roll(30, -170), -330, 0.1);
  EXPECT_NEAR(roll(0, 180), 0, 0.1) << "half a turn either way: the ready angle";
}

}  // namespace
}  // namespace core
}  // namespace wmra
