// Seed 0's closed-loop controller for a stepper whose position is measured on the joint side
// (behind a reducer with backlash): the position error becomes a rate-limited, saturated speed
// command for the step generator. One update per control period dt.
//
// The law (Cardozo's thesis, section 4.2, eqs. 4.2-4.4):
//     V_PD(k) = K_P e(k) + K_D (e(k) - e(k-1)) / dt
//     V_C(k)  = clamp(V_PD, V_C(k-1) - alpha dt, V_C(k-1) + alpha dt)   (the rule base)
//     V_C(k)  = clamp(V_C(k), -V_S, V_S)                                  (saturation)
// Two variants (Cardozo's thesis, chapter 4 and Appendix A):
//   thesis    exactly the above;
//   firmware  the joint-1 PIC firmware of Appendix A: |e| <= deadband gives 0 (anti-chatter),
//             |e| <= near gives K_P,near e (low gain at the target, against backlash limit
//             cycles), a non-zero command below V_MIN is raised to V_MIN, and a command whose
//             sign differs from the last one gives one period of zero speed (reversal through
//             rest). The zero from the deadband is still rate-limited, as in the original.
// The original computes in 16-bit signed integers and overflows for |e| > ~2,520 counts at
// kp = 13 (the command turns negative); here the error and its change are saturated to 16 bits
// and the products taken in 32 bits, so a large error saturates at +-V_S instead.
//
// Units: e in encoder counts (joint side), speeds in motor steps/s, as in the thesis: the gains
// absorb the counts-to-steps ratio. Gains in Q8 (kp_q8 = 256 K_P), kd as K_D/dt per period.
// This port keeps a fixed period (the PIC's period varied with the speed). Feed V_C to a StepRamp
// whose acceleration limit is at least alpha, so the step train follows the command.
//
// Constants (Cardozo's thesis, section 4.3): alpha by test (raise until steps are lost, keep the last good
// one), V_S from the torque-speed curve, and K_P from symmetric braking: braking from V_S at
// alpha needs e_0 = V_S^2 / (2 alpha) (4.8), and the PD reaches V_S at e_0 = V_S (1 + K_D)/K_P
// (4.10), so K_P = 2 alpha (1 + K_D) / V_S, about 2 alpha / V_S (4.12). The thesis prints
// (4.11) as (1 + K_D)/K_P = 2 alpha/V_S, which is inverted; 4.8, 4.10 and 4.12 agree with the
// form used here (seed0_kp_q8, checked in test_seed0_controller).
#pragma once

#include <stdint.h>

#include "control/control_math.h"
#include "kinematics/ratio.h"

