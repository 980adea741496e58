// Joystick shaping: two raw ADC channels in, a velocity command (x, y in Q15, |(x, y)| <= 1)
// out, once per sample, as a pure function of the samples. A caller may sample every few ticks
// of its clock: the rail check, the arming and the ramps count ticks, not samples.
//
// Pipeline, and why:
//   1. centre calibration   the mean of the first samples (seed 2: 10 after 500 ms); refused
//                           and restarted while they spread too much (stick moving) or sit
//                           far from mid-scale (deflected at power-up); once a centre measured
//                           with the stick released is stored (set_stored_centre), far from
//                           that instead, by the much tighter stored_tolerance: a hand resting
//                           on the stick within centre_tolerance of mid-scale would otherwise
//                           become the centre, and the stick released would drive the arm;
//   2. rail check           a reading within rail_margin of 0 or full scale is a broken or
//                           unplugged channel: it reads as neutral at once, and after
//                           rail_ticks in a row latches a fault (flag) until the stick has
//                           been valid and neutral again (no motion until valid and
//                           neutral). Full deflection must stay inside the margins (hardware);
//   3. normalise            per side of the centre, so that each full deflection is 1: the
//                           last reading before the rail margin, or full_deflection counts
//                           from the centre when the stick's travel ends before the rails
//                           (readings beyond it saturate at 1);
//   4. dead zone            per axis (seed 2: ~2 %), rescaled so the output is continuous at
//                           its edge; per axis rather than radial, so that a push along one
//                           axis gives no drift in the other;
//   5. square to disc       seed 2: the square of the two pots onto the unit disc, along the
//                           same direction, so every direction has the same maximum: the
//                           vector is scaled by max(|x|, |y|) / |(x, y)|;
//   6. response curve       on the radius: (1 - k) r + k r^3 (k = expo), monotone for k in
//                           [0, 1], fine control near the centre;
//   7. rate limit           per axis, rise_per_sample away from zero and fall_per_sample
//                           towards it: no step change of velocity, and letting go stops
//                           faster than pushing starts;
//   8. arming               nothing comes out until the stick has been neutral for
//                           neutral_ticks after calibration or a fault.
// Integer only: one table reciprocal square root per sample for step 5, the rest 16x16
// products and compares.
#pragma once

#include <stdint.h>

#include "control/control_math.h"
#include "kinematics/reciprocal.h"

namespace wmra {
namespace control {

enum JoystickStatus : uint8_t {
  kJoystickCalibrating = 1,  // the centre is not known yet
  kJoystickNotArmed = 2,     // waiting for the stick to be neutral
  kJoystickRailX = 4,        // channel x stuck at a rail (latched until re-armed)
  kJoystickRailY = 8,
};

struct JoystickConfig {
  uint16_t adc_max;              // full-scale reading (1023)
  uint16_t rail_margin;          // readings <= margin or >= adc_max - margin are a rail
  uint8_t rail_ticks;            // > 0
  uint8_t calibration_samples;   // 1..64
  uint16_t calibration_spread;   // largest max - min while calibrating
  uint16_t centre_tolerance;     // largest |centre - adc_max / 2|
  int16_t dead_zone_q15;         // [0, 16384)
  int16_t expo_q15;              // [0, 32767]
  int16_t rise_q15;              // per tick of the caller's clock, > 0
  int16_t fall_q15;              // per tick of the caller's clock, > 0
  uint16_t neutral_ticks;        // > 0
  uint16_t full_deflection = 0;  // counts from the centre that are a full stick; 0: up to the rail margin
  uint16_t stored_tolerance = 0;  // largest |centre - stored centre| once one is stored
};

struct JoystickOutput {
  int16_t x_q15;
  int16_t y_q15;
  uint8_t status;  // JoystickStatus bits; 0 = live
};

constexpr bool joystick_check(const JoystickConfig& c) {
  return c.adc_max >= 255 && c.rail_margin < c.adc_max / 4 && c.rail_ticks > 0 && c.calibration_samples > 0 &&
         c.calibration_samples <= 64 && c.centre_tolerance < c.adc_max / 4 && c.dead_zone_q15 >= 0 &&
         c.dead_zone_q15 < 16384 && c.expo_q15 >= 0 && c.rise_q15 > 0 && c.fall_q15 > 0 && c.neutral_ticks > 0 &&
         c.stored_tolerance <= c.centre_tolerance &&
         (c.full_deflection == 0 || (c.full_deflection > c.adc_max / 8 && c.full_deflection < c.adc_max / 2));
}

// num * 32768 / den (saturated at 32767) for 0 <= num <= den, den > 0, by a table reciprocal (no division)
inline int16_t ratio_q15(uint16_t num, uint16_t den) {
  uint8_t s = 0;
  while (!(den & 0x8000u)) {
    den <<= 1;
    ++s;
  }
  // 1/den_original = 2^s / den; half_reciprocal gives 2^31 / den
  const uint32_t r = fx::mul_uu(num, fx::half_reciprocal_uq16(den));  // num 2^31 / den
  const uint32_t q = r >> (16 - s);                                      // num 2^15 / den_original
  return (int16_t)(q > 32767u ? 32767u : q);
}

class Joystick {
 public:
  bool configure(const JoystickConfig& c) {
    if (!joystick_check(c)) return false;
    c_ = c;
    dead_scale_ = ratio_q15(32767u / 2, (uint16_t)(32767 - c.dead_zone_q15));  // half: fits Q15
    configured_ = true;
    recalibrate();
    return true;
  }

