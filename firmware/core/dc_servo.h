// One DC joint's position servo: the reference (pot units) in, a duty out, with the
// plausibility checks of its potentiometer and motion.
//
// Controller: the PID of lib/control/pid.h with the reference speed's feedforward, or seed 1's
// relay with dead zone (config). Parking: a worm-geared joint holds itself unpowered, so once
// the reference stands (no feedforward) and the error has stayed within park_units for
// park_ticks, the duty is 0 and the PID restarts bumplessly from rest at every update, until the
// error stays out of twice the band for unpark_ticks (one noisy reading at a count's edge
// must not start the motor) or the reference moves; holding with the integral's effort would
// draw current (about 20 A stretched) for nothing. A moving reference never parks: a slow one
// would otherwise stop and restart on every pot count (stick-slip); its effort maps to a duty
// through the motion's direction (pid.h's duty_moving), continuous through effort 0, so a joint
// a count ahead slows instead of the duty reversing and the worm stopping it dead.
//
// Holding effort: the worm does not let the load drive the joint, so a joint that lifts its
// load needs a large effort before it moves at all (J3 lifting the stretched forearm and the
// payload: 70 % duty), and one that lowers it needs little. Restarting the integral from zero
// after each park left J3 standing for most of a second while the error built it up. So the
// integral's effort while the reference moves is remembered per direction, and a restart in
// that direction presets the integral with it if it lifts the load (not a restart to correct a
// standing error, nor one that lowers a load the worm holds).
// When the reference stops, the integral's moving effort is dropped (a worm-geared joint needs
// none at rest; kept, it pushed J3 24 mrad past a stopped reference), and a standing
// reference the joint has not reached gets the load's holding effort only if the error asks to
// lift (the worm lowers the load with none). The checks get the duty that was applied during the tick that
// ends with the reading, as PlausibilityMonitor requires.
#pragma once

#include <stdint.h>

#include "control/pid.h"
#include "control/plausibility.h"
#include "control/relay.h"
#include "core/gravity.h"

namespace wmra {
namespace core {

struct DcServoConfig {
  bool use_relay;
  control::PidConfig pid;
  control::RelayConfig relay;
  control::PlausibilityConfig checks;
  int16_t park_units;  // [0, 16383]: twice it fits 16 bits, and a saturated error compares right with it
  uint16_t park_ticks;
  uint16_t unpark_ticks;  // a standing reference: out of twice the band this long (not a noise spike)
  int16_t moving_friction_q15;  // the duty the worm's friction takes while the joint moves, [0, pid.min_duty]
};

// the servo's own limits, beyond its PID's, relay's and checks' (pid_check, relay_check,
// plausibility_check): with those, what configure() accepts, for a static_assert on a constant one
constexpr bool dc_servo_limits_ok(const DcServoConfig& c) {
  return c.park_units >= 0 && c.park_units <= 16383 && c.moving_friction_q15 >= 0 && c.moving_friction_q15 <= c.pid.min_duty_q15 &&
         c.moving_friction_q15 <= c.pid.out_max_q15 / 2;
}

class DcServo {
 public:
  bool configure(const DcServoConfig& c) {
    use_relay_ = c.use_relay;
    park_units_ = c.park_units;
    park_ticks_ = c.park_ticks;
    unpark_ticks_ = c.unpark_ticks;
    moving_friction_q15_ = c.moving_friction_q15;
    const bool ok = pid_.configure(c.pid) == control::PidStatus::ok && relay_.configure(c.relay) == control::RelayStatus::ok &&
           checks_.configure(c.checks) == control::PlausibilityStatus::ok && dc_servo_limits_ok(c);
    breakaway_slope_q15_ = pid_.moving_slope_q15(pid_.config().min_duty_q15);
    moving_slope_q15_ = pid_.moving_slope_q15(moving_friction_q15_);
    // 1 / slope - 1 in Q16, rounded down (the slope is above a half: a friction of at most half
    // the full duty, so this fits 16 bits)
    inverse_slope_less1_q16_ = (uint16_t)(((uint32_t)1 << 31) / moving_slope_q15_ - 65536u);
    return ok;
  }

