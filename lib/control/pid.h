// PID position loop for a DC joint (potentiometer in, signed PWM duty out), run at a fixed
// sample rate: gains are per sample.
//
// What it adds to a textbook PID, and why:
//   derivative on the measurement   a setpoint step moves only P and I, never kicks D;
//   anti-windup                     the integral is held while the output is limited (by
//                                   saturation or by the rate limit) in the direction the
//                                   error pushes, and never holds more than full output, so it
//                                   unwinds within a few samples once the error turns;
//   bumpless start                  start() sets the integral so that the first output equals
//                                   the duty already applied (0 for a joint at rest);
//   velocity feedforward            the caller may add the effort that the setpoint's own speed
//                                   needs (speed / the joint's speed at full duty), so that a
//                                   moving setpoint is followed without first building an error
//                                   and an integral;
//   output rate limit               the effort changes by at most rate_q15 per sample: no step
//                                   of motor voltage (the joystick ramps the setpoint, this
//                                   covers disturbances and start-up);
//   effort bounds                   the caller may bound the effort each way below out_max
//                                   (set_effort_bounds: a speed governor, the effort that drives
//                                   the joint at its speed limit); anti-windup holds the integral
//                                   at them as at out_max, and an effort beyond a bound that fell
//                                   comes back at the rate limit;
//   stiction / dead-zone inverse    effort e > zero band maps to min_duty + e (1 - min/max):
//                                   the joint's dead zone (seed 2: ~30/255) is skipped, the
//                                   gain above it is kept, and |duty| <= out_max still holds.
//                                   Inside the zero band the duty is 0 (no hum at rest).
// Order per sample: P + I + D + feedforward -> saturate -> rate limit (on effort) -> dead-zone inverse.
//
// Fixed point: positions are 16-bit; the error and the change of the measurement are
// saturated to +-32767 once (a 16-bit subtraction and its overflow flag), and each term is one
// 16x16 product (gains Q8), so no term can wrap. Duty and effort are Q15 fractions
// of full PWM (32767 = 100 %): the firmware scales by its timer's TOP. The integral is kept in
// Q23 (Q15 duty * 256) so that small Ki still integrates. "Position units" are the caller's:
// e.g. ADC counts * 16, so that a setpoint integrated from a joint velocity keeps its fraction.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "control/control_math.h"
#include "kinematics/ratio.h"

