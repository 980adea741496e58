// The speed ramp of a timer-driven stepper, run once per control tick (constant-rate segments,
// as grbl does, one segment per tick): the step ISR only repeats the interval handed to it and
// counts the steps it makes; this decides that interval.
//
// Each tick the speed v moves towards the wanted speed by at most a dt:
//   speed command   wanted = the command (|command| below the slowest speed: 0)
//   position move   towards the target (d = target - steps made): v + a dt (at most v_cmd)
//                   if it can still brake on the target after this tick (u (u + a dt) <= 2 a |d|,
//                   no root), else v - a dt
// and v changes sign only through 0, and only once the channel has made its last step the
// other way. The interval is kTickHz / v in Q8 timer ticks (the ISR carries the fraction),
// from a table reciprocal (no division at run time); |v| below the slowest speed (the longest
// interval) makes no steps. A position move hands the ISR the steps left, |d|: it stops the
// channel on the target itself (exact arrival, no overshoot, whatever the tick's rounding).
//
// Why per tick and not per step: the per-step ramp (the old step_ramp.h) took up to ~2,000
// cycles in the step ISR; three steppers at 20 kHz are 60,000 edges a second, so the ISR must
// stay near 100 cycles and the maths must run 1,000 times a second, not 60,000.
//
// Speeds are Q8 steps/s (int32), intervals Q8 ticks (uint32, below 2^24).
#pragma once

#include <stdint.h>

#include "control/control_math.h"
#include "kinematics/reciprocal.h"