  // from rest at the measured position (start-up, and after the bridge was switched off)
  void rest(int16_t measured_units) {
    pid_.start(measured_units, measured_units, 0);
    parked_ = true;
    in_band_ = 0;
    out_of_band_ = 0;
    applied_ = 0;
  }
  void reset_checks(int16_t measured_units) { checks_.reset(measured_units); }

  // The PID's effort at most up_q15 positive and down_q15 negative (magnitudes): the effort
  // that drives the joint at its speed limit each way, so that a joint catching up a lag does
  // not pass that limit (the reference's speed is limited, the joint's catch-up is not). The
  // stall check then counts the drive as saturated from each bound's duty on: below its
  // configured 95 % it would never see a jammed joint or a dead drive under a bound. (Each way
  // its own: a lifting joint stands still up to its holding effort and the stiction's.)
  void set_effort_bounds(int16_t up_q15, int16_t down_q15) {
    pid_.set_effort_bounds(up_q15, down_q15);
    // (the moving map's duties: the lower, which both maps reach at a bound; duty_for's alone
    // a joint that moves, then jams, never reaches)
    checks_.set_drive_bounds(control::Pid::duty_moving(up_q15, false, moving_friction_q15_, moving_slope_q15_),
                             control::Pid::duty_moving(down_q15, false, moving_friction_q15_, moving_slope_q15_));
  }

  // The reading of this tick (`ticks` control ticks after the last): its rail and jump checks,
  // and if servo_ticks is not 0 the motion checks over the servo's last run's duty, applied
  // since then (servo_ticks ago; every reading's by default). The duty changes only when the
  // servo runs: checked right before each run, a motion window spans one duty, and its times
  // count the servo's ticks (2 for a servo every second tick), not the checks.
  uint8_t check(int16_t measured_units, uint8_t ticks = 1) { return check(measured_units, ticks, ticks); }
  uint8_t check(int16_t measured_units, uint8_t ticks, uint8_t servo_ticks) {
    return checks_.update(applied_, measured_units, ticks, servo_ticks);
  }