namespace wmra {
namespace control {

struct PidGains {
  int16_t kp_q4;  // Q15 duty per position unit, Q4
  int16_t ki_q8;  // Q15 duty per (position unit * sample), Q8
  int16_t kd;     // Q15 duty per (position unit / sample)
};

struct PidConfig {
  PidGains gains;
  int16_t out_max_q15;    // |effort| and |duty| limit, (0, 32767]
  int16_t rate_q15;       // largest change of effort per sample, > 0
  int16_t min_duty_q15;   // duty at which the joint starts to move (stiction), [0, out_max)
  int16_t zero_band_q15;  // |effort| below this gives duty 0, [0, out_max]
};

enum class PidStatus : uint8_t { ok = 0, gain_invalid, limit_invalid };

constexpr PidStatus pid_check(const PidConfig& c) {
  return (c.gains.kp_q4 < 0 || c.gains.ki_q8 < 0 || c.gains.kd < 0) ? PidStatus::gain_invalid
         : (c.out_max_q15 <= 0 || c.rate_q15 <= 0 || c.min_duty_q15 < 0 || c.min_duty_q15 >= c.out_max_q15 ||
            c.zero_band_q15 < 0 || c.zero_band_q15 > c.out_max_q15)
             ? PidStatus::limit_invalid
             : PidStatus::ok;
}

// Per-sample gains from continuous ones: Kp in duty fraction per count, Ki per count-second,
// Kd in duty fraction * s per count, at rate_hz samples/s with units_per_count position units
// per ADC count. ok is false when a gain does not fit its format.
struct PidGainsResult {
  PidGains gains;
  bool ok;
};
// duty_per_count * 32768 * 2^frac * scale_num / (scale_den * units_per_count), rounded
constexpr int64_t pid_gain(Ratio duty_per_count, int frac, int64_t scale_num, int64_t scale_den, int32_t units_per_count) {
  return div_round(duty_per_count.num * 32768 * ((int64_t)1 << frac) * scale_num,
                   duty_per_count.den * scale_den * units_per_count);
}
constexpr bool pid_fits(int64_t g) { return g >= 0 && g <= 32767; }
constexpr PidGainsResult pid_gains(Ratio kp, Ratio ki_per_s, Ratio kd_s, int32_t rate_hz, int32_t units_per_count) {
  return PidGainsResult{
      PidGains{(int16_t)pid_gain(kp, 4, 1, 1, units_per_count), (int16_t)pid_gain(ki_per_s, 8, 1, rate_hz, units_per_count),
               (int16_t)pid_gain(kd_s, 0, rate_hz, 1, units_per_count)},
      pid_fits(pid_gain(kp, 4, 1, 1, units_per_count)) && pid_fits(pid_gain(ki_per_s, 8, 1, rate_hz, units_per_count)) &&
          pid_fits(pid_gain(kd_s, 0, rate_hz, 1, units_per_count))};
}

class Pid {
 public:
  PidStatus configure(const PidConfig& c) {
    const PidStatus s = pid_check(c);
    if (s != PidStatus::ok) return s;
    c_ = c;
    // dead-zone inverse slope (out_max - min) / out_max in Q15, computed once
    integral_limit_ = (int32_t)c.out_max_q15 << 8;
    slope_q15_ = (uint16_t)(((int32_t)(c.out_max_q15 - c.min_duty_q15) << 15) / c.out_max_q15);
    p_error_limit_ = term_error_limit(kTermLimit, c.gains.kp_q4);
    i_error_limit_ = term_error_limit(integral_limit_, c.gains.ki_q8);
    kp_x16_ = c.gains.kp_q4 < 4096 ? (uint16_t)(c.gains.kp_q4 * 16) : (uint16_t)0;
    d_change_limit_ = term_error_limit(kTermLimit / 16, c.gains.kd);
    rate_twice_ = rate_over(2);
    top_ = c.out_max_q15;
    bottom_ = (int16_t)-c.out_max_q15;
    configured_ = true;
    start(0, 0, 0);
    return s;
  }

  // The effort's bounds: at most up_q15 positive and down_q15 negative (magnitudes, each
  // within [0, out_max]; out_max both after configure)
  void set_effort_bounds(int16_t up_q15, int16_t down_q15) {
    top_ = clamp_bound(up_q15);
    bottom_ = (int16_t)-clamp_bound(down_q15);
  }

  // Bumpless start: the next update with the same inputs outputs applied_effort_q15 (plus one
  // sample of integration).
  void start(int16_t setpoint, int16_t measurement, int16_t applied_effort_q15) {
    start_at_error(sub_saturated_i16(setpoint, measurement), measurement, applied_effort_q15);
  }
  // the same with the error setpoint - measurement already formed and saturated to +-32767
  // (a caller that needs it too: one subtraction). Out of line: a servo restarts from several
  // places of its update, each an inlined copy of P's product otherwise.
  __attribute__((noinline)) void start_at_error(int16_t error, int16_t measurement, int16_t applied_effort_q15) {
    m_prev_ = measurement;
    effort_ = applied_effort_q15 > c_.out_max_q15    ? c_.out_max_q15
              : applied_effort_q15 < -c_.out_max_q15 ? (int16_t)-c_.out_max_q15
                                                     : applied_effort_q15;
    integral_q23_ = clamp_integral(((int32_t)effort_ << 8) - p_q23(error));
  }