namespace wmra {
namespace control {

enum class RateStatus : uint8_t {
  ok = 0,
  accel_not_positive,    // a <= 0
  accel_too_low,         // less than 1/256 step/s of speed change per control tick
  accel_too_high,        // a 256 / tick rate overflows, or one tick's change exceeds the top speed
  min_interval_invalid,  // outside [1, 65534] ticks, or its speed squared overflows 2^31
  max_interval_invalid,  // not above the shortest interval, or above 65534 ticks
  slowest_too_fast,      // v_min^2 > a/2: the jump from rest to the slowest speed v_min would be
                         // more than half of constant acceleration's speed at its first step
};

struct StepRateConfig {
  int32_t accel_steps_s2;       // acceleration limit
  uint16_t min_interval_ticks;  // shortest interval the driver and motor allow (top speed)
  // Longest interval: slower speeds are a stop. An edge once scheduled cannot be moved, so this
  // bounds how long a new command can wait behind a slow step.
  uint16_t max_interval_ticks;
};

struct StepRateConstants {
  RateStatus status;
  uint32_t dv_q8_per_tick;     // a / tick rate
  int32_t v_max_q8;            // kTickHz / min_interval
  int32_t v_min_q8;            // kTickHz / max_interval, rounded up: slower is no step
  uint32_t min_interval_q8;
  uint32_t max_interval_q8;
  uint32_t two_a;              // 2 a, steps/s^2
  uint32_t budget_saturation_steps;  // |d| from which 2 a |d| saturates 32 bits
  int32_t one_step_brake_q8;   // sqrt(2 a): the braking curve one step from the target
};

constexpr StepRateConstants step_rate_constants(uint32_t tick_hz, uint16_t loop_hz, const StepRateConfig& c) {
  StepRateConstants k{RateStatus::ok, 0, 0, 0, 0, 0, 0, 0, 0};
  if (c.accel_steps_s2 <= 0) {
    k.status = RateStatus::accel_not_positive;
    return k;
  }
  if (c.min_interval_ticks < 1 || c.min_interval_ticks > 65534) {
    k.status = RateStatus::min_interval_invalid;
    return k;
  }
  const uint32_t v_max = tick_hz / c.min_interval_ticks;  // steps/s
  if ((uint64_t)v_max * v_max >= (1ull << 31) || (uint64_t)v_max * 256 > 0x7FFFFFFFull) {
    k.status = RateStatus::min_interval_invalid;
    return k;
  }
  if (c.max_interval_ticks <= c.min_interval_ticks || c.max_interval_ticks > 65534) {
    k.status = RateStatus::max_interval_invalid;
    return k;
  }
  const uint64_t dv = (uint64_t)c.accel_steps_s2 * 256 / loop_hz;
  if (dv == 0) {
    k.status = RateStatus::accel_too_low;
    return k;
  }
  if (dv > (uint64_t)v_max * 256 || (uint64_t)c.accel_steps_s2 * 2 > 0x7FFFFFFFull) {
    k.status = RateStatus::accel_too_high;
    return k;
  }
  const uint64_t v_min_2 = ((uint64_t)tick_hz * tick_hz + (uint64_t)c.max_interval_ticks * c.max_interval_ticks - 1) /
                         ((uint64_t)c.max_interval_ticks * c.max_interval_ticks);
  if (2 * v_min_2 > (uint64_t)c.accel_steps_s2) {
    k.status = RateStatus::slowest_too_fast;
    return k;
  }
  k.dv_q8_per_tick = (uint32_t)dv;
  k.v_max_q8 = (int32_t)(v_max * 256);
  k.v_min_q8 = (int32_t)(((uint64_t)tick_hz * 256 + c.max_interval_ticks - 1) / c.max_interval_ticks);
  k.min_interval_q8 = (uint32_t)c.min_interval_ticks << 8;
  k.max_interval_q8 = (uint32_t)c.max_interval_ticks << 8;
  k.two_a = (uint32_t)c.accel_steps_s2 * 2;
  k.budget_saturation_steps = 0xFFFFFFFFu / k.two_a;
  k.one_step_brake_q8 = (int32_t)(isqrt64((uint64_t)k.two_a << 16) + 1);
  return k;
}

// |speed| steps/s as Q8, within the top speed; below the slowest speed, 0. Below the top speed
// it fits 16 bits (v_max^2 < 2^31: step_rate_constants), so the shift by 8 is a byte move;
// v_max_q8 is v_max 2^8 exactly.
constexpr int32_t speed_q8_of(const StepRateConstants& k, uint32_t speed_steps_s) {
  if (speed_steps_s >= (uint32_t)k.v_max_q8 >> 8) return k.v_max_q8;
  const int32_t q8 = (int32_t)((uint32_t)(uint16_t)speed_steps_s << 8);
  return q8 < k.v_min_q8 ? 0 : q8;
}

// a speed change dv (Q8) in steps/s, at most v_max
constexpr uint32_t dv_steps_s_of(const StepRateConstants& k, int32_t dv_q8) {
  return (uint32_t)dv_q8 >> 8 > (uint32_t)k.v_max_q8 >> 8 ? (uint32_t)k.v_max_q8 >> 8 : (uint32_t)dv_q8 >> 8;
}

// A position move's speed: Q8 (speed_q8_of), and the distance from which the ramp at it can
// still brake on the target after any tick of one loop period, c (c + a dt) < 2 a d: there a
// tick needs no braking products (two 32-bit library calls a tick; this is a division, once a
// move, at compile time for a constant speed). c (c + a dt) < 2^32: both at most v_max,
// v_max^2 < 2^31.
struct MoveSpeed {
  int32_t q8;
  uint32_t cruise_steps;
};
constexpr MoveSpeed move_speed(const StepRateConstants& k, uint32_t speed_steps_s) {
  const int32_t q8 = speed_q8_of(k, speed_steps_s);
  if (q8 == 0) return MoveSpeed{0, 0};
  const uint32_t c = (uint32_t)q8 >> 8;
  return MoveSpeed{q8, c * (c + dv_steps_s_of(k, (int32_t)k.dv_q8_per_tick)) / k.two_a + 1};
}

// A ramp's stop: a train whose interval is at least the start/stop interval (at or below
// the start/stop rate) ends at once: the motor's magnetic spring takes the rotor and its load
// from that speed to rest; a faster one slows at the stop's deceleration first
// (firmware/config/stop_config.h derives both from the motor and its load).
struct StopConstants {
  uint32_t dv_q8_per_tick;             // the stop's deceleration / tick rate
  uint16_t start_stop_interval_ticks;  // kTickHz / the start/stop rate
};
constexpr StopConstants stop_constants(uint32_t tick_hz, uint16_t loop_hz, int32_t decel_steps_s2, uint32_t start_stop_steps_s) {
  return StopConstants{(uint32_t)((uint64_t)decel_steps_s2 * 256 / loop_hz),
                       (uint16_t)(start_stop_steps_s == 0 || tick_hz / start_stop_steps_s > 0xFFFF ? 0xFFFF : tick_hz / start_stop_steps_s)};
}

// What the step ISR gets for the next tick.
struct StepPlan {
  uint32_t interval_q8;  // 0: no step (the channel stops at its next edge)
  uint16_t steps_left;   // the channel stops by itself after this many steps (0xFFFF: none near)
};

template <uint32_t kTickHz, uint16_t kLoopHz>
class StepRate {
 public:
  static constexpr int32_t kPositionLimit = (int32_t)1 << 30;
  static constexpr uint16_t kNoStop = 0xFFFF;