  void recalibrate() {
    calibrated_ = false;
    armed_ = false;
    cal_count_ = 0;
    rail_flags_ = 0;
    rail_count_[0] = rail_count_[1] = 0;
    out_[0] = out_[1] = 0;
    neutral_count_ = 0;
  }

  // ticks: the clock ticks since the last sample; the ramps advance by that many steps, so that
  // they take the same time however often the caller samples
  JoystickOutput update(uint16_t raw_x, uint16_t raw_y, uint8_t ticks = 1) {
    if (!configured_) return JoystickOutput{0, 0, kJoystickCalibrating | kJoystickNotArmed};
    const uint16_t raw[2] = {raw_x, raw_y};
    bool at_rail[2];
    for (uint8_t i = 0; i < 2; ++i) {
      at_rail[i] = raw[i] <= c_.rail_margin || raw[i] >= c_.adc_max - c_.rail_margin;
      if (at_rail[i]) {
        rail_count_[i] = add_saturated_u8(rail_count_[i], ticks);
        if (rail_count_[i] >= c_.rail_ticks) rail_flags_ |= (uint8_t)(kJoystickRailX << i);
      } else {
        rail_count_[i] = 0;
      }
    }
    if (!calibrated_) {
      calibrate(raw, at_rail[0] || at_rail[1]);
      return JoystickOutput{0, 0, status()};
    }
    int16_t v[2];
    for (uint8_t i = 0; i < 2; ++i) v[i] = at_rail[i] ? 0 : axis(raw[i], i);
    // arming: neutral (inside the dead zone, both channels valid) for neutral_ticks
    const bool neutral = v[0] == 0 && v[1] == 0 && !at_rail[0] && !at_rail[1];
    if (!armed_ || rail_flags_) {
      armed_ = false;
      neutral_count_ = !neutral ? 0 : neutral_count_ > 0xFFFFu - ticks ? 0xFFFFu : (uint16_t)(neutral_count_ + ticks);
      if (neutral_count_ >= c_.neutral_ticks) {
        armed_ = true;
        rail_flags_ = 0;
      }
    }
    int16_t target[2] = {0, 0};
    if (armed_) {
      // shaped again only when its input changed: a stick held still (at full deflection the
      // readings' noise is beyond the saturation) keeps its shape, the reciprocal square root
      // and the curve's products, ~400 cycles a sample on the AVR
      if (v[0] != shaped_in_[0] || v[1] != shaped_in_[1]) {
        shaped_in_[0] = v[0];
        shaped_in_[1] = v[1];
        shape(v[0], v[1], shaped_);
      }
      target[0] = shaped_[0];
      target[1] = shaped_[1];
    }
    for (uint8_t i = 0; i < 2; ++i) out_[i] = ramp(out_[i], target[i], ticks);
    return output();
  }

  // what the last update() returned
  JoystickOutput output() const { return JoystickOutput{out_[0], out_[1], status()}; }

  uint16_t centre(uint8_t axis) const { return centre_[axis]; }

  // The stick's centre measured with it released (x, y counts), which every later calibration
  // must agree with within stored_tolerance; 0 0: none stored, mid-scale within
  // centre_tolerance as on a new board. Checked from the next calibration on: the one in use
  // stays.
  void set_stored_centre(uint16_t x, uint16_t y) {
    stored_centre_[0] = x;
    stored_centre_[1] = y;
  }

