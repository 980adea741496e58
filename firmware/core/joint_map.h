// Conversions between the firmware's joint units, without a division in the control loop:
//   Angle       fx::Angle, 2^18 counts per turn: the references q_ref and the kinematics;
//   steps       microsteps of a stepper joint (its ramp's position count);
//   pot units   ADC counts x 16 of a DC joint's potentiometer (the PID's position unit: the
//               factor 16 keeps the fraction of a reference integrated from a velocity);
//   rad/s       fx::Real (Q23) joint velocities from the resolved rate.
// Each conversion factor is a Scale: x -> x * m / 2^15 * 2^e with m in [2^14, 2^15), one
// 32 x 16 multiply and a shift (relative error below 2^-14 from rounding m).
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "kinematics/fixed_point.h"
#include "kinematics/fixed_trig.h"
#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace core {

struct Scale {
  int16_t m;
  int8_t e;
};

// a Scale for a positive factor (constexpr: from config numbers at compile time, or at boot
// from a calibration)
constexpr Scale scale_for(double factor) {
  int8_t e = 0;
  double f = factor;
  while (f >= 1.0) {
    f /= 2;
    ++e;
  }
  while (f < 0.5) {
    f *= 2;
    --e;
  }
  const int32_t m = (int32_t)(f * 32768.0 + 0.5);
  return m >= 32768 ? Scale{16384, (int8_t)(e + 1)} : Scale{(int16_t)m, e};
}

// The same Scale for num / den > 0 at run time (a calibration from EEPROM), in integers: float
// arithmetic would link the AVR's float library for one boot-time computation, and 64-bit
// integers libgcc's 64-bit division (~700 B of flash).
// num / den = f 2^e with f in [0.5, 1), m = round(f 2^15) = floor((n 2^16 + d) / (2 d))
// = floor((floor(n 2^16 / d) + 1) / 2) (floors compose), the quotient's 16 bits by long
// division: the remainder r < d doubles into r - (d - r) or r + r, never past 32 bits.
// For num, den < 2^31 (d << 1 and 2 n stay within 32 bits). At boot and at a calibration only.
inline Scale scale_for_ratio(uint32_t num, uint32_t den) {
  int8_t e = 0;
  uint32_t n = num, d = den;
  while (n >= d) {
    d <<= 1;
    ++e;
  }
  while (2 * n < d) {
    n <<= 1;
    --e;
  }
  uint32_t r = n;
  uint16_t q = 0;
  for (uint8_t bit = 0; bit < 16; ++bit) {
    const uint32_t rest = d - r;
    q = (uint16_t)(q << 1);
    if (r >= rest) {
      r -= rest;
      q |= 1;
    } else {
      r += r;
    }
  }
  const uint16_t m = (uint16_t)((q >> 1) + (q & 1));  // (q + 1) / 2: q + 1 overflows 16 bits
  return m >= 32768 ? Scale{16384, (int8_t)(e + 1)} : Scale{(int16_t)m, e};
}

// p 2^e. avr-gcc shifts a 32-bit value by any count but 8, 16 and 24 in a loop, ~6 cycles a
// bit (the position per tick's 2^-9 was 60 cycles): whole bytes first, as register moves, the
// empty asm keeping the compiler from folding them back into one shift; a loop of at most 7
// bits remains. The same result as one shift (an arithmetic shift right is a floor, and
// floors compose).
inline int32_t times_power_of_two(int32_t p, int8_t e) {
  if (e >= 0) {
    uint8_t n = (uint8_t)e;
    if (n >= 8) {
      p = (int32_t)((uint32_t)p << 8);
      asm("" : "+r"(p));
      n = (uint8_t)(n - 8);
    }
    return (int32_t)((uint32_t)p << n);
  }
  uint8_t n = (uint8_t)-e;
  if (n >= 16) {
    p >>= 16;
    asm("" : "+r"(p));
    n = (uint8_t)(n - 16);
  }
  if (n >= 8) {
    p >>= 8;
    asm("" : "+r"(p));
    n = (uint8_t)(n - 8);
  }
  return p >> n;
}