  // Sets the limits and halts; the position count is kept. On an error the ramp keeps its
  // previous limits (or, never configured, never moves). The constants come from
  // step_rate_constants(kTickHz, kLoopHz, config), at compile time where the configuration is
  // constant (at run time its 64-bit divisions take ~1 ms a ramp on the AVR).
  RateStatus configure(const StepRateConstants& k) {
    if (k.status != RateStatus::ok) return k.status;
    k_ = k;
    halt();
    return RateStatus::ok;
  }

  // Run at a signed speed (steps/s), within the acceleration limit; below the slowest speed
  // (|speed| < kTickHz / max_interval) it brakes to rest. Saturates at the top speed.
  void set_speed(int32_t speed_steps_s) {
    stopping_ = false;
    quick_ = false;
    want_q8_ = speed_q8(magnitude_u32(speed_steps_s));
    if (speed_steps_s < 0) want_q8_ = -want_q8_;
    has_target_ = false;
  }
  // Go to a position (steps) and stop there exactly, at most at max_speed_steps_s (a speed
  // below the slowest one brakes to rest instead). The speed's MoveSpeed is worked out (a
  // division) only when it is not the move's already: a caller may command every tick (the moves
  // to a pose take a MoveSpeed made at compile time).
  void move_to(int32_t target_steps, uint32_t max_speed_steps_s) {
    const bool same_speed = has_target_ && speed_q8_of(k_, max_speed_steps_s) == want_q8_;
    move_to(target_steps, same_speed ? MoveSpeed{want_q8_, cruise_steps_} : move_speed(k_, max_speed_steps_s));
  }
  // the same with the speed's MoveSpeed (move_speed() of this ramp's constants, at compile time)
  void move_to(int32_t target_steps, const MoveSpeed& speed) {
    const int32_t target = clamp_i32(target_steps, -kPositionLimit, kPositionLimit);
    if (!has_target_ || target != target_) stopping_ = false;
    quick_ = false;
    target_ = target;
    want_q8_ = speed.q8;
    cruise_steps_ = speed.cruise_steps;
    has_target_ = want_q8_ != 0;
  }
  // Brake to rest at the acceleration limit.
  void stop() {
    stopping_ = false;
    quick_ = false;
    want_q8_ = 0;
    has_target_ = false;
  }
  // Forget the speed at once (the caller has cut the driver: a hang, a release).
  void halt() {
    stop();
    v_q8_ = 0;
  }
  // The stop: the train ends at once at or below the start/stop rate, else the speed falls at
  // the stop's deceleration (configure_stop) to it, then ends. Kept until the next command.
  void quick_stop() {
    stop();
    quick_ = true;
  }
  // Another acceleration limit for the same ramp, while it runs: k from the same intervals as
  // the configured constants (the speed and any move carry on; a move's braking distance,
  // MoveSpeed, stays the one it was made with: made for the lowest limit, it brakes early).
  void set_acceleration(const StepRateConstants& k) {
    if (k.status == RateStatus::ok && k.min_interval_q8 == k_.min_interval_q8 && k.max_interval_q8 == k_.max_interval_q8) k_ = k;
  }
  void configure_stop(const StopConstants& s) { stop_ = s; }
  const StopConstants& stop_constants() const { return stop_; }

