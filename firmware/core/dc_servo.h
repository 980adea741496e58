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
  // (at start-up only: built for size, 1 KB at the firmware's -O3)
  __attribute__((cold, optimize("Os"))) bool configure(const DcServoConfig& c) {
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
  // asm; update_portable is the C of every case, the host's, and the asm's reference
  // (test/avr/fixed_products_avr.cpp compares the two on the chip).
  __attribute__((noinline)) int16_t update(int16_t reference_units, int16_t measured_units, int16_t feedforward_q15,
                                           int16_t holding_q15 = 0, uint8_t ticks = 1) {
#if defined(__AVR__)
    if (ticks == 2 && !parked_ && !use_relay_ && pid_.configured())
      return update_running(reference_units, measured_units, feedforward_q15, holding_q15);
#endif
    return update_portable(reference_units, measured_units, feedforward_q15, holding_q15, ticks);
  }
  // (on the AVR only the rare runs take it: out of line, its registers out of update's, and
  // small)
  __attribute__((noinline, cold, optimize("Os"))) int16_t update_portable(int16_t reference_units, int16_t measured_units, int16_t feedforward_q15,
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

#if defined(__AVR__)
// --- update_running: update_portable's common run in AVR asm (ticks 2, not parked, the PID)
// avr-gcc's update kept ~20 values live through the PID's terms and sums: 18 registers pushed,
// `this` and the terms spilled to the stack. Here three asm stages, each reaching the servo's
// and the PID's fields through Z (this), pass their few values in registers:
//   front   e = reference - reading (saturated), still / direction / park in f, the integral
//           dropped when the reference stops, the holding effort's substitution (t), the
//           in-band count, the breakaway's flag;
//   terms   the reading's change (the D term's, per tick), P and the integral's step (di), t =
//           feedforward - D (Q15, 32 bits), as Pid::update_effort forms them for two ticks;
//   settle  the effort's limits, the conditional integration, the rounded clamped effort, the
//           remembered integral, then the duty (duty_for still, duty_moving moving) and applied_.
// Bit-identical to update_portable (test/avr/fixed_products_avr.cpp: on the chip, random and
// edge vectors, every branch counted). A park leaves the front with f's bit 7 and the rest to C.
// r1 is the zero register outside the products (each clears it after); k their zero byte.

// r = a b, signed: fixed_point.h's mul_ss on bytes (a, b in r16-r23; rc the even one of r's top pair)
#define WMRA_DC_MUL_SS(ra, rb, rc, rd, al, ah, bl, bh)                                           \
  "clr   %[k]\n\t"                                                                               \
  "muls  " ah ", " bh "\n\t"                                                                     \
  "movw  " rc ", r0\n\t"                                                                         \
  "mul   " al ", " bl "\n\t"                                                                     \
  "movw  " ra ", r0\n\t"                                                                         \
  "mulsu " ah ", " bl "\n\t"                                                                     \
  "sbc   " rd ", %[k]\n\t"                                                                       \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "mulsu " bh ", " al "\n\t"                                                                     \
  "sbc   " rd ", %[k]\n\t"                                                                       \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "clr   __zero_reg__\n\t"
// r = a b, a unsigned, b signed: mul_us
#define WMRA_DC_MUL_US(ra, rb, rc, rd, al, ah, bl, bh)                                           \
  "clr   %[k]\n\t"                                                                               \
  "mulsu " bh ", " ah "\n\t"                                                                     \
  "movw  " rc ", r0\n\t"                                                                         \
  "mul   " al ", " bl "\n\t"                                                                     \
  "movw  " ra ", r0\n\t"                                                                         \
  "mulsu " bh ", " al "\n\t"                                                                     \
  "sbc   " rd ", %[k]\n\t"                                                                       \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "mul   " ah ", " bl "\n\t"                                                                     \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "clr   __zero_reg__\n\t"
// -x of a 16-bit register pair
#define WMRA_DC_NEG16(x) "neg   %B[" x "]\n\t" "neg   %A[" x "]\n\t" "sbc   %B[" x "], __zero_reg__\n\t"
// x = Pid::towards(effort_, the bound at Z+bound, rate_twice_); y the bound, m the step
#define WMRA_DC_TOWARDS(bound)                                                                   \
  "ldd   %A[x], Z+%[o_ef]\n\t"                                                                   \
  "ldd   %B[x], Z+%[o_ef]+1\n\t"                                                                 \
  "ldd   %A[y], Z+" bound "\n\t"                                                                 \
  "ldd   %B[y], Z+" bound "+1\n\t"                                                               \
  "ldd   %A[m], Z+%[o_rt]\n\t"                                                                   \
  "ldd   %B[m], Z+%[o_rt]+1\n\t"                                                                 \
  "sub   %A[x], %A[y]\n\t"                   /* from - to (its flags: from < to?) */            \
  "sbc   %B[x], %B[y]\n\t"                                                                       \
  "brlt  72f\n\t"                                                                                \
  "cp    %A[m], %A[x]\n\t"                   /* from >= to: the step below from - to? */        \
  "cpc   %B[m], %B[x]\n\t"                                                                       \
  "brlo  71f\n\t"                                                                                \
  "movw  %A[x], %A[y]\n\t"                   /* within the step: the bound */                   \
  "rjmp  74f\n"                                                                                  \
  "71:\n\t"                                                                                      \
  "sub   %A[x], %A[m]\n\t"                   /* (from - to) - step + to */                      \
  "sbc   %B[x], %B[m]\n\t"                                                                       \
  "add   %A[x], %A[y]\n\t"                                                                       \
  "adc   %B[x], %B[y]\n\t"                                                                       \
  "rjmp  74f\n"                                                                                  \
  "72:\n\t"                                                                                      \
  WMRA_DC_NEG16("x")                         /* to - from */                                    \
  "cp    %A[m], %A[x]\n\t"                                                                       \
  "cpc   %B[m], %B[x]\n\t"                                                                       \
  "brlo  73f\n\t"                                                                                \
  "movw  %A[x], %A[y]\n\t"                                                                       \
  "rjmp  74f\n"                                                                                  \
  "73:\n\t"                                                                                      \
  "sub   %A[m], %A[x]\n\t"                   /* step - (to - from) + to */                      \
  "sbc   %B[m], %B[x]\n\t"                                                                       \
  "add   %A[m], %A[y]\n\t"                                                                       \
  "adc   %B[m], %B[y]\n\t"                                                                       \
  "movw  %A[x], %A[m]\n"                                                                         \
  "74:\n\t"

inline __attribute__((always_inline)) int16_t DcServo::update_running(int16_t reference_units, int16_t measured_units,
                                                                      int16_t feedforward_q15, int16_t holding_q15) {
  constexpr control::Pid::Layout l = control::Pid::layout();
  static_assert(offsetof(DcServo, pid_) == 0, "the PID's fields at their own offsets");
  constexpr uint8_t kTail = 20;  // settle's duty reaches its fields from Z + kTail
  static_assert(l.min_duty >= kTail && offsetof(DcServo, moving_slope_q15_) + 1 - kTail <= 63 &&
                    offsetof(DcServo, broke_away_) <= 63 && offsetof(DcServo, start_units_) + 1 <= 63 &&
                    offsetof(DcServo, park_ticks_) + 1 <= 63 && offsetof(DcServo, holding_q15_) + 3 <= 63 &&
                    l.integral_limit + 3 <= 63,
                "update_running's fields within ldd's displacement (of Z, or of Z + kTail)");
  static_assert(l.bottom == l.top + 2, "the effort's bounds together");

  // front. e: the error; t: the feedforward (then the holding effort's), sign-extended; x: the
  // holding effort, then scratch; f: bit 0 still, bit 1 moving negative, bit 7 park
  int16_t e = reference_units, x = holding_q15, y;
  int32_t t = feedforward_q15;
  uint8_t f;
  asm volatile(
      "sub   %A[e], %A[m]\n\t"
      "sbc   %B[e], %B[m]\n\t"
      "brvc  1f\n\t"
      "sbrs  %B[e], 7\n\t"                // overflowed: the true sign is the result's inverse
      "rjmp  2f\n\t"
      "ldi   %A[e], 0xFF\n\t"
      "ldi   %B[e], 0x7F\n\t"
      "rjmp  3f\n"
      "2:\n\t"
      "ldi   %A[e], 0x01\n\t"
      "ldi   %B[e], 0x80\n\t"
      "rjmp  3f\n"
      "1:\n\t"
      "tst   %A[e]\n\t"                   // -32768 saturates to -32767
      "brne  3f\n\t"
      "cpi   %B[e], 0x80\n\t"
      "brne  3f\n\t"
      "inc   %A[e]\n"
      "3:\n\t"
      "clr   %[f]\n\t"
      "sbrc  %B[t], 7\n\t"
      "ldi   %[f], 2\n\t"                 // the motion's direction: the feedforward's, before the holding's
      "ldd   %A[y], Z+%[o_zb]\n\t"        // still: -zero band < feedforward < zero band
      "ldd   %B[y], Z+%[o_zb]+1\n\t"
      "cp    %A[t], %A[y]\n\t"
      "cpc   %B[t], %B[y]\n\t"
      "brge  4f\n\t"
      WMRA_DC_NEG16("y")
      "cp    %A[y], %A[t]\n\t"
      "cpc   %B[y], %B[t]\n\t"
      "brge  4f\n\t"
      "ori   %[f], 1\n\t"
      "ldd   __tmp_reg__, Z+%[o_ws]\n\t"
      "tst   __tmp_reg__\n\t"
      "brne  5f\n\t"
      "std   Z+%[o_i], __zero_reg__\n\t"  // the reference stopped: the moving effort's integral dropped
      "std   Z+%[o_i]+1, __zero_reg__\n\t"
      "std   Z+%[o_i]+2, __zero_reg__\n\t"
      "std   Z+%[o_i]+3, __zero_reg__\n\t"
      "inc   __tmp_reg__\n\t"
      "std   Z+%[o_ws], __tmp_reg__\n"
      "5:\n\t"
      "cp    %A[e], __zero_reg__\n\t"     // ahead (e != 0) the way the holding effort pushes: it
      "cpc   %B[e], __zero_reg__\n\t"     // is the feedforward (e > 0 with h > 0, e < 0 with h <= 0)
      "breq  6f\n\t"
      "sbrc  %B[e], 7\n\t"
      "rjmp  7f\n\t"
      "cp    __zero_reg__, %A[x]\n\t"
      "cpc   __zero_reg__, %B[x]\n\t"
      "brge  6f\n\t"
      "rjmp  8f\n"
      "7:\n\t"
      "cp    __zero_reg__, %A[x]\n\t"
      "cpc   __zero_reg__, %B[x]\n\t"
      "brlt  6f\n"
      "8:\n\t"
      "movw  %A[t], %A[x]\n\t"
      "clr   %C[t]\n\t"
      "sbrc  %B[t], 7\n\t"
      "com   %C[t]\n\t"
      "mov   %D[t], %C[t]\n"
      "6:\n\t"
      "movw  %A[y], %A[e]\n\t"            // |e| within the park band: counted in
      "sbrs  %B[e], 7\n\t"
      "rjmp  9f\n\t"
      WMRA_DC_NEG16("y")
      "9:\n\t"
      "ldd   %A[x], Z+%[o_pu]\n\t"
      "ldd   %B[x], Z+%[o_pu]+1\n\t"
      "cp    %A[x], %A[y]\n\t"
      "cpc   %B[x], %B[y]\n\t"
      "brlo  10f\n\t"
      "ldd   %A[x], Z+%[o_ib]\n\t"
      "ldd   %B[x], Z+%[o_ib]+1\n\t"
      "subi  %A[x], 0xFE\n\t"             // + 2 ticks
      "sbci  %B[x], 0xFF\n\t"
      "rjmp  11f\n"
      "4:\n\t"
      "std   Z+%[o_ws], __zero_reg__\n"   // moving
      "10:\n\t"
      "clr   %A[x]\n\t"
      "clr   %B[x]\n"
      "11:\n\t"
      "std   Z+%[o_ib], %A[x]\n\t"
      "std   Z+%[o_ib]+1, %B[x]\n\t"
      "ldd   %A[y], Z+%[o_pt]\n\t"
      "ldd   %B[y], Z+%[o_pt]+1\n\t"
      "cp    %A[x], %A[y]\n\t"
      "cpc   %B[x], %B[y]\n\t"
      "brlo  12f\n\t"
      "ori   %[f], 0x80\n\t"              // park: C's (e and the reading as they came)
      "rjmp  13f\n"
      "12:\n\t"
      "ldd   __tmp_reg__, Z+%[o_ba]\n\t"  // not yet broken away: the reading past the band its way?
      "tst   __tmp_reg__\n\t"
      "brne  13f\n\t"
      "ldd   %A[y], Z+%[o_su]\n\t"
      "ldd   %B[y], Z+%[o_su]+1\n\t"
      "sbrc  %[f], 1\n\t"
      "rjmp  14f\n\t"
      "movw  %A[x], %A[m]\n\t"            // reading - start > park band (int: 16 bits)
      "sub   %A[x], %A[y]\n\t"
      "sbc   %B[x], %B[y]\n\t"
      "ldd   %A[y], Z+%[o_pu]\n\t"
      "ldd   %B[y], Z+%[o_pu]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brge  13f\n\t"
      "rjmp  15f\n"
      "14:\n\t"
      "sub   %A[y], %A[m]\n\t"            // start - reading > park band
      "sbc   %B[y], %B[m]\n\t"
      "ldd   %A[x], Z+%[o_pu]\n\t"
      "ldd   %B[x], Z+%[o_pu]+1\n\t"
      "cp    %A[x], %A[y]\n\t"
      "cpc   %B[x], %B[y]\n\t"
      "brge  13f\n"
      "15:\n\t"
      "clr   __tmp_reg__\n\t"
      "inc   __tmp_reg__\n\t"
      "std   Z+%[o_ba], __tmp_reg__\n"
      "13:"
      : [e] "+d"(e), [t] "+r"(t), [x] "+d"(x), [y] "=&r"(y), [f] "=&d"(f)
      : [m] "r"(measured_units), "z"(this), [o_zb] "I"(l.zero_band), [o_ws] "I"(offsetof(DcServo, was_still_)),
        [o_i] "I"(l.integral), [o_pu] "I"(offsetof(DcServo, park_units_)), [o_ib] "I"(offsetof(DcServo, in_band_)),
        [o_pt] "I"(offsetof(DcServo, park_ticks_)), [o_ba] "I"(offsetof(DcServo, broke_away_)),
        [o_su] "I"(offsetof(DcServo, start_units_))
      : "memory");
  if (f & 0x80) return stop(e, measured_units);

  // terms: m the reading, then its change per tick; p P (Q23), di the integral's step (Q23),
  // t feedforward - D (Q15); x |e|, then |dm|, then with e D's product; y a gain or a limit
  // (the products' operands in r16-r23, where muls and mulsu reach them: named, as avr-gcc's
  // reload does not find three pairs of that class itself)
  register int16_t ea asm("r22") = e;
  register int16_t m asm("r18") = measured_units;
  register int16_t ya asm("r20");
  int32_t p, di;
  uint8_t k;
  asm volatile(
      "ldd   %A[y], Z+%[o_mp]\n\t"
      "ldd   %B[y], Z+%[o_mp]+1\n\t"
      "std   Z+%[o_mp], %A[m]\n\t"
      "std   Z+%[o_mp]+1, %B[m]\n\t"
      "sub   %A[m], %A[y]\n\t"            // the reading's change, saturated, halved (two ticks)
      "sbc   %B[m], %B[y]\n\t"
      "brvc  1f\n\t"
      "sbrs  %B[m], 7\n\t"
      "rjmp  2f\n\t"
      "ldi   %A[m], 0xFF\n\t"
      "ldi   %B[m], 0x7F\n\t"
      "rjmp  1f\n"
      "2:\n\t"
      "ldi   %A[m], 0x01\n\t"             // (-32768 halves as -32767 does: no case of its own)
      "ldi   %B[m], 0x80\n"
      "1:\n\t"
      "asr   %B[m]\n\t"
      "ror   %A[m]\n\t"
      "cp    %A[e], __zero_reg__\n\t"     // e = 0: no P, no integral's step
      "cpc   %B[e], __zero_reg__\n\t"
      "brne  3f\n\t"
      "clr   %A[p]\n\t"
      "clr   %B[p]\n\t"
      "movw  %C[p], %A[p]\n\t"
      "movw  %A[di], %A[p]\n\t"
      "movw  %C[di], %A[p]\n\t"
      "rjmp  20f\n"
      "3:\n\t"
      "movw  %A[x], %A[e]\n\t"
      "sbrs  %B[e], 7\n\t"
      "rjmp  4f\n\t"
      WMRA_DC_NEG16("x")
      "4:\n\t"
      "ldd   %A[y], Z+%[o_pl]\n\t"
      "ldd   %B[y], Z+%[o_pl]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brsh  5f\n\t"
      "clr   %A[p]\n\t"                   // P clamped: +-2^30
      "clr   %B[p]\n\t"
      "clr   %C[p]\n\t"
      "ldi   %[k], 0x40\n\t"
      "sbrc  %B[e], 7\n\t"
      "ldi   %[k], 0xC0\n\t"
      "mov   %D[p], %[k]\n\t"
      "rjmp  6f\n"
      "5:\n\t"
      "ldd   %A[y], Z+%[o_kpx]\n\t"
      "ldd   %B[y], Z+%[o_kpx]+1\n\t"
      "cp    %A[y], __zero_reg__\n\t"
      "cpc   %B[y], __zero_reg__\n\t"
      "breq  7f\n\t"
      WMRA_DC_MUL_US("%A[p]", "%B[p]", "%C[p]", "%D[p]", "%A[y]", "%B[y]", "%A[e]", "%B[e]")  // 16 Kp e
      "rjmp  6f\n"
      "7:\n\t"
      "ldd   %A[y], Z+%[o_kp]\n\t"        // Kp 16 past 16 bits (or Kp 0): e Kp, times 16
      "ldd   %B[y], Z+%[o_kp]+1\n\t"
      WMRA_DC_MUL_SS("%A[p]", "%B[p]", "%C[p]", "%D[p]", "%A[e]", "%B[e]", "%A[y]", "%B[y]")
      "ldi   %[k], 4\n"
      "8:\n\t"
      "lsl   %A[p]\n\t"
      "rol   %B[p]\n\t"
      "rol   %C[p]\n\t"
      "rol   %D[p]\n\t"
      "dec   %[k]\n\t"
      "brne  8b\n"
      "6:\n\t"
      "ldd   %A[y], Z+%[o_ki]\n\t"        // di = e Ki, clamped to the integral's limit past i_error_limit, twice
      "ldd   %B[y], Z+%[o_ki]+1\n\t"
      WMRA_DC_MUL_SS("%A[di]", "%B[di]", "%C[di]", "%D[di]", "%A[e]", "%B[e]", "%A[y]", "%B[y]")
      "ldd   %A[y], Z+%[o_il]\n\t"
      "ldd   %B[y], Z+%[o_il]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brsh  9f\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]\n\t"   // L - di < 0: L
      "cp    __tmp_reg__, %A[di]\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+1\n\t"
      "cpc   __tmp_reg__, %B[di]\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+2\n\t"
      "cpc   __tmp_reg__, %C[di]\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+3\n\t"
      "cpc   __tmp_reg__, %D[di]\n\t"
      "brge  10f\n\t"
      "ldd   %A[di], Z+%[o_l]\n\t"
      "ldd   %B[di], Z+%[o_l]+1\n\t"
      "ldd   %C[di], Z+%[o_l]+2\n\t"
      "ldd   %D[di], Z+%[o_l]+3\n\t"
      "rjmp  9f\n"
      "10:\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]\n\t"   // di + L < 0: -L (|di| <= 2^30: no overflow)
      "add   %A[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+1\n\t"
      "adc   %B[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+2\n\t"
      "adc   %C[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+3\n\t"
      "adc   %D[di], __tmp_reg__\n\t"
      "brpl  11f\n\t"
      "clr   %A[di]\n\t"
      "clr   %B[di]\n\t"
      "movw  %C[di], %A[di]\n"
      "11:\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]\n\t"
      "sub   %A[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+1\n\t"
      "sbc   %B[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+2\n\t"
      "sbc   %C[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+3\n\t"
      "sbc   %D[di], __tmp_reg__\n"
      "9:\n\t"
      "lsl   %A[di]\n\t"
      "rol   %B[di]\n\t"
      "rol   %C[di]\n\t"
      "rol   %D[di]\n"
      "20:\n\t"
      "cp    %A[m], __zero_reg__\n\t"     // t = feedforward - D; dm = 0: no D
      "cpc   %B[m], __zero_reg__\n\t"
      "breq  21f\n\t"
      "movw  %A[x], %A[m]\n\t"
      "sbrs  %B[m], 7\n\t"
      "rjmp  22f\n\t"
      WMRA_DC_NEG16("x")
      "22:\n\t"
      "ldd   %A[y], Z+%[o_dl]\n\t"
      "ldd   %B[y], Z+%[o_dl]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brsh  23f\n\t"
      "ldi   %[k], 0x40\n\t"              // D clamped: +-2^22
      "sbrc  %B[m], 7\n\t"
      "rjmp  24f\n\t"
      "sub   %C[t], %[k]\n\t"
      "sbc   %D[t], __zero_reg__\n\t"
      "rjmp  21f\n"
      "24:\n\t"
      "add   %C[t], %[k]\n\t"
      "adc   %D[t], __zero_reg__\n\t"
      "rjmp  21f\n"
      "23:\n\t"
      "ldd   %A[y], Z+%[o_kd]\n\t"
      "ldd   %B[y], Z+%[o_kd]+1\n\t"
      WMRA_DC_MUL_SS("%A[x]", "%B[x]", "%A[e]", "%B[e]", "%A[m]", "%B[m]", "%A[y]", "%B[y]")  // D in x (low), e (high)
      "sub   %A[t], %A[x]\n\t"
      "sbc   %B[t], %B[x]\n\t"
      "sbc   %C[t], %A[e]\n\t"
      "sbc   %D[t], %B[e]\n"
      "21:"
      : [e] "+a"(ea), [m] "+a"(m), [t] "+r"(t), [p] "=&r"(p), [di] "=&r"(di), [x] "=&r"(x), [y] "=&a"(ya), [k] "=&d"(k)
      : "z"(this), [o_mp] "I"(l.m_prev), [o_pl] "I"(l.p_error_limit), [o_kpx] "I"(l.kp_x16), [o_kp] "I"(l.kp),
        [o_ki] "I"(l.ki), [o_il] "I"(l.i_error_limit), [o_l] "I"(l.integral_limit), [o_dl] "I"(l.d_change_limit),
        [o_kd] "I"(l.kd)
      : "memory");

  // settle: e hi, then the effort; x lo, then the duty's base; p P + the integral, then the duty's product; di the trial
  // integral, then P + it; y:m scratch (24-bit limit - t), then the duty
  const DcServo* z = this;
  asm volatile(
      WMRA_DC_TOWARDS("%[o_top]")
      "movw  %A[e], %A[x]\n\t"
      WMRA_DC_TOWARDS("%[o_top]+2")  // (bottom_ after top_)
      "mov   %[k], %A[di]\n\t"            // di = 0 (e or Ki 0): the integral held
      "or    %[k], %B[di]\n\t"
      "or    %[k], %C[di]\n\t"
      "or    %[k], %D[di]\n\t"
      "brne  1f\n\t"
      "rjmp  6f\n"
      "1:\n\t"
      "bst   %D[di], 7\n\t"               // T: di < 0, the error's sign
      "ldd   __tmp_reg__, Z+%[o_i]\n\t"   // trial = integral + di (within +-L and |di| <= 2L: no
      "add   %A[di], __tmp_reg__\n\t"     // overflow), clamped on di's side only
      "ldd   __tmp_reg__, Z+%[o_i]+1\n\t"
      "adc   %B[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+2\n\t"
      "adc   %C[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+3\n\t"
      "adc   %D[di], __tmp_reg__\n\t"
      "ldd   %A[y], Z+%[o_l]\n\t"         // y:m = L
      "ldd   %B[y], Z+%[o_l]+1\n\t"
      "ldd   %A[m], Z+%[o_l]+2\n\t"
      "ldd   %B[m], Z+%[o_l]+3\n\t"
      "brts  2f\n\t"
      "cp    %A[y], %A[di]\n\t"           // e > 0: L < trial: L
      "cpc   %B[y], %B[di]\n\t"
      "cpc   %A[m], %C[di]\n\t"
      "cpc   %B[m], %D[di]\n\t"
      "brge  3f\n\t"
      "movw  %A[di], %A[y]\n\t"
      "movw  %C[di], %A[m]\n"
      "3:\n\t"
      "add   %A[di], %A[p]\n\t"           // s = P + trial
      "adc   %B[di], %B[p]\n\t"
      "adc   %C[di], %C[p]\n\t"
      "adc   %D[di], %D[p]\n\t"
      "movw  %A[y], %A[e]\n\t"            // hi - t in 24 bits (y, m's low byte): |hi - t| < 2^23
      "clr   %A[m]\n\t"
      "sbrc  %B[e], 7\n\t"
      "com   %A[m]\n\t"
      "sub   %A[y], %A[t]\n\t"
      "sbc   %B[y], %B[t]\n\t"
      "sbc   %A[m], %C[t]\n\t"
      "ldi   %[k], 16\n\t"                // integrate if s <= (hi - t) 256 + 15: s < that + 1
      "cp    %A[di], %[k]\n\t"
      "cpc   %B[di], %A[y]\n\t"
      "cpc   %C[di], %B[y]\n\t"
      "cpc   %D[di], %A[m]\n\t"
      "brlt  5f\n\t"
      "rjmp  6f\n"
      "2:\n\t"
      "add   %A[y], %A[di]\n\t"           // e < 0: trial + L < 0: -L (trial less that sum)
      "adc   %B[y], %B[di]\n\t"
      "adc   %A[m], %C[di]\n\t"
      "adc   %B[m], %D[di]\n\t"
      "brpl  4f\n\t"
      "sub   %A[di], %A[y]\n\t"
      "sbc   %B[di], %B[y]\n\t"
      "sbc   %C[di], %A[m]\n\t"
      "sbc   %D[di], %B[m]\n"
      "4:\n\t"
      "add   %A[di], %A[p]\n\t"           // s = P + trial
      "adc   %B[di], %B[p]\n\t"
      "adc   %C[di], %C[p]\n\t"
      "adc   %D[di], %D[p]\n\t"
      "movw  %A[y], %A[x]\n\t"            // lo - t in 24 bits
      "clr   %A[m]\n\t"
      "sbrc  %B[x], 7\n\t"
      "com   %A[m]\n\t"
      "sub   %A[y], %A[t]\n\t"
      "sbc   %B[y], %B[t]\n\t"
      "sbc   %A[m], %C[t]\n\t"
      "cp    %B[di], %A[y]\n\t"           // integrate if s >= (lo - t) 256 (s's low byte against
      "cpc   %C[di], %B[y]\n\t"           // 0 borrows nothing)
      "cpc   %D[di], %A[m]\n\t"
      "brlt  6f\n"
      "5:\n\t"
      "sub   %A[di], %A[p]\n\t"           // integrate: the trial (s - P) stored, the sum is s
      "sbc   %B[di], %B[p]\n\t"
      "sbc   %C[di], %C[p]\n\t"
      "sbc   %D[di], %D[p]\n\t"
      "std   Z+%[o_i], %A[di]\n\t"
      "std   Z+%[o_i]+1, %B[di]\n\t"
      "std   Z+%[o_i]+2, %C[di]\n\t"
      "std   Z+%[o_i]+3, %D[di]\n\t"
      "add   %A[p], %A[di]\n\t"
      "adc   %B[p], %B[di]\n\t"
      "adc   %C[p], %C[di]\n\t"
      "adc   %D[p], %D[di]\n\t"
      "rjmp  7f\n"
      "6:\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]\n\t"   // held: the sum with the integral as it is
      "add   %A[p], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+1\n\t"
      "adc   %B[p], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+2\n\t"
      "adc   %C[p], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+3\n\t"
      "adc   %D[p], __tmp_reg__\n"
      "7:\n\t"
      "lsl   %A[p]\n\t"                   // floor((sum + 128) / 256): bit 7 rounds up; |.| < 2^23,
      "adc   %B[p], __zero_reg__\n\t"     // in bytes B..D
      "adc   %C[p], __zero_reg__\n\t"
      "adc   %D[p], __zero_reg__\n\t"
      "clr   %[k]\n\t"                    // u = that + t (|u| < 2^24)
      "sbrc  %D[p], 7\n\t"
      "com   %[k]\n\t"
      "add   %A[t], %B[p]\n\t"
      "adc   %B[t], %C[p]\n\t"
      "adc   %C[t], %D[p]\n\t"
      "adc   %D[t], %[k]\n\t"
      "clr   %[k]\n\t"                    // u > hi: hi
      "sbrc  %B[e], 7\n\t"
      "com   %[k]\n\t"
      "cp    %A[e], %A[t]\n\t"
      "cpc   %B[e], %B[t]\n\t"
      "cpc   %[k], %C[t]\n\t"
      "cpc   %[k], %D[t]\n\t"
      "brlt  8f\n\t"
      "clr   %[k]\n\t"                    // u < lo: lo; else u
      "sbrc  %B[x], 7\n\t"
      "com   %[k]\n\t"
      "movw  %A[e], %A[x]\n\t"
      "cp    %A[t], %A[x]\n\t"
      "cpc   %B[t], %B[x]\n\t"
      "cpc   %C[t], %[k]\n\t"
      "cpc   %D[t], %[k]\n\t"
      "brlt  8f\n\t"
      "movw  %A[e], %A[t]\n"
      "8:\n\t"
      "std   Z+%[o_ef], %A[e]\n\t"
      "std   Z+%[o_ef]+1, %B[e]\n\t"
      "sbrc  %[f], 0\n\t"                 // moving: the integral's effort remembered its way
      "rjmp  9f\n\t"
      "ldd   %A[y], Z+%[o_i]+1\n\t"
      "ldd   %B[y], Z+%[o_i]+2\n\t"
      "sbrc  %[f], 1\n\t"
      "rjmp  10f\n\t"
      "std   Z+%[o_h], %A[y]\n\t"
      "std   Z+%[o_h]+1, %B[y]\n\t"
      "rjmp  9f\n"
      "10:\n\t"
      "std   Z+%[o_h]+2, %A[y]\n\t"
      "std   Z+%[o_h]+3, %B[y]\n"
      "9:\n\t"
      "adiw  r30, %[tail]\n\t"
      "sbrs  %[f], 0\n\t"
      "rjmp  13f\n\t"
      "movw  %A[y], %A[e]\n\t"            // still: the dead-zone inverse (duty_for) of a = |effort|
      "sbrs  %B[e], 7\n\t"
      "rjmp  11f\n\t"
      WMRA_DC_NEG16("y")
      "11:\n\t"
      "ldd   %A[m], Z+%[o_zb]\n\t"        // a = 0 or within the zero band: 0
      "ldd   %B[m], Z+%[o_zb]+1\n\t"
      "cp    %A[y], __zero_reg__\n\t"
      "cpc   %B[y], __zero_reg__\n\t"
      "breq  12f\n\t"
      "cp    %A[y], %A[m]\n\t"
      "cpc   %B[y], %B[m]\n\t"
      "brlo  12f\n\t"
      "ldd   %A[m], Z+%[o_sl]\n\t"        // min_duty + (slope a)'s bits 15..30
      "ldd   %B[m], Z+%[o_sl]+1\n\t"
      "ldd   %A[x], Z+%[o_md]\n\t"
      "ldd   %B[x], Z+%[o_md]+1\n\t"
      "rjmp  14f\n"
      "12:\n\t"
      "clr   %A[y]\n\t"
      "clr   %B[y]\n\t"
      "rjmp  16f\n"
      "13:\n\t"
      "movw  %A[y], %A[e]\n\t"            // moving: a = the effort the motion's way (duty_moving)
      "sbrs  %[f], 1\n\t"
      "rjmp  15f\n\t"
      WMRA_DC_NEG16("y")
      "15:\n\t"
      "ldd   __tmp_reg__, Z+%[o_ba]\n\t"  // not broken away, past the load's effort, below the
      "tst   __tmp_reg__\n\t"             // breakaway's: the breakaway's
      "brne  17f\n\t"
      "ldd   %A[m], Z+%[o_lift]\n\t"
      "ldd   %B[m], Z+%[o_lift]+1\n\t"
      "cp    %A[m], %A[y]\n\t"
      "cpc   %B[m], %B[y]\n\t"
      "brge  17f\n\t"
      "ldd   %A[m], Z+%[o_bre]\n\t"
      "ldd   %B[m], Z+%[o_bre]+1\n\t"
      "cp    %A[y], %A[m]\n\t"
      "cpc   %B[y], %B[m]\n\t"
      "brge  17f\n\t"
      "movw  %A[y], %A[m]\n"
      "17:\n\t"
      "ldd   %A[m], Z+%[o_ms]\n\t"        // friction + (moving slope a)'s bits 15..30
      "ldd   %B[m], Z+%[o_ms]+1\n\t"
      "ldd   %A[x], Z+%[o_fr]\n\t"
      "ldd   %B[x], Z+%[o_fr]+1\n"
      "14:\n\t"
      WMRA_DC_MUL_US("%A[p]", "%B[p]", "%C[p]", "%D[p]", "%A[m]", "%B[m]", "%A[y]", "%B[y]")
      "lsl   %B[p]\n\t"
      "rol   %C[p]\n\t"
      "rol   %D[p]\n\t"
      "movw  %A[y], %A[x]\n\t"
      "add   %A[y], %C[p]\n\t"
      "adc   %B[y], %D[p]\n\t"
      "sbrc  %[f], 0\n\t"                 // the sign: the effort's (still), the motion's (moving)
      "rjmp  18f\n\t"
      "sbrc  %[f], 1\n\t"
      "rjmp  19f\n\t"
      "rjmp  16f\n"
      "18:\n\t"
      "sbrs  %B[e], 7\n\t"
      "rjmp  16f\n"
      "19:\n\t"
      WMRA_DC_NEG16("y")
      "16:\n\t"
      "std   Z+%[o_ap], %A[y]\n\t"
      "std   Z+%[o_ap]+1, %B[y]\n\t"
      : [p] "+r"(p), [di] "+r"(di), [t] "+r"(t), [e] "=&r"(e), [x] "=&r"(x), [y] "=&a"(ya), [m] "=&a"(m), [k] "=&d"(k),
        "+z"(z)
      : [f] "r"(f), [tail] "I"(kTail), [o_ef] "I"(l.effort), [o_top] "I"(l.top), [o_rt] "I"(l.rate_twice),
        [o_i] "I"(l.integral), [o_l] "I"(l.integral_limit), [o_h] "I"(offsetof(DcServo, holding_q15_)),
        [o_md] "I"(l.min_duty - kTail), [o_zb] "I"(l.zero_band - kTail), [o_sl] "I"(l.slope - kTail),
        [o_ap] "I"(offsetof(DcServo, applied_) - kTail), [o_lift] "I"(offsetof(DcServo, lift_q15_) - kTail),
        [o_bre] "I"(offsetof(DcServo, breakaway_effort_q15_) - kTail), [o_fr] "I"(offsetof(DcServo, moving_friction_q15_) - kTail),
        [o_ms] "I"(offsetof(DcServo, moving_slope_q15_) - kTail), [o_ba] "I"(offsetof(DcServo, broke_away_) - kTail)
      : "memory");
  return ya;
}
#undef WMRA_DC_MUL_SS
#undef WMRA_DC_MUL_US
#undef WMRA_DC_NEG16
#undef WMRA_DC_TOWARDS
#endif

}  // namespace core
}  // namespace wmra