  // Preset the integral to an effort the loop is known to need (a load it held before), so
  // that it need not build it up from the error again; the output still ramps at the rate limit.
  void preset_integral(int16_t effort_q15) { integral_q23_ = clamp_integral((int32_t)effort_q15 << 8); }

  // One sample: the duty (Q15, signed) to apply. samples: how many sample periods passed since
  // the last update (a caller that runs every few periods, or overran): the integral, the
  // output's rate limit and the measurement's rate scale with it, so that the gains keep their
  // meaning in time.
  int16_t update(int16_t setpoint, int16_t measurement, int16_t feedforward_q15 = 0, uint8_t samples = 1) {
    return update_at_error(sub_saturated_i16(setpoint, measurement), measurement, feedforward_q15, samples);
  }
  // the same with the error setpoint - measurement already formed and saturated to +-32767
  int16_t update_at_error(int16_t e, int16_t measurement, int16_t feedforward_q15 = 0, uint8_t samples = 1) {
    return duty_for(update_effort(e, measurement, feedforward_q15, samples));
  }
  // One sample's effort (Q15, signed), before the dead-zone inverse: a caller that maps it
  // itself (duty_moving). On the AVR core::DcServo's rare runs alone call it (its common run is
  // an asm kernel of its own).
  int16_t update_effort(int16_t e, int16_t measurement, int16_t feedforward_q15 = 0, uint8_t samples = 1) {
    if (!configured_) return 0;
    int16_t dm = sub_saturated_i16(measurement, m_prev_);
    m_prev_ = measurement;
    int32_t di = e == 0 ? 0 : fx::mul_ss(e, c_.gains.ki_q8);  // Q23 (a joint on its reference: no product)
    // several periods: the measurement's change per period, the integral and the rate over all.
    // Two, a servo that runs every second tick, without a call or a product.
    uint16_t rate = (uint16_t)c_.rate_q15;
    if (samples == 2) {
      dm = (int16_t)(dm >> 1);
      // (|e| Ki within the clamp, the usual case: a 16-bit compare says so)
      if (distance_u16(e, 0) > i_error_limit_) di = clamp_integral(di);
      di += di;  // at most full output a sample: no overflow
      rate = rate_twice_;
    } else if (samples != 1) {
      dm = per_sample(dm, samples);
      if (samples > 1) di = mul_i32_u8(clamp_integral(di), samples);
      rate = rate_over(samples);
    }
    // P in Q19 clamped far beyond full output (2^26 = 128 x full), then in Q23 beside the
    // integral; D (clamped alike) and the feedforward stay in Q15 and join after the sum's
    // byte shift. Exactly the Q19 formulation's effort (see the test's reference): with
    // s = 16 P + I, that sum's u = P + 16 (ff - D) + floor(I / 16) is floor(s / 16) + 16 t, and
    // its rounded, clamped effort is clamp(floor((s + 128) / 256) + t, lo, hi); so the only
    // shift by other than whole bytes left is 16 P (shifts by 4 are loops on the AVR).
    const int32_t p = p_q23(e);
    // (a reading in ADC counts x 16 stands still most samples: no product then)
    const int32_t d_q15 = dm == 0                                  ? 0
                          : distance_u16(dm, 0) > d_change_limit_ ? (dm < 0 ? -kTermLimit / 16 : kTermLimit / 16)
                                                                   : fx::mul_ss(dm, c_.gains.kd);
    const int32_t t_q15 = (int32_t)feedforward_q15 - d_q15;
    // the effort's limits this sample: from where it is towards each bound, at most the rate
    // (top_ >= 0 >= bottom_, so lo <= hi also when a bound fell below the effort)
    const int16_t hi = towards(effort_, top_, rate);
    const int16_t lo = towards(effort_, bottom_, rate);
    // conditional integration: hold the integral when it would push further into a limit
    // (u > 16 hi is s > 256 (hi - t) + 15, u < 16 lo is s < 256 (lo - t)). di has the sign of
    // e (Ki >= 0, samples >= 0), and di = 0 leaves the integral as it is (always within its
    // clamp): the 32-bit sum, clamp and compare only when it integrates.
    if (e != 0 && c_.gains.ki_q8 != 0) {
      const int32_t trial = clamp_integral(integral_q23_ + di);
      const int32_t s_trial = p + trial;
      if (e > 0 ? s_trial <= (hi - t_q15) * 256 + 15 : s_trial >= (lo - t_q15) * 256) integral_q23_ = trial;
    }
    effort_ = (int16_t)clamp_i32(((p + integral_q23_ + 128) >> 8) + t_q15, lo, hi);
    return effort_;
  }