  // The steps the channel made since the last count (signed: in its direction).
  void count_steps(int32_t steps) { position_ += steps; }
  // Sets the position count (homing). Only at rest.
  bool set_position(int32_t steps) {
    if (v_q8_ != 0) return false;
    position_ = clamp_i32(steps, -kPositionLimit, kPositionLimit);
    return true;
  }

  // One control tick of `ticks` loop periods: the new speed and what the ISR does with it.
  // stepping_dir: the direction of the edge the channel still has scheduled (0: stopped); the
  // speed leaves 0 the other way only once that edge is made.
  StepPlan plan(uint8_t ticks, int8_t stepping_dir) {
    if (quick_) return plan_quick_stop(ticks);
    int32_t want = want_q8_;
    uint16_t steps_left = kNoStop;
    if (has_target_) {
      const Approach a = approach_target(dv_q8(ticks), ticks, stepping_dir);
      if (a.at_rest) return StepPlan{0, 0};
      want = a.want_q8;
      steps_left = a.steps_left;
    } else if ((want > 0 && position_ >= kPositionLimit) || (want < 0 && position_ <= -kPositionLimit)) {
      want = 0;  // the count saturates, never wraps (15 hours at 20 kHz from zero)
    }
    // At the wanted speed already (a speed command held, or at rest): the steps below leave
    // it as it is, since a speed not 0 is never below the slowest one.
    if (want == v_q8_) return want == 0 ? StepPlan{0, 0} : StepPlan{interval_q8_, steps_left};
    const int32_t dv = dv_q8(ticks);
    int32_t v = v_q8_;
    if ((v > 0 && want < 0) || (v < 0 && want > 0)) want = 0;  // reversals through rest
    if (v == 0 && ((stepping_dir > 0 && want < 0) || (stepping_dir < 0 && want > 0))) want = 0;
    if (want > v) {
      v = want - v > dv ? v + dv : want;
    } else {
      v = v - want > dv ? v - dv : want;
    }
    // below the slowest speed no steps are made: the speed jumps over that band, from rest to
    // the slowest speed and back (at most half the speed constant acceleration has at its
    // first step, sqrt(2 a): step_rate_constants checks it)
    if (magnitude_u32(v) < (uint32_t)k_.v_min_q8) v = want >= k_.v_min_q8 ? k_.v_min_q8 : want <= -k_.v_min_q8 ? -k_.v_min_q8 : 0;
    if (v == 0) {
      v_q8_ = 0;
      return StepPlan{0, 0};
    }
    if (v != v_q8_) interval_q8_ = interval_q8(magnitude_u32(v));  // at a steady speed: the last one
    v_q8_ = v;
    return StepPlan{interval_q8_, steps_left};
  }

  int32_t position_steps() const { return position_; }
  int32_t speed_q8() const { return v_q8_; }
  bool moving() const { return v_q8_ != 0; }
  // At most the braking curve's speed one step out (sqrt(2 a)): the ramp itself could stop
  // within one step, so cutting the driver now costs no more than cutting it at rest.
  bool stops_within_a_step() const { return magnitude_u32(v_q8_) <= (uint32_t)k_.one_step_brake_q8; }
  const StepRateConstants& constants() const { return k_; }