// x m / 2^15 2^e; for e < 0 one bit of the shift goes into the product (mul_q16, which keeps
// bytes 2-5 of it, where mul_q15 shifts them all one bit): the same floor
inline int32_t apply(Scale s, int32_t x) {
  return s.e < 0 ? times_power_of_two(fx::mul_q16(x, s.m), (int8_t)(s.e + 1)) : times_power_of_two(fx::mul_q15(x, s.m), s.e);
}

constexpr double kPi = 3.14159265358979323846;
constexpr double kAngleCountsPerRad = fx::kAngleTurn / (2 * kPi);
constexpr double kRealPerRad = 8388608.0;  // fx::Real is Q23
// fx::Real per thousandth, rounded: m/s from mm/s, rad/s from mrad/s (the link's units)
constexpr int32_t kRealPerMilli = 8389;
constexpr double kLoopHz = 1000.0;

// a step per control tick over the `ticks` that passed: one tick, or two after an overrun,
// need no product (a 32-bit one is a library call, ~70 cycles)
inline int32_t ticks_times(int32_t per_tick, uint8_t ticks) {
  return ticks == 1 ? per_tick : ticks == 2 ? per_tick + per_tick : per_tick * ticks;
}

// A velocity in rad/s (Q23) as Angle counts per control tick, Q16 (the fraction is carried),
// and per two ticks (the motion pass's period): the same product, shifted one bit less
constexpr Scale kRateToAngleQ16PerTick = scale_for(kAngleCountsPerRad / kRealPerRad / kLoopHz * 65536.0);
constexpr Scale kRateToAngleQ16PerTwoTicks = Scale{kRateToAngleQ16PerTick.m, (int8_t)(kRateToAngleQ16PerTick.e + 1)};

// The joints' reference angles and velocities, plus the fraction of a count that each angle's
// integration carries. The angles are one JointAngles, which the kinematics read in place (a
// copy of six angles out of {angle, fraction} pairs was ~120 cycles an iteration); each
// velocity lies 24 bytes after its angle, so that the AVR's pass over the six joints reaches
// both through one pointer (the fractions through the other).
struct JointReferences {
  kin::JointAngles<kin::Fixed> q;
  fx::Real qd_rad_s[6];
  uint16_t fraction[6];

  void set(uint8_t j, fx::Angle a) {
    q.q[j] = a;
    fraction[j] = 0;
  }
  // one step at qd: of one control tick, or of two (kRateToAngleQ16PerTwoTicks)
  void advance(uint8_t j, fx::Real qd, Scale per_step = kRateToAngleQ16PerTick) {
    const int32_t delta_q16 = apply(per_step, qd.raw) + fraction[j];
    q.q[j].raw += delta_q16 >> 16;  // arithmetic shift: floor, the fraction stays in [0, 1)
    fraction[j] = (uint16_t)delta_q16;
  }
  // one step of every joint at its qd_rad_s, of one tick or of two: advance(j, qd_rad_s[j], the
  // step's Scale) for each j
  void advance_all(bool two_ticks = false);
  // `ticks` control ticks: steps of two (a motion pass's), an odd tick one step of its own; the
  // carried fraction composes the steps
  void advance_ticks(uint8_t ticks) {
    while (ticks) {
      const bool two = ticks >= 2;
      advance_all(two);
      ticks = (uint8_t)(ticks - (two ? 2 : 1));
    }
  }
};

static_assert(kRateToAngleQ16PerTick.e == -1 && kRateToAngleQ16PerTick.m > 0,
              "advance_all's step is apply()'s mul_q16 alone (two ticks': mul_q15), of a positive factor");