  // Effort -> duty through the dead-zone inverse (also usable alone, e.g. by the relay).
  int16_t duty_for(int16_t effort_q15) const {
    const int16_t a = effort_q15 < 0 ? (int16_t)-effort_q15 : effort_q15;
    if (a == 0 || a < c_.zero_band_q15) return 0;
    const int16_t d = (int16_t)(c_.min_duty_q15 + shr15_to_i16((int32_t)fx::mul_uu((uint16_t)a, slope_q15_)));
    return effort_q15 < 0 ? (int16_t)-d : d;
  }

  // Effort -> duty for a joint that moves one way (negative: towards -), as it does along a
  // moving reference. The worm's Coulomb friction opposes the motion whatever the effort's
  // sign, so its compensation takes the motion's sign and the moving friction's size
  // (friction_q15, at most the breakaway's min_duty): friction + slope * effort that way,
  // continuous through effort 0, with slope_q15 = moving_slope_q15(friction_q15) so that full
  // effort is still full duty (a joint lifting near its drive's limit keeps all of it). An
  // effort against the motion pushes less than the friction (the joint slows) and reverses the
  // duty only past friction / slope. duty_for's inverse jumps by twice min_duty where the
  // effort crosses 0: a P term of more than the effort a slow motion needs (J4: 7 % a pot
  // count against ~6 %) reversed the duty at each count the joint ran ahead, and the worm,
  // which does not back-drive, stopped the joint dead (J4 0.22 -> 0.01 rad/s in 15 ms): S1's
  // 4 Hz ringing. Within [-out_max, out_max] for an effort within the bounds.
  static int16_t duty_moving(int16_t effort_q15, bool negative, int16_t friction_q15, uint16_t slope_q15) {
    const int16_t a = negative ? (int16_t)-effort_q15 : effort_q15;
    const int16_t d = (int16_t)(friction_q15 + shr15_to_i16(fx::mul_us(slope_q15, a)));
    return negative ? (int16_t)-d : d;
  }
  // the slope from friction_q15 at effort 0 to out_max at full effort (Q15 of 32768)
  uint16_t moving_slope_q15(int16_t friction_q15) const {
    return (uint16_t)(((int32_t)(c_.out_max_q15 - friction_q15) << 15) / c_.out_max_q15);
  }

  const PidConfig& config() const { return c_; }
  bool configured() const { return configured_; }
  int16_t effort_q15() const { return effort_; }
  int32_t integral_q23() const { return integral_q23_; }

  // Where an update's fields lie in a Pid, for an AVR kernel that reaches them through its
  // holder's pointer (core::DcServo's update; its C twin is update_effort)
  struct Layout {
    uint8_t integral, m_prev, effort, top, bottom, kp, ki, kd, min_duty, zero_band, slope, p_error_limit, d_change_limit,
        i_error_limit, kp_x16, rate_twice, integral_limit;
  };
  static constexpr Layout layout() {
    return Layout{offsetof(Pid, integral_q23_),   offsetof(Pid, m_prev_),         offsetof(Pid, effort_),
                  offsetof(Pid, top_),            offsetof(Pid, bottom_),         offsetof(Pid, c_.gains.kp_q4),
                  offsetof(Pid, c_.gains.ki_q8),  offsetof(Pid, c_.gains.kd),     offsetof(Pid, c_.min_duty_q15),
                  offsetof(Pid, c_.zero_band_q15), offsetof(Pid, slope_q15_),     offsetof(Pid, p_error_limit_),
                  offsetof(Pid, d_change_limit_), offsetof(Pid, i_error_limit_), offsetof(Pid, kp_x16_),
                  offsetof(Pid, rate_twice_),     offsetof(Pid, integral_limit_)};
  }