  // kTickHz 256 / (speed_q8 / 256), for speeds in [v_min, v_max]: the table reciprocal of
  // kinematics/reciprocal.h. speed = M 2^(e-16) with M in [2^15, 2^16) (h = 2^31 / M from the
  // table's 1/(2m)), kTickHz 2^16 / speed = floor(kTickHz 2^8 h 2^(-7-e)). The speed is below
  // 2^24 (v_max^2 < 2^31) and at least 2^8 (kTickHz >= 2^16 below), so it is shifted up by one
  // or two whole bytes (byte moves) and then by z < 8 bits, e = 32 - 8 bytes - z; the bits'
  // shift of the result is folded into the product's constant, kTickHz 2^(z+1) from a table:
  // floor(kTickHz 2^(z+1) h 2^-16), shifted down a byte for speeds from 2^16 (floors compose).
  // A loop of up to seven 32-bit shifts of the result took ~60 cycles of the ~290.
  __attribute__((always_inline)) uint32_t interval_q8(uint32_t speed_q8) const {
    if (speed_q8 < (1ul << 8)) return k_.max_interval_q8;  // below 1 step/s: slower than v_min
    if (speed_q8 >= (1ul << 24)) return k_.min_interval_q8;  // above v_max
    const bool one_byte = speed_q8 >= (1ul << 16);
    uint32_t v = speed_q8 << 8;
    if (!one_byte) v <<= 8;
    uint8_t z = 0;
    while (!(v & 0x80000000u)) {
      v <<= 1;
      ++z;
    }
    const uint16_t h = fx::half_reciprocal_uq16(fx::hi16(v));
    uint32_t p = mul_hi_u32xu16(flash_read_u32(tick_hz_shifted() + z), h);
    if (one_byte) p >>= 8;
    if (p < k_.min_interval_q8) return k_.min_interval_q8;
    return p > k_.max_interval_q8 ? k_.max_interval_q8 : p;
  }

 private:
  int32_t speed_q8(uint32_t speed_steps_s) const { return speed_q8_of(k_, speed_steps_s); }

  // Braking from u after this tick, a dt less each tick, stops within d steps: the tick at
  // u, then u - a dt, ... covers u^2 / (2a) + u dt / 2, so u (u + a dt) <= 2 a d (steps/s;
  // products below 2^32: u <= v_max, a dt capped at v_max, v_max^2 < 2^31).
  static bool can_brake_in(uint32_t speed_q8, uint32_t dv_steps_s, uint32_t budget) {
    const uint32_t u = speed_q8 >> 8;
    return u * (u + dv_steps_s) <= budget;
  }
  uint32_t brake_budget(uint32_t d) const { return d >= k_.budget_saturation_steps ? 0xFFFFFFFFu : k_.two_a * d; }
  uint32_t dv_steps_s(int32_t dv_q8) const { return dv_steps_s_of(k_, dv_q8); }
  // kTickHz 2^(z+1) for z = 0..7 (interval_q8)
  static const uint32_t* tick_hz_shifted() {
    static_assert(kTickHz < (1ul << 24), "kTickHz 2^8 fits 32 bits");
    static_assert(kTickHz >= (1ul << 16), "the slowest interval (65534 ticks) at least 1 step/s: a speed_q8 of 2^8");
    static const uint32_t table[8] WMRA_FLASH = {kTickHz << 1, kTickHz << 2, kTickHz << 3, kTickHz << 4,
                                                 kTickHz << 5, kTickHz << 6, kTickHz << 7, kTickHz << 8};
    return table;
  }
  // A position move's speed for this tick (magnitude, Q8): up by a dt (to the command) if it
  // can still brake on the target after it, else down by a dt; never below the slowest speed
  // (it would stall short of the target).
  uint32_t approach_speed(uint32_t speed, uint32_t command, uint32_t d, int32_t dv, uint8_t ticks) const {
    uint32_t up = speed + (uint32_t)dv;
    if (up > command) up = command;
    uint32_t next = up;
    if (!(ticks == 1 && d >= cruise_steps_) && !can_brake_in(up, dv_steps_s(dv), brake_budget(d))) {
      next = speed > (uint32_t)dv ? speed - (uint32_t)dv : 0;
    }
    return next < (uint32_t)k_.v_min_q8 ? (uint32_t)k_.v_min_q8 : next;
  }