static_assert((kRateToAngleQ16PerTick.m & 0xFF) < 0x80, "two ticks' factor 2m: its low byte twice m's, without a carry");
#if defined(__AVR__)
// One asm loop (avr-gcc's six-joint loop reloaded its pointers and `ticks` from the stack,
// ~113 cycles a joint): Z walks the angles (the velocity at Z+24), X the fractions. Per joint
// fixed_point.h's mul_q16 without the factor's sign (m > 0), the fraction added and stored,
// the whole counts (bytes 2-3, sign-extended) added to the angle. r1 is restored once, at the
// end. Two ticks' step is the product by 2m (unsigned, below 2^16): with lo8(m) < 128 its
// left-out term lo8(x) lo8(2m) is twice m's, so bytes 2-5 are mul_q15's floor of the product
// by m, without its shift (7 cycles a joint).
inline void JointReferences::advance_all(bool two_ticks) {
  static_assert(offsetof(JointReferences, qd_rad_s) == offsetof(JointReferences, q) + 24, "each velocity 24 bytes after its angle");
  fx::Angle* angle = q.q;
  uint16_t* carried = fraction;
  int32_t x, r;
  uint8_t t, z, n;
  asm volatile(
      "clr   %[z]\n\t"
      "ldi   %[n], 6\n"
      "1:\n\t"
      "ldd   %A[x], Z+24\n\t"
      "ldd   %B[x], Z+25\n\t"
      "ldd   %C[x], Z+26\n\t"
      "ldd   %D[x], Z+27\n\t" WMRA_MUL32X16_SET_ASM(x, c) WMRA_REAL_SIGN_ASM(x, c, 2)
      "ld    %A[x], X+\n\t"  // + the carried fraction, whose new value is the low half
      "ld    %B[x], X\n\t"
      "add   %A[r], %A[x]\n\t"
      "adc   %B[r], %B[x]\n\t"
      "adc   %C[r], %[z]\n\t"
      "adc   %D[r], %[z]\n\t"
      "st    X, %B[r]\n\t"
      "st    -X, %A[r]\n\t"
      "adiw  %A[f], 2\n\t"
      "clr   %[t]\n\t"  // the high half's sign
      "sbrc  %D[r], 7\n\t"
      "com   %[t]\n\t"
      "ld    %A[x], Z\n\t"
      "ldd   %B[x], Z+1\n\t"
      "ldd   %C[x], Z+2\n\t"
      "ldd   %D[x], Z+3\n\t"
      "add   %A[x], %C[r]\n\t"
      "adc   %B[x], %D[r]\n\t"
      "adc   %C[x], %[t]\n\t"
      "adc   %D[x], %[t]\n\t"
      "st    Z+, %A[x]\n\t"
      "st    Z+, %B[x]\n\t"
      "st    Z+, %C[x]\n\t"
      "st    Z+, %D[x]\n\t"
      "dec   %[n]\n\t"
      "breq  3f\n\t"
      "rjmp  1b\n"
      "3:\n\t"
      "clr   __zero_reg__"
      : [x] "=&r"(x), [r] "=&r"(r), [t] "=&r"(t), [z] "=&r"(z), [n] "=&d"(n), [q] "+z"(angle), [f] "+x"(carried)
      : [c] "r"((uint16_t)(two_ticks ? 2 * kRateToAngleQ16PerTick.m : kRateToAngleQ16PerTick.m))
      : "memory");
}
#else
inline void JointReferences::advance_all(bool two_ticks) {
  for (uint8_t j = 0; j < 6; ++j) advance(j, qd_rad_s[j], two_ticks ? kRateToAngleQ16PerTwoTicks : kRateToAngleQ16PerTick);
}
#endif

// A stepper joint: steps per turn of the joint (motor steps x microsteps x reduction).
// angle() keeps kExtraBits more bits through its product than apply() (whose product, shifted
// up, has its lowest e bits 0: 32 counts, 1.6 steps of J1), and steps() rounds to the nearest
// step, so that steps(angle(n)) == n: a reference taken from the step count (entering running,
// after homing or a move) asks for no step at all. For |steps| < 2^16 (J5's 90 deg: 16,000).
struct StepperMap {
  static constexpr int8_t kExtraBits = 14;