  // Steps 5 and 6 alone (tests): square to disc, then the curve on the radius
  void shape(int16_t x, int16_t y, int16_t out[2]) const {
    const uint16_t ax = (uint16_t)(x < 0 ? -x : x), ay = (uint16_t)(y < 0 ? -y : y);
    const uint16_t m = ax > ay ? ax : ay;
    if (m == 0) {
      out[0] = out[1] = 0;
      return;
    }
    // 1 / |(x, y)| by a table reciprocal square root: r 2^(s-31)
    uint8_t s;
    const uint16_t inv = rsqrt_normalised(fx::mul_uu(ax, ax) + fx::mul_uu(ay, ay), s);
    const uint16_t r = curve(m);
    uint32_t kk = fx::mul_uu(r, inv);  // r / |(x, y)| = kk 2^(s-31), in Q15 kk >> (16 - s)
    uint8_t n = (uint8_t)(16 - s);     // by bytes first: a 32-bit shift by one bit is a loop step
    if (n >= 8) {
      kk >>= 8;
      n = (uint8_t)(n - 8);
    }
    if (n >= 8) {
      kk >>= 8;
      n = (uint8_t)(n - 8);
    }
    for (; n > 0; --n) kk >>= 1;
    const int16_t k = (int16_t)(kk > 32767u ? 32767u : kk);
    out[0] = shr15_to_i16(fx::mul_ss(x, k) + 16384);
    out[1] = shr15_to_i16(fx::mul_ss(y, k) + 16384);
  }

  // (1 - k) r + k r^3 on [0, 32767]
  uint16_t curve(uint16_t r) const {
    const fx::Unit u{(int16_t)r};
    const fx::Unit cube = u * u * u;
    const int32_t v = (int32_t)r + shr15_to_i16(fx::mul_ss(c_.expo_q15, (int16_t)(cube.raw - (int16_t)r)));
    return (uint16_t)clamp_i32(v, 0, 32767);
  }

 private:
  uint8_t status() const {
    return (uint8_t)((calibrated_ ? 0 : kJoystickCalibrating) | (armed_ ? 0 : kJoystickNotArmed) | rail_flags_);
  }

  // (runs only until the centre is known)
  void calibrate(const uint16_t raw[2], bool rail) {
    if (rail) {
      cal_count_ = 0;
      return;
    }
    for (uint8_t i = 0; i < 2; ++i) {
      if (cal_count_ == 0) {
        cal_sum_[i] = 0;
        cal_min_[i] = cal_max_[i] = raw[i];
      }
      cal_sum_[i] += raw[i];
      if (raw[i] < cal_min_[i]) cal_min_[i] = raw[i];
      if (raw[i] > cal_max_[i]) cal_max_[i] = raw[i];
    }
    if (++cal_count_ < c_.calibration_samples) return;
    cal_count_ = 0;
    const bool stored = stored_centre_[0] != 0;
    const uint16_t tolerance = stored ? c_.stored_tolerance : c_.centre_tolerance;
    for (uint8_t i = 0; i < 2; ++i) {
      const uint16_t centre = (uint16_t)((cal_sum_[i] + c_.calibration_samples / 2) / c_.calibration_samples);
      const uint16_t expected = stored ? stored_centre_[i] : c_.adc_max / 2;
      const uint16_t off = centre > expected ? centre - expected : expected - centre;
      if (cal_max_[i] - cal_min_[i] > c_.calibration_spread || off > tolerance) return;  // try again
      centre_[i] = centre;
    }
    // per side: full deflection is the last reading before the rail margin, or closer
    for (uint8_t i = 0; i < 2; ++i) {
      uint16_t hi_span = (uint16_t)(c_.adc_max - c_.rail_margin - 1 - centre_[i]);
      uint16_t lo_span = (uint16_t)(centre_[i] - c_.rail_margin - 1);
      if (c_.full_deflection != 0 && hi_span > c_.full_deflection) hi_span = c_.full_deflection;
      if (c_.full_deflection != 0 && lo_span > c_.full_deflection) lo_span = c_.full_deflection;
      scale_hi_[i] = ratio_q15(128, hi_span);  // 128 * 32768 / span
      scale_lo_[i] = ratio_q15(128, lo_span);
      axis_raw_[i] = kNoReading;
    }
    calibrated_ = true;
  }