  // The duty for the next tick. feedforward_q15: the effort the reference's speed needs; 0
  // (within the PID's zero band) for a standing reference. Not inlined: three copies unrolled
  // into the loop cost 3 KB of flash for a call's 50 cycles.
  // ticks: the control ticks since the last update (the servo's period, more after an overrun); the PID
  // and the park timers count time, not calls.
  // holding_q15: the effort that holds the joint's load (+: the drive pushes positive to hold
  // it), for a standing reference that the joint has not reached yet.
  // Positions are 16-bit (pot units: ADC counts x 16 < 16,368); the error is saturated to
  // +-32767 once: every threshold it meets (park_units, twice it) is below that, so the
  // saturation changes no decision.
  // On the AVR the common run (not parked, the PID, every second tick) is update_running's
  // asm (core/avr/dc_servo_running.h); update_portable is the C of every case, the host's, and
  // the asm's specification (test/avr/kinematics/fixed_products_avr.cpp compares the two on the chip).
  __attribute__((noinline)) int16_t update(int16_t reference_units, int16_t measured_units, int16_t feedforward_q15,
                                           int16_t holding_q15 = 0, uint8_t ticks = 1) {
#if defined(__AVR__)
    if (ticks == 2 && !parked_ && !use_relay_ && pid_.configured())
      return update_running(reference_units, measured_units, feedforward_q15, holding_q15);
#endif
    return update_portable(reference_units, measured_units, feedforward_q15, holding_q15, ticks);
  }
  // (on the AVR only the rare runs take it: out of line, its registers out of update's)
  __attribute__((noinline)) int16_t update_portable(int16_t reference_units, int16_t measured_units, int16_t feedforward_q15,
                                                                          int16_t holding_q15 = 0, uint8_t ticks = 1) {
    const int16_t e = control::sub_saturated_i16(reference_units, measured_units);
    const uint16_t error = control::distance_u16(e, 0);
    // (not -feedforward < zero band: -(-32768) is no int16, and the AVR's int is 16 bits)
    const bool still = feedforward_q15 < pid_.config().zero_band_q15 && feedforward_q15 > -pid_.config().zero_band_q15;
    const uint8_t direction = feedforward_q15 < 0 ? 1 : 0;
    if (still && !was_still_) pid_.preset_integral(0);
    was_still_ = still;
    // a standing reference ahead: the effort that lifts the load, if the error asks to lift (a
    // worm that does not back-drive lowers it with none)
    if (still && (e > 0) == (holding_q15 > 0) && e != 0) feedforward_q15 = holding_q15;
    if (parked_) {
      out_of_band_ = error > (uint16_t)(2 * park_units_) ? (uint16_t)(out_of_band_ + ticks) : 0;
      if (!still || out_of_band_ >= unpark_ticks_) {
        parked_ = false;
        in_band_ = out_of_band_ = 0;
        // lifting: the integral it moved with before, and the effort's ramp starts at the holding
        // effort (the worm holds the load up to it, so the step moves nothing): from 0, the D
        // term's kicks at every flip of a noisy pot count moved it down and up a rate step in
        // turn, and J2 lifted 50-90 ms after J3 and J4 lowered (S2's hand turned 0.9 deg);
        // lowering (the worm takes the load): none, the remembered effort pushed J4 off at twice
        // its reference's speed at S1's start (the hand 5.3 mm below its line after 0.2 s, 3.4 without)
        if (!still) {
          start_units_ = measured_units;
          broke_away_ = false;
          const int16_t lift_q15 = lifting_effort_q15(holding_q15, direction == 0 ? 1 : -1);
          const bool lifting = lift_q15 != 0;
          if (lifting) pid_.start_at_error(e, measured_units, holding_q15);
          set_breakaway(lift_q15 < 0 ? (int16_t)-lift_q15 : lift_q15);
          pid_.preset_integral(lifting ? holding_q15_[direction] : (int16_t)0);
        }
      } else {
        return stop(e, measured_units);
      }
    }
    in_band_ = still && error <= (uint16_t)park_units_ ? (uint16_t)(in_band_ + ticks) : 0;
    if (in_band_ >= park_ticks_) return stop(e, measured_units);
    // (a moving reference: the friction's compensation in its direction, pid.h's duty_moving)
    if (use_relay_) applied_ = relay_.update(reference_units, measured_units);
    else {
      const int16_t effort = pid_.update_effort(e, measured_units, feedforward_q15, ticks);
      // Until the pot shows the joint moved past the park band (two counts: one is a noisy
      // reading at a count's edge) its way since it left park, an effort past the load's
      // (lift_q15_) gets at least the breakaway's duty, the static friction's and the load's
      // (stiction: a joint that starts with the moving friction's 2 % less, J3 lifting in S1,
      // broke away 30 ms late); past that, the moving friction's map, which it is on once it
      // moves. The breakaway's map instead (min_duty + the effort) kept the static friction's
      // excess over the Coulomb's, 2.2 % duty or 40-100 mrad/s at J2-J4, on every motion until
      // the pot saw two counts (12 mrad at J4): the lowering joints ran at twice their
      // references' speed in the stick's ramp, S1's hand 4.7 mm below its line at 0.18 s.
      if (!broke_away_)
        broke_away_ = direction == 0 ? measured_units - start_units_ > park_units_
                                     : start_units_ - measured_units > park_units_;
      if (still) applied_ = pid_.duty_for(effort);
      else {
        const bool negative = direction != 0;
        int16_t a = negative ? (int16_t)-effort : effort;  // the effort the motion's way
        if (!broke_away_ && a > lift_q15_ && a < breakaway_effort_q15_) a = breakaway_effort_q15_;
        applied_ = control::Pid::duty_moving(negative ? (int16_t)-a : a, negative, moving_friction_q15_, moving_slope_q15_);
      }
    }
    if (!still) holding_q15_[direction] = (int16_t)(pid_.integral_q23() >> 8);
    return applied_;
  }

