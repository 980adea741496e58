// Reciprocals without a divide instruction, and the damped reciprocal used at singularities.
//
// A libgcc 32/16 division costs ~650 cycles on the AVR. Here 1/x comes from a normalised
// mantissa and a power of two: x is shifted into [0.5, 1) and 1/(2m) is interpolated in a
// table (checked exhaustively in test/host), then scaled back by the shift.
#pragma once

#include "kinematics/fixed_point.h"
#include "kinematics/flash.h"

namespace wmra {
namespace fx {

// value = (negative ? -1 : 1) * mantissa / 2^16 * scale. The scale is a power of two up to
// 2^7, so |value| < 128: the singular factors are inverted at least eps = 0.05 away from zero
// (1/x <= 20), and the largest product of two, 1/(a2 s3), stays below 60. The mantissa is in
// [2^15, 2^16) except for values below 0.5, which keep scale 1, and for damped values.
struct Recip {
  uint16_t mantissa;
  uint8_t scale;
  bool negative;
};
constexpr uint8_t kRecipMaxScale = 128;

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

// 1/(2m) in UQ16 for m = normalised / 2^16 in [0.5, 1): the table at i = the 8 bits after
// the leading one, less step * f2 / 256 rounded, with f2 the remaining 7 bits (as a fraction
// of 256) and step the drop to the next entry (< 256, so only the low bytes are read).
inline uint16_t half_reciprocal_uq16(uint16_t normalised) {
  const uint8_t i = (uint8_t)(normalised >> 7);
  const uint8_t f2 = (uint8_t)(normalised << 1);
  const uint16_t* t = half_reciprocal_table();
  const uint16_t hi = flash_read_u16(t + i);
  const uint8_t step = (uint8_t)(hi - flash_read_u16(t + i + 1));
  return (uint16_t)(hi - (((uint16_t)step * f2 + 128u) >> 8));
}

// 1/x for x = +-magnitude / 2^15, magnitude != 0, saturated at +-128 for |x| < 2^-7.
// x = a / 2^15; a << s = A in [2^15, 2^16) gives x = 2 (A / 2^16) 2^-s and 1/x = 2^s / (2m):
// the table's value with scale 2^s.
#if defined(__AVR__)
// One asm block: the doublings unrolled (at most seven), then half_reciprocal_uq16 with
// three LPM reads and one MUL ((x + 128) >> 8 as the high byte plus bit 7 of the low byte).
#define WMRA_DOUBLE_UNLESS_NORMALISED_ASM \
  "sbrc  %B[n], 7\n\t"                    \
  "rjmp  1f\n\t"                          \
  "lsl   %A[n]\n\t"                       \
  "rol   %B[n]\n\t"                       \
  "lsl   %[scale]\n\t"
inline Recip reciprocal_of_magnitude(uint16_t magnitude, bool negative) {
  const uint16_t* t = half_reciprocal_table();
  uint16_t m;
  uint8_t scale, i, f2, z;
  asm("ldi   %[scale], 1\n\t"
      WMRA_DOUBLE_UNLESS_NORMALISED_ASM WMRA_DOUBLE_UNLESS_NORMALISED_ASM WMRA_DOUBLE_UNLESS_NORMALISED_ASM
      WMRA_DOUBLE_UNLESS_NORMALISED_ASM WMRA_DOUBLE_UNLESS_NORMALISED_ASM WMRA_DOUBLE_UNLESS_NORMALISED_ASM
      WMRA_DOUBLE_UNLESS_NORMALISED_ASM
      "sbrc  %B[n], 7\n\t"
      "rjmp  1f\n\t"
      "ldi   %A[m], 0xFF\n\t"  // still below 2^15 after seven doublings: saturated
      "ldi   %B[m], 0xFF\n\t"
      "rjmp  2f\n"
      "1:\n\t"
      "clr   %[z]\n\t"
      "mov   %[f2], %A[n]\n\t"
      "lsl   %[f2]\n\t"  // f2, and bit 7 into the carry
      "mov   %[i], %B[n]\n\t"
      "rol   %[i]\n\t"  // i: bits 7-14
      "add   r30, %[i]\n\t"
      "adc   r31, %[z]\n\t"
      "add   r30, %[i]\n\t"
      "adc   r31, %[z]\n\t"
      "lpm   %A[m], Z+\n\t"  // t[i]
      "lpm   %B[m], Z+\n\t"
      "lpm   %[i], Z\n\t"  // low byte of t[i + 1]
      "neg   %[i]\n\t"
      "add   %[i], %A[m]\n\t"  // the step
      "mul   %[i], %[f2]\n\t"
      "lsl   r0\n\t"
      "adc   r1, %[z]\n\t"
      "sub   %A[m], r1\n\t"
      "sbc   %B[m], %[z]\n\t"
      "clr   __zero_reg__\n"
      "2:"
      : [m] "=&d"(m), [scale] "=&d"(scale), [i] "=&r"(i), [f2] "=&r"(f2), [z] "=&r"(z), "+z"(t),
        [n] "+r"(magnitude));
  return Recip{m, scale, negative};
}
#undef WMRA_DOUBLE_UNLESS_NORMALISED_ASM
#else
inline Recip reciprocal_of_magnitude(uint16_t magnitude, bool negative) {
  uint8_t scale = 1;
  while (!(magnitude & 0x8000u)) {
    if (scale == kRecipMaxScale) return Recip{65535, kRecipMaxScale, negative};
    magnitude <<= 1;
    scale <<= 1;
  }
  return Recip{half_reciprocal_uq16(magnitude), scale, negative};
}
#endif

// 1/x for a Unit x != 0, saturated at +-128 for |x| < 2^-7.
inline Recip reciprocal(Unit x) {
  return reciprocal_of_magnitude((uint16_t)(x.raw < 0 ? -(int32_t)x.raw : x.raw), x.raw < 0);
}

// 1/x for a Real x > 0. Shifting the raw value left by n into [2^31, 2^32) gives
// x = m 2^(9-n) with m in [0.5, 1), so 1/x = (1/2m) 2^(n-8): the table's value with scale
// 2^(n-8). For x >= 2 (n < 8) the mantissa is shifted down instead (scale 1); below
// x = 2^-7 the result saturates at 128, as reciprocal(Unit) does.
inline Recip reciprocal(Real x) {
  if (x.raw <= 0) return Recip{65535, kRecipMaxScale, false};
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
  if (n < 8) return Recip{(uint16_t)(mantissa >> (8 - n)), 1, false};
  if (n > 15) return Recip{65535, kRecipMaxScale, false};
  return Recip{mantissa, (uint8_t)(1u << (n - 8)), false};
}

// Real * Recip = +-floor((x mantissa - lo8(x) lo8(mantissa)) / 2^16) scale, saturated at
// +-kRecipProductLimit (lo8 as in fixed_point.h's products).
// Only products through a damped reciprocal, with a large twist and two singular factors at
// once, come near the limit; the saturation keeps later sums of a few such terms far inside
// the Real range (+-256).
constexpr int32_t kRecipProductLimit = (int32_t)1 << 29;  // 64.0 in Q23
#if defined(__AVR__)
// One asm block. r = floor((x m - lo8(x) lo8(m)) / 2^16) from the partial products of
// fixed_point.h (only the sign of x to put back, m is unsigned); q = r scale, a 40-bit
// product of four 8x8 MULs less [r < 0] scale 2^32; q is in range when bytes 3-4, read as
// an int16, lie in [-32, 32).
inline Real operator*(Real x, Recip k) {
  int32_t q, r;
  uint8_t t, top, z;
  asm("clr   %[z]\n\t" WMRA_MUL32X16_SET_ASM(x, m) WMRA_REAL_SIGN_ASM(x, m, 1)
      "mul   %A[r], %[s]\n\t"  // q = r scale
      "movw  %A[q], r0\n\t"
      "mul   %C[r], %[s]\n\t"
      "movw  %C[q], r0\n\t"
      "mul   %B[r], %[s]\n\t"
      "clr   %[top]\n\t"
      "add   %B[q], r0\n\t"
      "adc   %C[q], r1\n\t"
      "adc   %D[q], %[z]\n\t"
      "adc   %[top], %[z]\n\t"
      "mul   %D[r], %[s]\n\t"
      "add   %D[q], r0\n\t"
      "adc   %[top], r1\n\t"
      "sbrc  %D[r], 7\n\t"
      "sub   %[top], %[s]\n\t"
      "clr   __zero_reg__\n\t"
      "mov   %A[r], %D[q]\n\t"  // (top:D) + 32 < 64 unsigned: in range
      "mov   %B[r], %[top]\n\t"
      "subi  %A[r], 0xE0\n\t"
      "sbci  %B[r], 0xFF\n\t"
      "cpi   %A[r], 0x40\n\t"
      "cpc   %B[r], %[z]\n\t"
      "brlo  2f\n\t"
      "clr   %A[q]\n\t"  // +-2^29 by the sign of q
      "clr   %B[q]\n\t"
      "clr   %C[q]\n\t"
      "ldi   %A[r], 0x20\n\t"
      "sbrc  %[top], 7\n\t"
      "ldi   %A[r], 0xE0\n\t"
      "mov   %D[q], %A[r]\n"
      "2:\n\t"
      "sbrs  %[neg], 0\n\t"
      "rjmp  3f\n\t"
      "com   %D[q]\n\t"  // -q = ~q + 1 (com sets the carry)
      "com   %C[q]\n\t"
      "com   %B[q]\n\t"
      "com   %A[q]\n\t"
      "adc   %A[q], %[z]\n\t"
      "adc   %B[q], %[z]\n\t"
      "adc   %C[q], %[z]\n\t"
      "adc   %D[q], %[z]\n"
      "3:"
      : [q] "=&r"(q), [r] "=&d"(r), [t] "=&r"(t), [top] "=&r"(top), [z] "=&r"(z)
      : [x] "r"(x.raw), [m] "r"(k.mantissa), [s] "r"(k.scale), [neg] "r"(k.negative));
  return Real{q};
}
#else
inline Real operator*(Real x, Recip k) {
  const int64_t q = (product_without_low_bytes(x.raw, k.mantissa) >> 16) * k.scale;
  const int64_t limit = kRecipProductLimit;
  const int32_t limited = (int32_t)(q > limit ? limit : q < -limit ? -limit : q);
  return Real{k.negative ? -limited : limited};
}
#endif

// Recip * Recip: the high half of the product of the mantissas, renormalised by one bit if
// the scale allows, and the product of the scales; saturated at the largest Recip.
#if defined(__AVR__)
// One asm block: the three high 8x8 partial products of the mantissas (byte 0 of the 32-bit
// product never carries) and one for the scales.
inline Recip operator*(Recip a, Recip b) {
  uint16_t m, scale;
  uint8_t t, z;
  asm("clr   %[z]\n\t"
      "mul   %A[a], %A[b]\n\t"  // @0
      "mov   %[t], r1\n\t"
      "mul   %B[a], %B[b]\n\t"  // @2
      "movw  %[m], r0\n\t"
      "mul   %B[a], %A[b]\n\t"  // @1
      "add   %[t], r0\n\t"
      "adc   %A[m], r1\n\t"
      "adc   %B[m], %[z]\n\t"
      "mul   %A[a], %B[b]\n\t"  // @1
      "add   %[t], r0\n\t"
      "adc   %A[m], r1\n\t"
      "adc   %B[m], %[z]\n\t"
      "mul   %[sa], %[sb]\n\t"
      "movw  %[scale], r0\n\t"
      "clr   __zero_reg__\n\t"
      "sbrc  %B[m], 7\n\t"  // renormalise: the top bit clear and scale > 1
      "rjmp  1f\n\t"
      "cpi   %A[scale], 2\n\t"
      "cpc   %B[scale], %[z]\n\t"
      "brlo  1f\n\t"
      "lsl   %[t]\n\t"
      "rol   %A[m]\n\t"
      "rol   %B[m]\n\t"
      "lsr   %B[scale]\n\t"
      "ror   %A[scale]\n"
      "1:\n\t"
      "cpi   %A[scale], 0x81\n\t"  // above kRecipMaxScale (128): saturated
      "cpc   %B[scale], %[z]\n\t"
      "brlo  2f\n\t"
      "ldi   %A[m], 0xFF\n\t"
      "ldi   %B[m], 0xFF\n\t"
      "ldi   %A[scale], 0x80\n"
      "2:"
      : [m] "=&d"(m), [scale] "=&d"(scale), [t] "=&r"(t), [z] "=&r"(z)
      : [a] "r"(a.mantissa), [b] "r"(b.mantissa), [sa] "r"(a.scale), [sb] "r"(b.scale));
  return Recip{m, (uint8_t)scale, a.negative != b.negative};
}
#else
inline Recip operator*(Recip a, Recip b) {
  uint32_t p = (uint32_t)a.mantissa * b.mantissa;  // UQ32
  uint16_t scale = (uint16_t)(a.scale * b.scale);
  if (!(p & 0x80000000u) && scale > 1) {
    p <<= 1;
    scale >>= 1;
  }
  const bool negative = a.negative != b.negative;
  if (scale > kRecipMaxScale) return Recip{65535, kRecipMaxScale, negative};
  return Recip{(uint16_t)(p >> 16), (uint8_t)scale, negative};
}
#endif

// Recip of a positive rational constant c, in integer arithmetic: 1/c = den/num lies in
// [2^(s-1), 2^s) and the mantissa is (den/num) / 2^s in UQ16.
constexpr uint8_t recip_shift_for(int64_t den, int64_t num) { return den < num ? 0 : 1 + recip_shift_for(den, num * 2); }
constexpr Recip recip_from_mantissa(int64_t mantissa, uint8_t shift) {
  return mantissa >= 65536 ? Recip{32768, (uint8_t)(1 << (shift + 1)), false}
                           : Recip{(uint16_t)mantissa, (uint8_t)(1 << shift), false};
}
constexpr Recip recip_constant(Ratio c) {
  return recip_shift_for(c.den, c.num) > 7
             ? Recip{65535, kRecipMaxScale, false}
             : recip_from_mantissa(div_round(c.den * 65536, c.num << recip_shift_for(c.den, c.num)),
                                   recip_shift_for(c.den, c.num));
}

// The band |x| < eps of a damped reciprocal. Inside it |x|/eps^2 < 1/eps gets the fixed scale
// 2^s >= 1/eps, so a = |x| in Q15 is below 2^(16 - s), and the mantissa
// a / eps^2 / 2^s in UQ16 is (a 2^s) slope / 2^15 with slope = 2^(46 - 2s) / eps^2 in Q15
// units, which lies in (2^14, 2^16] (2^16 itself is kept as 65535).
struct DampedBand {
  Unit eps;
  uint16_t slope;
  uint8_t scale;
};
constexpr uint8_t damped_shift_for(int64_t eps_raw, uint8_t shift = 0) {
  return (32768 >> shift) <= eps_raw ? shift : damped_shift_for(eps_raw, (uint8_t)(shift + 1));
}
constexpr uint16_t damped_slope(int64_t slope) { return (uint16_t)(slope > 65535 ? 65535 : slope); }
constexpr DampedBand damped_band(Unit eps) {
  return DampedBand{
      eps,
      damped_slope(div_round((int64_t)1 << (46 - 2 * damped_shift_for(eps.raw)), (int64_t)eps.raw * eps.raw)),
      (uint8_t)(1 << damped_shift_for(eps.raw))};
}

// Damped reciprocal: 1/x for |x| >= eps, x/eps^2 inside the band. It is odd, continuous
// at |x| = eps, bounded by 1/eps, and zero at x = 0, so a factor that passes through zero
// gives joint velocities that pass through zero instead of jumping to infinity.
inline Recip damped_reciprocal(Unit x, DampedBand band) {
  const int16_t a = x.raw < 0 ? -x.raw : x.raw;
  if (a >= band.eps.raw) return reciprocal_of_magnitude((uint16_t)a, x.raw < 0);
  return Recip{hi16(mul_uu((uint16_t)(a * band.scale), band.slope) << 1), band.scale, x.raw < 0};
}

}  // namespace fx
}  // namespace wmra
