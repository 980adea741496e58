// Reciprocals without a divide instruction, and the damped reciprocal used at singularities.
//
// A libgcc 32/16 division costs ~650 cycles on the AVR. Here 1/x is a normalised mantissa
// and a power of two: x is shifted into [0.5, 1) and 1/(2m) is interpolated in a table
// (checked exhaustively in test/host).
#pragma once

#include "kinematics/fixed_point.h"
#include "kinematics/flash.h"

namespace wmra {
namespace fx {

// value = (negative ? -1 : 1) * mantissa / 2^16 * 2^shift; the mantissa is in [2^15, 2^16)
// except for values below 0.5 that a damped reciprocal can produce
struct Recip {
  uint16_t mantissa;
  uint8_t shift;
  bool negative;
};

// Table round(2^16 / (2m)) for m = 0.5 + i/512, i = 0..256 (entry 0 saturates at 65535);
// test/host checks every entry. Neighbours differ by at most 255, so the interpolation is
// one 8x8 MUL; its error is below 3.8e-6 of the value.
inline const uint16_t* half_reciprocal_table() {
  static const uint16_t table[257] WMRA_FLASH = {
    65535, 65281, 65028, 64777, 64528, 64281, 64035, 63792, 63550, 63310, 63072, 62836,
    62602, 62369, 62138, 61909, 61681, 61455, 61231, 61008, 60787, 60568, 60350, 60133,
    59919, 59705, 59494, 59283, 59075, 58867, 58662, 58457, 58254, 58053, 57852, 57654,
    57456, 57260, 57065, 56872, 56680, 56489, 56299, 56111, 55924, 55738, 55554, 55370,
    55188, 55007, 54828, 54649, 54471, 54295, 54120, 53946, 53773, 53601, 53431, 53261,
    53092, 52925, 52759, 52593, 52429, 52265, 52103, 51942, 51782, 51622, 51464, 51306,
    51150, 50995, 50840, 50686, 50534, 50382, 50231, 50081, 49932, 49784, 49637, 49490,
    49345, 49200, 49056, 48913, 48771, 48630, 48489, 48349, 48210, 48072, 47935, 47798,
    47663, 47528, 47393, 47260, 47127, 46995, 46864, 46733, 46603, 46474, 46346, 46218,
    46091, 45965, 45839, 45714, 45590, 45467, 45344, 45222, 45100, 44979, 44859, 44739,
    44620, 44502, 44384, 44267, 44151, 44035, 43919, 43805, 43691, 43577, 43464, 43352,
    43240, 43129, 43019, 42908, 42799, 42690, 42582, 42474, 42367, 42260, 42154, 42048,
    41943, 41838, 41734, 41631, 41528, 41425, 41323, 41222, 41121, 41020, 40920, 40820,
    40721, 40623, 40525, 40427, 40330, 40233, 40137, 40041, 39946, 39851, 39756, 39662,
    39569, 39476, 39383, 39291, 39199, 39108, 39017, 38926, 38836, 38746, 38657, 38568,
    38480, 38392, 38304, 38217, 38130, 38044, 37958, 37872, 37787, 37702, 37617, 37533,
    37449, 37366, 37283, 37200, 37118, 37036, 36954, 36873, 36792, 36712, 36631, 36552,
    36472, 36393, 36314, 36236, 36158, 36080, 36003, 35926, 35849, 35772, 35696, 35620,
    35545, 35470, 35395, 35320, 35246, 35172, 35099, 35026, 34953, 34880, 34808, 34735,
    34664, 34592, 34521, 34450, 34380, 34309, 34239, 34169, 34100, 34031, 33962, 33893,
    33825, 33757, 33689, 33622, 33554, 33487, 33421, 33354, 33288, 33222, 33157, 33091,
    33026, 32961, 32897, 32832, 32768,
  };
  return table;
}

// 1/(2m) in UQ16 for m = normalised / 2^16 in [0.5, 1)
inline uint16_t half_reciprocal_uq16(uint16_t normalised) {
  const uint8_t i = (uint8_t)(normalised >> 7);   // the 8 bits after the leading one
  const uint8_t f2 = (uint8_t)(normalised << 1);  // the remaining 7 bits, as a fraction of 256
  const uint16_t* t = half_reciprocal_table();
  const uint16_t hi = flash_read_u16(t + i);
  const uint8_t step = (uint8_t)(hi - flash_read_u16(t + i + 1));
  return (uint16_t)(hi - (((uint16_t)step * f2 + 128u) >> 8));
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

// 1/x for a Real x > 0. Shifting the raw value left by n into [2^31, 2^32) gives
// x = m 2^(9-n) with m in [0.5, 1), so 1/x = (1/2m) 2^(n-8); for x >= 2 (n < 8) the
// mantissa is shifted down instead, as a Recip's shift is not negative.
inline Recip reciprocal(Real x) {
  uint32_t v = (uint32_t)x.raw;
  uint8_t n = 0;
  while (!(v & 0xFF000000u)) {
    v <<= 8;
    n += 8;
  }
  while (!(v & 0x80000000u)) {
    v <<= 1;
    ++n;
  }
  const uint16_t mantissa = half_reciprocal_uq16(hi16(v));
  if (n >= 8) return Recip{mantissa, (uint8_t)(n - 8), false};
  return Recip{(uint16_t)(mantissa >> (8 - n)), 0, false};
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

// Recip * Recip: the product of the mantissas, renormalised, and the sum of the shifts.
inline Recip operator*(Recip a, Recip b) {
  Word32 p;
  p.u = mul_uu(a.mantissa, b.mantissa);  // UQ32
  uint8_t shift = (uint8_t)(a.shift + b.shift);
  if (!(p.u & 0x80000000u) && shift > 0) {
    p.u <<= 1;
    --shift;
  }
  return Recip{(uint16_t)p.h.hi, shift, a.negative != b.negative};
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