  Scale steps_per_angle;  // position
  Scale angle_per_step;
  Scale steps_s_per_rate;  // speed: steps/s per Q23 rad/s
  int16_t half_step;       // Angle counts in half a step (rounded down)

  static constexpr StepperMap make(uint32_t steps_per_turn) {
    return StepperMap{scale_for((double)steps_per_turn / fx::kAngleTurn), scale_for((double)fx::kAngleTurn / steps_per_turn),
                      scale_for(steps_per_turn / (2 * kPi) / kRealPerRad), (int16_t)(fx::kAngleTurn / 2 / steps_per_turn)};
  }
  int32_t steps(fx::Angle a) const { return apply(steps_per_angle, a.raw + half_step); }
  fx::Angle angle(int32_t steps) const {
    return fx::Angle{fx::mul_q15(steps << kExtraBits, angle_per_step.m) >> (kExtraBits - angle_per_step.e)};
  }
  // angle() for a stepper known at compile time (a constant Scale): the same floors, its shifts
  // by constants in byte moves and a few bits, where a shift by a count is a loop (~7 cycles a bit)
  __attribute__((always_inline)) static fx::Angle angle_of(int32_t steps, Scale angle_per_step) {
    return fx::Angle{times_power_of_two(fx::mul_q15(times_power_of_two(steps, kExtraBits), angle_per_step.m),
                                        (int8_t)(angle_per_step.e - kExtraBits))};
  }
  int32_t speed_steps_s(fx::Real qd) const { return apply(steps_s_per_rate, qd.raw); }
};

// A DC joint's potentiometer: pot units at the joint's lower limit and per Angle count.
struct PotMap {
  fx::Angle q_min;
  int32_t units_at_min;
  Scale units_per_angle;
  Scale angle_per_unit;

  // from the pot units (ADC counts x 16) read at the joint's two limits (a calibration),
  // units_at_max > units_at_min, q_max > q_min. At boot and at a calibration only.
  static PotMap make(fx::Angle q_min, fx::Angle q_max, int32_t units_at_min, int32_t units_at_max) {
    const uint32_t units = (uint32_t)(units_at_max - units_at_min), counts = (uint32_t)(q_max.raw - q_min.raw);
    return PotMap{q_min, units_at_min, scale_for_ratio(units, counts), scale_for_ratio(counts, units)};
  }
  // A reference in pot units as 16 bits, saturated to [-16384, 16383]: a reading's range
  // [0, 16368] and as far again below, so that a reference less a reading fits 16 bits. A
  // reference within the joint's limits is within [units_at_min, units_at_max], untouched.
  // Every calibration settings.cpp takes as plausible (a span of 600 to 1023 ADC counts over
  // J2-J4's 180 to 320 deg) has an exponent of -3 or -4: apply()'s shift after mul_q16 is then
  // 2 or 3 bits, here by constants (a run-time count is a loop, ~7 cycles a bit) in steps of at
  // most 2 bits (avr-gcc unrolls those; floors compose); any other exponent as apply() does.
  int16_t units(fx::Angle a) const {
    const int32_t x = a.raw - q_min.raw;
    const Scale s = units_per_angle;
    int32_t scaled;
    if (s.e >= 0) {
      scaled = apply(s, x);
    } else {
      scaled = fx::mul_q16(x, s.m);
      switch (s.e) {
        case -3:
          scaled >>= 2;
          break;
        case -4:
          scaled >>= 2;
          asm("" : "+r"(scaled));
          scaled >>= 1;
          break;
        default:
          scaled = times_power_of_two(scaled, (int8_t)(s.e + 1));
      }
    }
    const int32_t u = units_at_min + scaled;
    return (int16_t)(u > 16383 ? 16383 : u < -16384 ? -16384 : u);
  }
  fx::Angle angle(int32_t units) const { return fx::Angle{q_min.raw + apply(angle_per_unit, units - units_at_min)}; }
};

}  // namespace core
}  // namespace wmra