 private:
  static constexpr int32_t kTermLimit = (int32_t)1 << 26;  // Q19: 128 x full output

  // The largest |x| whose product with gain stays within limit: a term is clamped when |x| is
  // past it (|x| gain > limit is |x| > floor(limit / gain)), a 16-bit compare in place of the
  // product's 32-bit clamp. 65535: never.
  static uint16_t term_error_limit(int32_t limit, int16_t gain) {
    const int32_t x = gain == 0 ? 65535 : limit / gain;
    return (uint16_t)(x > 65535 ? 65535 : x);
  }
  // P in Q23: the error's product (Q19) clamped to +-kTermLimit, times 16
  int32_t p_q23(int16_t e) const {
    if (e == 0) return 0;
    if (distance_u16(e, 0) > p_error_limit_) return e < 0 ? -kTermLimit * 16 : kTermLimit * 16;
    // Kp 16 within 16 bits unsigned: one product, no 32-bit shift (a loop on the AVR)
    if (kp_x16_ != 0 || c_.gains.kp_q4 == 0) return fx::mul_us(kp_x16_, e);
    return fx::mul_ss(e, c_.gains.kp_q4) * 16;
  }
  // the rate limit over several samples, capped at 65535 (past the full span
  // 2 out_max, any rate is the same)
  uint16_t rate_over(uint8_t samples) const {
    const uint32_t r = fx::mul_uu((uint16_t)c_.rate_q15, samples);
    return (uint16_t)(r > 65535 ? 65535 : r);
  }

  // the change of the measurement over `samples` periods as a change per period (out of line,
  // and tested once in update, so that the compiler does not copy the whole update per case of
  // `samples`, 600 bytes); two samples are update's own case
  static __attribute__((noinline)) int16_t per_sample(int16_t dm, uint8_t samples) {
    if (samples > 2) return (int16_t)(dm / (int16_t)samples);
    return dm;
  }

  int32_t clamp_integral(int32_t i) const { return clamp_i32(i, -integral_limit_, integral_limit_); }
  int16_t clamp_bound(int16_t b) const { return b < 0 ? (int16_t)0 : b > c_.out_max_q15 ? c_.out_max_q15 : b; }

  // from moved towards `to` by at most step (both within +-out_max: their distance fits 16
  // bits unsigned, as does a step past it)
  static int16_t towards(int16_t from, int16_t to, uint16_t step) {
    if (to >= from) return (uint16_t)(to - from) <= step ? to : (int16_t)(from + step);
    return (uint16_t)(from - to) <= step ? to : (int16_t)(from - step);
  }

  // (the state an update reads first: within the AVR's 64-byte displacement of a caller that
  // holds the Pid at its start, as DcServo does)
  int32_t integral_q23_ = 0;
  int16_t m_prev_ = 0;
  int16_t effort_ = 0;
  int16_t top_ = 1, bottom_ = -1;  // the effort's bounds (set_effort_bounds)
  PidConfig c_{{0, 0, 0}, 1, 1, 0, 0};
  bool configured_ = false;
  uint16_t slope_q15_ = 32768;
  uint16_t p_error_limit_ = 65535, d_change_limit_ = 65535;
  uint16_t i_error_limit_ = 65535;  // |e| Ki within the integral's clamp up to this |e|
  uint16_t kp_x16_ = 0;             // Kp 16, when it fits 16 bits (Kp < 4096), else 0
  uint16_t rate_twice_ = 2;       // the rate limit over two samples
  int32_t integral_limit_ = 256;  // out_max in Q23
};

}  // namespace control
}  // namespace wmra