  // normalised and through the dead zone, again only when the reading moved by more than one
  // count from the one kept (a product and two clamps an axis; the calibration forgets the kept
  // readings). A reading that flickers by a count is the ADC's noise, not the hand (the stick's
  // is about half an LSB rms): taken, each flicker reshaped the stick (the reciprocal square root
  // and the curve, ~400 cycles of the motion pass) and moved the twist by 0.2 % of a full
  // deflection; held, the command lags a slow hand by one count at most.
  // (the test inline, the new reading's work out of line: one copy for both axes)
  int16_t axis(uint16_t raw, uint8_t i) {
    if ((uint16_t)(raw - axis_raw_[i] + 1u) > 2u) take_reading(raw, i);  // |raw - kept| > 1, modulo 2^16
    return axis_v_[i];
  }
  __attribute__((noinline)) void take_reading(uint16_t raw, uint8_t i) {
    axis_raw_[i] = raw;
    axis_v_[i] = dead_zone(normalise(raw, i));
  }

  // reading -> [-32767, 32767], each side scaled to its own span
  int16_t normalise(uint16_t raw, uint8_t i) const {
    const int16_t d = (int16_t)(raw - centre_[i]);
    // scale = 128 * 32767 / span (Q15 of 128/span); d * scale >> 7 = d * 32767 / span
    const int32_t v = shr7(fx::mul_ss(d, d >= 0 ? scale_hi_[i] : scale_lo_[i]));
    return (int16_t)clamp_i32(v, -32767, 32767);
  }

  int16_t dead_zone(int16_t v) const {
    const int16_t a = v < 0 ? (int16_t)-v : v;
    if (a <= c_.dead_zone_q15) return 0;
    // (a - dz) * 32767 / (32767 - dz), with dead_scale_ = (32767/2) * 32767 / (32767 - dz)
    const int32_t r = clamp_i32(shr14_to_i16(fx::mul_ss((int16_t)(a - c_.dead_zone_q15), dead_scale_) + 8192), 0, 32767);
    return v < 0 ? (int16_t)-r : (int16_t)r;
  }

  int16_t ramp(int16_t current, int16_t target, uint8_t ticks) const {
    if (current == target) return current;  // held (what the steps below give, without them)
    const int32_t rise = (int32_t)c_.rise_q15 * ticks, fall = (int32_t)c_.fall_q15 * ticks;
    int32_t next;
    if (current > 0 && target < current) {
      next = (int32_t)current - fall;
      if (next < target) next = target;
      if (next < 0) next = 0;  // through zero one sample at a time
    } else if (current < 0 && target > current) {
      next = (int32_t)current + fall;
      if (next > target) next = target;
      if (next > 0) next = 0;
    } else if (target > current) {
      next = (int32_t)current + rise;  // int32: on the AVR int is 16 bits, and 32767 + rise wraps
      if (next > target) next = target;
    } else {
      next = (int32_t)current - rise;
      if (next < target) next = target;
    }
    return (int16_t)next;
  }

  JoystickConfig c_{1023, 8, 50, 16, 24, 100, 655, 0, 100, 300, 100};
  bool configured_ = false;
  bool calibrated_ = false;
  bool armed_ = false;
  uint8_t cal_count_ = 0;
  uint16_t cal_sum_[2] = {0, 0};
  uint16_t cal_min_[2] = {0, 0};
  uint16_t cal_max_[2] = {0, 0};
  uint16_t centre_[2] = {0, 0};
  uint16_t stored_centre_[2] = {0, 0};
  int16_t scale_hi_[2] = {0, 0};
  int16_t scale_lo_[2] = {0, 0};
  int16_t dead_scale_ = 32767;
  uint8_t rail_count_[2] = {0, 0};
  uint8_t rail_flags_ = 0;
  uint16_t neutral_count_ = 0;
  int16_t out_[2] = {0, 0};
  static constexpr uint16_t kNoReading = 0x8000;  // more than a count from any reading (<= adc_max < 2^15)
  uint16_t axis_raw_[2] = {kNoReading, kNoReading};  // the reading each axis was last normalised from
  int16_t axis_v_[2] = {0, 0};                        // and what axis() made of it
  // the last input of shape() and its output; a new configuration is shaped afresh, since
  // arming shapes the neutral stick's (0, 0) first
  int16_t shaped_in_[2] = {0, 0};
  int16_t shaped_[2] = {0, 0};
};

}  // namespace control
}  // namespace wmra