  // The speed change allowed over `ticks` loop periods, < 2^31: accel_too_high bounds it (one
  // tick, or two: the ramps' period while the stick drives, without a product; two hardware
  // products otherwise, the same value modulo 2^32 as the 32-bit library product)
  int32_t dv_q8(uint8_t ticks) const {
    const int32_t dv = (int32_t)k_.dv_q8_per_tick;
    return ticks == 1 ? dv : ticks == 2 ? dv + dv : mul_i32_u8(dv, ticks);
  }
  // A position move's wanted speed (signed) and the steps the ISR may still make; at_rest: on
  // the target. Not inlined: the speed commands of running (the usual ticks) then keep their
  // registers for themselves; returned by value (in registers: references to the caller's
  // want and steps left kept them in its stack frame, loaded and stored every tick).
  struct Approach {
    int32_t want_q8;
    uint16_t steps_left;
    bool at_rest;
  };
  __attribute__((noinline)) Approach approach_target(int32_t dv, uint8_t ticks, int8_t stepping_dir) {
    int32_t want = want_q8_;
    uint16_t steps_left = kNoStop;
    const int32_t v = v_q8_;
    const int32_t to_go = target_ - position_;  // both within +-2^30
    const uint32_t d = magnitude_u32(to_go);
    if (d == 0 && stepping_dir == 0) {
      v_q8_ = 0;  // stopped on the target (by the ISR's count): at rest there
      return Approach{0, 0, true};
    }
    // Stopped by the ISR on the target when it can brake there (with a slack of the
    // tracking's 2 a dt and sqrt(2 a), the braking curve's speed one step out); once so,
    // it goes on (near the target the curve falls faster than a dt a tick). Faster (a new
    // target close ahead) it brakes at the limit, passes the target and comes back.
    const bool toward = d != 0 && (v == 0 || (v > 0) == (to_go > 0));
    const uint32_t speed = magnitude_u32(v);
    const uint32_t slack = (uint32_t)(2 * dv + k_.one_step_brake_q8);
    if (toward && (stopping_ || speed <= slack || can_brake_in(speed - slack, dv_steps_s(dv), brake_budget(d)))) {
      stopping_ = true;
      steps_left = d > kNoStop ? kNoStop : (uint16_t)d;  // the ISR stops on the target itself
      want = (int32_t)approach_speed(speed, (uint32_t)want, d, dv, ticks);
    } else {
      stopping_ = false;
      if (toward || d == 0) want = 0;
    }
    if (to_go < 0) want = -want;
    return Approach{want, steps_left, false};
  }

  // The stop's tick: down by its deceleration's dv, and to rest once at or below the start/stop
  // rate. Out of line: a stop's ticks are few, the running ones keep their registers.
  __attribute__((noinline)) StepPlan plan_quick_stop(uint8_t ticks) {
    const uint32_t speed = magnitude_u32(v_q8_);
    // (a deceleration of 2^24 Q8 a tick, 65,000 steps/s, or more stops any train at once: the
    // product then fits 32 bits)
    const uint32_t dv = stop_.dv_q8_per_tick >= (1ul << 24) ? 0xFFFFFFFFu : stop_.dv_q8_per_tick * ticks;
    const uint32_t slower = speed > dv ? speed - dv : 0;
    const uint32_t interval = slower < (uint32_t)k_.v_min_q8 ? 0xFFFFFFFFu : interval_q8(slower);
    if (interval >= (uint32_t)stop_.start_stop_interval_ticks << 8) {
      v_q8_ = 0;
      return StepPlan{0, 0};
    }
    v_q8_ = v_q8_ < 0 ? -(int32_t)slower : (int32_t)slower;
    interval_q8_ = interval;
    return StepPlan{interval_q8_, kNoStop};
  }

  StepRateConstants k_{RateStatus::ok, 0, 0, 0x7FFFFFFF, 0, 0, 0, 0, 0};  // not configured: no speed is fast enough
  StopConstants stop_{1ul << 24, 0};  // not configured: any speed stops at once
  bool quick_ = false;  // quick_stop() until the next command
  int32_t want_q8_ = 0;
  bool has_target_ = false;
  bool stopping_ = false;  // the ISR has the target's steps left
  int32_t target_ = 0;
  uint32_t cruise_steps_ = 0;  // |d| from which the move's speed brakes in time (move_to)
  int32_t position_ = 0;
  int32_t v_q8_ = 0;
  uint32_t interval_q8_ = 0;  // for v_q8_ (when not 0)
};

template <uint32_t kTickHz, uint16_t kLoopHz>
constexpr int32_t StepRate<kTickHz, kLoopHz>::kPositionLimit;
template <uint32_t kTickHz, uint16_t kLoopHz>
constexpr uint16_t StepRate<kTickHz, kLoopHz>::kNoStop;

}  // namespace control
}  // namespace wmra
