// The control blocks' sample functions as they were before their cycle cuts (branch perf2),
// kept verbatim as references: test_control_equivalence checks the faster versions against
// them, bit for bit, on random inputs. Only what changed is kept.
#pragma once

#include <stdint.h>

#include "control/pid.h"

namespace wmra {
namespace control {
namespace reference {

class Pid {
 public:
  PidStatus configure(const PidConfig& c) {
    const PidStatus s = pid_check(c);
    if (s != PidStatus::ok) return s;
    c_ = c;
    // dead-zone inverse slope (out_max - min) / out_max in Q15, computed once
    slope_q15_ = (uint16_t)(((int32_t)(c.out_max_q15 - c.min_duty_q15) << 15) / c.out_max_q15);
    configured_ = true;
    start(0, 0, 0);
    return s;
  }

  // Bumpless start: the next update with the same inputs outputs applied_effort_q15 (plus one
  // sample of integration).
  void start(int32_t setpoint, int32_t measurement, int16_t applied_effort_q15) {
    m_prev_ = measurement;
    effort_ = (int16_t)clamp_i32(applied_effort_q15, -c_.out_max_q15, c_.out_max_q15);
    const int16_t e = saturate_i16(sub_saturated(setpoint, measurement));
    const int32_t p_q19 = fx::mul_ss(e, c_.gains.kp_q4);
    integral_q23_ = clamp_integral(((int32_t)effort_ << 8) - clamp_i32(p_q19, -kTermLimit, kTermLimit) * 16);
  }

  // Preset the integral to an effort the loop is known to need (a load it held before), so
  // that it need not build it up from the error again; the output still ramps at the rate limit.
  void preset_integral(int16_t effort_q15) { integral_q23_ = clamp_integral((int32_t)effort_q15 << 8); }

  // One sample: the duty (Q15, signed) to apply. samples: how many sample periods passed since
  // the last update (a caller that overran): the integral, the output's rate limit and the
  // measurement's rate scale with it, so that the gains keep their meaning in time.
  int16_t update(int32_t setpoint, int32_t measurement, int16_t feedforward_q15 = 0, uint8_t samples = 1) {
    if (!configured_) return 0;
    const int16_t e = saturate_i16(sub_saturated(setpoint, measurement));
    int16_t dm = saturate_i16(sub_saturated(measurement, m_prev_));
    m_prev_ = measurement;
    if (samples == 2) dm = (int16_t)(dm >> 1);
    else if (samples > 2) dm = (int16_t)(dm / (int16_t)samples);
    // P and D in Q19, each clamped far beyond full output (2^26 = 128 x full) before summing
    const int32_t p = clamp_i32(fx::mul_ss(e, c_.gains.kp_q4), -kTermLimit, kTermLimit);
    const int32_t d = clamp_i32(fx::mul_ss(dm, c_.gains.kd), -kTermLimit / 16, kTermLimit / 16) * 16;
    const int32_t pd = p - d + ((int32_t)feedforward_q15 << 4);
    int32_t di = fx::mul_ss(e, c_.gains.ki_q8);  // Q23
    if (samples > 1) di = clamp_integral(di) * samples;  // at most full output a sample: no overflow
    const int32_t limit = (int32_t)c_.out_max_q15 << 4;
    const int32_t rate = (int32_t)c_.rate_q15 * samples;
    const int32_t hi = clamp_i32(((int32_t)effort_ + rate) << 4, -limit, limit);
    const int32_t lo = clamp_i32(((int32_t)effort_ - rate) << 4, -limit, limit);
    const int32_t trial = clamp_integral(integral_q23_ + di);
    const int32_t u_trial = pd + (trial >> 4);
    // conditional integration: hold the integral when it would push further into a limit
    if (!((u_trial > hi && di > 0) || (u_trial < lo && di < 0))) integral_q23_ = trial;
    const int32_t u = clamp_i32(pd + (integral_q23_ >> 4), lo, hi);
    effort_ = (int16_t)((u + 8) >> 4);
    return duty_for(effort_);
  }

  // Effort -> duty through the dead-zone inverse (also usable alone, e.g. by the relay).
  int16_t duty_for(int16_t effort_q15) const {
    const int16_t a = effort_q15 < 0 ? (int16_t)-effort_q15 : effort_q15;
    if (a == 0 || a < c_.zero_band_q15) return 0;
    const int16_t d = (int16_t)(c_.min_duty_q15 + shr15_to_i16((int32_t)fx::mul_uu((uint16_t)a, slope_q15_)));
    return effort_q15 < 0 ? (int16_t)-d : d;
  }

  int16_t effort_q15() const { return effort_; }
  int32_t integral_q23() const { return integral_q23_; }

 private:
  static constexpr int32_t kTermLimit = (int32_t)1 << 26;  // Q19: 128 x full output

  int32_t clamp_integral(int32_t i) const {
    const int32_t limit = (int32_t)c_.out_max_q15 << 8;
    return clamp_i32(i, -limit, limit);
  }

  PidConfig c_{{0, 0, 0}, 1, 1, 0, 0};
  bool configured_ = false;
  uint16_t slope_q15_ = 32768;
  int32_t m_prev_ = 0;
  int16_t effort_ = 0;
  int32_t integral_q23_ = 0;
};

}  // namespace reference
}  // namespace control
}  // namespace wmra