  bool parked() const { return parked_; }
  int16_t applied() const { return applied_; }
  const control::Pid& pid() const { return pid_; }

 private:
  // parked (or staying so): duty 0, the PID restarted from rest at the reading
  __attribute__((noinline)) int16_t stop(int16_t e, int16_t measured_units) {
    parked_ = true;
    pid_.start_at_error(e, measured_units, 0);
    applied_ = 0;
    return 0;
  }

#if defined(__AVR__)
  inline __attribute__((always_inline)) int16_t update_running(int16_t reference_units, int16_t measured_units,
                                                                int16_t feedforward_q15, int16_t holding_q15);
#endif

  // the efforts that hold the load a motion lifts (lift_q15 >= 0, the motion's way; 0 lowering:
  // the worm takes the load) and, the least one, on the moving map reach the breakaway's duty,
  // the static friction's and that load's (duty_for's dead-zone inverse of it: min_duty + slope
  // lift). On leaving park only, without a division (three servos leave it in one tick at a
  // move's start, a 32-bit division each took that tick past 1 ms): the excess over the moving
  // friction times 1 / slope through the reciprocal rounded down, at most a few below the least
  // effort, then up to it.
  __attribute__((noinline)) void set_breakaway(int16_t lift_q15) {
    lift_q15_ = lift_q15;
    const int16_t out_max = pid_.config().out_max_q15;
    const int16_t breakaway_q15 = control::Pid::duty_moving(lift_q15, false, pid_.config().min_duty_q15, breakaway_slope_q15_);
    const int16_t over_q15 = (int16_t)(breakaway_q15 - moving_friction_q15_);  // >= 0: friction <= min_duty
    int32_t a = over_q15 + (int32_t)fx::hi16(fx::mul_uu((uint16_t)over_q15, inverse_slope_less1_q16_));
    while (a < out_max && control::Pid::duty_moving((int16_t)a, false, moving_friction_q15_, moving_slope_q15_) < breakaway_q15) ++a;
    breakaway_effort_q15_ = (int16_t)(a > out_max ? out_max : a);
  }

  // update's state first: update_running reaches it through one pointer, within the AVR's
  // 64-byte displacement (its last stage from 20 bytes on: kTail)
  control::Pid pid_;
  int16_t holding_q15_[2] = {0, 0};  // moving up (positive), down
  bool parked_ = true;
  bool use_relay_ = false;
  uint16_t in_band_ = 0;
  bool was_still_ = true;
  int16_t park_units_ = 0;
  uint16_t park_ticks_ = 1;
  int16_t start_units_ = 0;  // the reading when the servo last left park for a moving reference
  bool broke_away_ = false;  // and the joint has moved past the park band its way since
  int16_t applied_ = 0;
  int16_t lift_q15_ = 0;              // set_breakaway's
  int16_t breakaway_effort_q15_ = 0;
  int16_t moving_friction_q15_ = 0;
  uint16_t moving_slope_q15_ = 32768;     // Pid::moving_slope_q15 of the moving friction
  uint16_t out_of_band_ = 0;
  uint16_t unpark_ticks_ = 1;
  uint16_t breakaway_slope_q15_ = 32768;  // and of the breakaway's (min_duty)
  uint16_t inverse_slope_less1_q16_ = 0;  // 1 / moving_slope_q15_ - 1, Q16, rounded down
  control::Relay relay_;
  control::PlausibilityMonitor checks_;
};

}  // namespace core
}  // namespace wmra

#if defined(__AVR__)
#include "core/avr/dc_servo_running.h"
#endif