namespace wmra {
namespace control {

enum class Seed0Variant : uint8_t { thesis, firmware };

struct Seed0Config {
  Seed0Variant variant;
  int32_t kp_q8;             // K_P, steps/s per count, Q8
  int32_t kd_q8;             // K_D / dt, steps/s per (count of change per period), Q8
  int32_t accel_per_period;  // alpha dt, steps/s per period
  int32_t v_s;               // saturation speed V_S, steps/s
  // firmware variant only
  int32_t deadband_counts;   // |e| <= this: command 0 (joint 1: 1)
  int32_t near_counts;       // |e| <= this: kp_near (joint 1: 10)
  int32_t kp_near_q8;        // (joint 1: 2)
  int32_t v_min;             // smallest non-zero speed (joint 1: 25)
};

enum class Seed0Status : uint8_t { ok = 0, gain_invalid, accel_not_positive, speed_invalid, band_invalid };

// K_P = 2 alpha (1 + K_D) / V_S in Q8 (K_D in seconds)
constexpr int32_t seed0_kp_q8(int32_t alpha_steps_s2, int32_t v_s, Ratio kd_s) {
  return (int32_t)div_round(2 * (int64_t)alpha_steps_s2 * (kd_s.den + kd_s.num) * 256, (int64_t)v_s * kd_s.den);
}
// K_D / dt in Q8
constexpr int32_t seed0_kd_q8(Ratio kd_s, int32_t dt_ms) {
  return (int32_t)div_round(kd_s.num * 1000 * 256, kd_s.den * dt_ms);
}
// alpha dt, steps/s per period
constexpr int32_t seed0_accel_per_period(int32_t alpha_steps_s2, int32_t dt_ms) {
  return (int32_t)div_round((int64_t)alpha_steps_s2 * dt_ms, 1000);
}

constexpr Seed0Status seed0_check(const Seed0Config& c) {
  return (c.kp_q8 < 0 || c.kp_q8 > 32767 || c.kd_q8 < 0 || c.kd_q8 > 32767 || c.kp_near_q8 < 0 ||
          c.kp_near_q8 > 32767)
             ? Seed0Status::gain_invalid
         : c.accel_per_period <= 0 ? Seed0Status::accel_not_positive
         : (c.v_s <= 0 || c.v_s > 1000000 || c.v_min < 0 || c.v_min > c.v_s) ? Seed0Status::speed_invalid
         : (c.deadband_counts < 0 || c.near_counts < c.deadband_counts) ? Seed0Status::band_invalid
                                                                         : Seed0Status::ok;
}

class Seed0StepperController {
 public:
  Seed0Status configure(const Seed0Config& c) {
    const Seed0Status s = seed0_check(c);
    if (s != Seed0Status::ok) return s;
    c_ = c;
    configured_ = true;
    reset(0, 0);
    return s;
  }

  // Start from rest with no derivative kick: the last error is taken to be the present one.
  void reset(int32_t pos_desired_counts, int32_t pos_measured_counts) {
    e_prev_ = saturate_i16(sub_saturated(pos_desired_counts, pos_measured_counts));
    v_prev_ = 0;
    negative_ = false;
  }

  // One period: the speed command V_C in steps/s (signed).
  int32_t update(int32_t pos_desired_counts, int32_t pos_measured_counts) {
    if (!configured_) return 0;
    const int16_t e = saturate_i16(sub_saturated(pos_desired_counts, pos_measured_counts));
    const int16_t de = saturate_i16((int32_t)e - e_prev_);
    e_prev_ = e;
    // |kp e| + |kd de| <= 2 * 32767^2 < 2^31
    int32_t v = round_q8(fx::mul_ss(e, (int16_t)c_.kp_q8) + fx::mul_ss(de, (int16_t)c_.kd_q8));
    const int32_t magnitude = e < 0 ? -(int32_t)e : e;
    const bool firmware = c_.variant == Seed0Variant::firmware;
    if (firmware) {
      if (magnitude <= c_.near_counts) v = round_q8(fx::mul_ss(e, (int16_t)c_.kp_near_q8));
      if (magnitude <= c_.deadband_counts) v = 0;
    }
    v = clamp_i32(v, v_prev_ - c_.accel_per_period, v_prev_ + c_.accel_per_period);  // rule base
    if (firmware) {
      if (v > 0 && v < c_.v_min) v = c_.v_min;
      if (v < 0 && v > -c_.v_min) v = -c_.v_min;
    }
    v = clamp_i32(v, -c_.v_s, c_.v_s);
    if (!firmware) {
      v_prev_ = v;
      return v;
    }
    const bool negative = v < 0;
    const bool reversal = negative != negative_;
    negative_ = negative;
    const int32_t out = reversal ? 0 : v;
    v_prev_ = out;  // after a stopped period the PIC restarts its rule base from 0
    return out;
  }

  int32_t last_command() const { return v_prev_; }

 private:
  static int32_t round_q8(int32_t x) { return (x + 128) >> 8; }  // arithmetic shift

  Seed0Config c_{Seed0Variant::thesis, 0, 0, 1, 1, 0, 0, 0, 0};
  bool configured_ = false;
  int16_t e_prev_ = 0;
  int32_t v_prev_ = 0;
  bool negative_ = false;
};

}  // namespace control
}  // namespace wmra
