// Reciprocals without a divide instruction, and the damped reciprocal used at singularities.
//
// A libgcc 32/16 division costs ~650 cycles on the AVR. Here 1/x is a normalised mantissa
// and a power of two: x is shifted into [0.5, 1), a linear first guess (error <= 1/17) is
// refined by two Newton steps y <- y + y(1 - 2m y) on the 16-bit multiplier, which leaves
// an error near the 16-bit rounding floor (checked exhaustively in test/host).
#pragma once

#include "kinematics/fixed_point.h"

namespace wmra {
namespace fx {

// value = (negative ? -1 : 1) * mantissa / 2^16 * 2^shift; the mantissa is in [2^15, 2^16)
// except for values below 0.5 that a damped reciprocal can produce
struct Recip {
  uint16_t mantissa;
  uint8_t shift;
  bool negative;
};

// 1/(2m) for m = normalised / 2^16 in [0.5, 1), as UQ16 (1.0 saturates to 65535).
inline uint16_t half_reciprocal_uq16(uint16_t normalised) {
  // y0 = 24/17 - 16/17 m  (in UQ16: 92521 - 0.941176 * M)
  uint32_t y = 92521u - (mul_uu(normalised, 61681u) >> 16);
  for (uint8_t i = 0; i < 2; ++i) {
    // e = 1 - 2 m y in Q31; |e| <= 1/17 < 2^-4, so e in Q16 needs 13 bits and the
    // doubling below cannot overflow
    const uint16_t y16 = y > 65535u ? 65535u : (uint16_t)y;
    const int32_t e_q31 = (int32_t)(0x80000000u - mul_uu(normalised, y16));
    Word32 e;
    e.s = (e_q31 + 0x4000) << 1;
    y = (uint32_t)((int32_t)y16 + (mul_us(y16, e.h.hi) >> 16));
  }
  return y > 65535u ? 65535u : (uint16_t)y;
}

// 1/x for a Unit x != 0.
inline Recip reciprocal(Unit x) {
  uint16_t magnitude = (uint16_t)(x.raw < 0 ? -(int32_t)x.raw : x.raw);
  // x = a / 2^15; shift a into [2^15, 2^16): a << s = M, x = 2 (M / 2^16) 2^-s, 1/x = 2^s / (2m)
  uint8_t s = 0;
  while (!(magnitude & 0x8000u)) {
    magnitude <<= 1;
    ++s;
  }
  return Recip{half_reciprocal_uq16(magnitude), s, x.raw < 0};
}

// Real * Recip, saturated at +-kRecipProductLimit. Only products through a damped
// reciprocal, with a large twist and two singular factors at once, come near it; the
// saturation keeps later sums of a few such terms far inside the Real range (+-256).
constexpr int32_t kRecipProductLimit = (int32_t)1 << 29;  // 64.0 in Q23
inline Real operator*(Real r, Recip k) {
  int32_t p = mul_hi_32xu16(r.raw, k.mantissa);
  for (uint8_t i = 0; i < k.shift; ++i) {
    if (p >= kRecipProductLimit / 2 || p <= -kRecipProductLimit / 2) {
      p = p > 0 ? kRecipProductLimit : -kRecipProductLimit;
      break;
    }
    p += p;
  }
  return Real{k.negative ? -p : p};
}

// Recip of a positive rational constant c, in integer arithmetic: 1/c = den/num lies in
// [2^(s-1), 2^s) and the mantissa is (den/num) / 2^s in UQ16.
constexpr uint8_t recip_shift_for(int64_t den, int64_t num) { return den < num ? 0 : 1 + recip_shift_for(den, num * 2); }
constexpr Recip recip_from_mantissa(int64_t mantissa, uint8_t shift) {
  return mantissa >= 65536 ? Recip{32768, (uint8_t)(shift + 1), false} : Recip{(uint16_t)mantissa, shift, false};
}
constexpr Recip recip_constant(Ratio c) {
  return recip_from_mantissa(div_round(c.den * 65536, c.num << recip_shift_for(c.den, c.num)),
                             recip_shift_for(c.den, c.num));
}

// Damped reciprocal: 1/x for |x| >= eps, x/eps^2 inside the band. It is odd, continuous
// at |x| = eps, bounded by 1/eps, and zero at x = 0, so a factor that passes through zero
// gives joint velocities that pass through zero instead of jumping to infinity.
// inv_eps2 = recip_constant(eps * eps).
inline Recip damped_reciprocal(Unit x, Unit eps, Recip inv_eps2) {
  const int16_t a = x.raw < 0 ? -x.raw : x.raw;
  if (a >= eps.raw) return reciprocal(x);
  // (a/2^15)*(mant/2^16) = p/2^31, so the value is (p>>16)/2^16 * 2^(shift+1); normalise the
  // mantissa for precision, but never below a shift of 0 (tiny values keep a small mantissa)
  Word32 n;
  n.u = mul_uu((uint16_t)a, inv_eps2.mantissa);
  uint8_t shift = inv_eps2.shift + 1;
  while (!(n.u & 0x80000000u) && shift > 0) {
    n.u <<= 1;
    --shift;
  }
  return Recip{(uint16_t)n.h.hi, shift, x.raw < 0};
}

}  // namespace fx
}  // namespace wmra
