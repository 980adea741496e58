// Trigonometry on binary angles: sin, cos, atan2 and sqrt in integer arithmetic.
//
// Angle: int32 with 2^18 counts per turn, so each quadrant is exactly the low 16 bits and
// the quadrant number is bits 16-17; wrap-around is free and +-8192 turns are representable.
// One count is 2.4e-5 rad. sin and cos interpolate a quarter-wave table; atan on [0, 1] is
// an odd degree-9 polynomial (fit error 1.2e-5 rad) whose products are 16x16 multiplies
// with a shift by 16.
#pragma once

#include "kinematics/flash.h"
#include "kinematics/reciprocal.h"

namespace wmra {
namespace fx {

constexpr double kPi = 3.14159265358979323846;

struct Angle {
  int32_t raw;
};
constexpr int32_t kAngleTurn = 262144;  // 2^18 counts per turn
constexpr Angle angle_deg(Ratio degrees) { return Angle{(int32_t)div_round(degrees.num * kAngleTurn, degrees.den * 360)}; }
inline Angle angle(double rad) { return Angle{round_to_int32(rad * (kAngleTurn / (2.0 * kPi)))}; }
constexpr double to_radians(Angle a) { return a.raw * (2.0 * kPi / kAngleTurn); }
inline Angle operator+(Angle a, Angle b) { return Angle{a.raw + b.raw}; }
inline Angle operator-(Angle a, Angle b) { return Angle{a.raw - b.raw}; }
inline Angle operator-(Angle a) { return Angle{-a.raw}; }
inline bool operator<(Angle a, Angle b) { return a.raw < b.raw; }
inline bool operator>(Angle a, Angle b) { return a.raw > b.raw; }
// the same direction in (-pi, pi]: the low 18 bits, sign-extended
inline Angle wrap(Angle a) {
  const int32_t r = a.raw & (kAngleTurn - 1);
  return Angle{r > kAngleTurn / 2 ? r - kAngleTurn : r};
}

struct SinCos {
  Unit s;
  Unit c;
};

// Quarter-wave table round(32768 sin(pi/2 i/256)), i = 0..257 (entries 256 and 257 saturate
// at 32767), kept in flash; test/host checks every entry. Linear interpolation between
// entries is within 4.7e-6 of the sine; neighbours differ by at most 201, so the
// interpolation is one 8x8 MUL. (A literal, not a constexpr computation: avr-gcc's double
// has 32 bits and could round an entry differently from the host.)
inline const int16_t* sin_table() {
  static const int16_t table[258] WMRA_FLASH = {
    0, 201, 402, 603, 804, 1005, 1206, 1407, 1608, 1809, 2009, 2210,
    2411, 2611, 2811, 3012, 3212, 3412, 3612, 3812, 4011, 4211, 4410, 4609,
    4808, 5007, 5205, 5404, 5602, 5800, 5998, 6195, 6393, 6590, 6787, 6983,
    7180, 7376, 7571, 7767, 7962, 8157, 8351, 8546, 8740, 8933, 9127, 9319,
    9512, 9704, 9896, 10088, 10279, 10469, 10660, 10850, 11039, 11228, 11417, 11605,
    11793, 11980, 12167, 12354, 12540, 12725, 12910, 13095, 13279, 13463, 13646, 13828,
    14010, 14192, 14373, 14553, 14733, 14912, 15091, 15269, 15447, 15624, 15800, 15976,
    16151, 16326, 16500, 16673, 16846, 17018, 17190, 17361, 17531, 17700, 17869, 18037,
    18205, 18372, 18538, 18703, 18868, 19032, 19195, 19358, 19520, 19681, 19841, 20001,
    20160, 20318, 20475, 20632, 20788, 20943, 21097, 21251, 21403, 21555, 21706, 21856,
    22006, 22154, 22302, 22449, 22595, 22740, 22884, 23028, 23170, 23312, 23453, 23593,
    23732, 23870, 24008, 24144, 24279, 24414, 24548, 24680, 24812, 24943, 25073, 25202,
    25330, 25457, 25583, 25708, 25833, 25956, 26078, 26199, 26320, 26439, 26557, 26674,
    26791, 26906, 27020, 27133, 27246, 27357, 27467, 27576, 27684, 27791, 27897, 28002,
    28106, 28209, 28311, 28411, 28511, 28610, 28707, 28803, 28899, 28993, 29086, 29178,
    29269, 29359, 29448, 29535, 29622, 29707, 29792, 29875, 29957, 30038, 30118, 30196,
    30274, 30350, 30425, 30499, 30572, 30644, 30715, 30784, 30853, 30920, 30986, 31050,
    31114, 31177, 31238, 31298, 31357, 31415, 31471, 31527, 31581, 31634, 31686, 31737,
    31786, 31834, 31881, 31927, 31972, 32015, 32058, 32099, 32138, 32177, 32214, 32251,
    32286, 32319, 32352, 32383, 32413, 32442, 32470, 32496, 32522, 32546, 32568, 32590,
    32610, 32629, 32647, 32664, 32679, 32693, 32706, 32718, 32729, 32738, 32746, 32753,
    32758, 32762, 32766, 32767, 32767, 32767,
  };
  return table;
}

// The table interpolated at x/256 for x in [0, 2^16): sin(pi/2 x/2^16), and with the table
// read backwards (cos(x) = sin(2^16 - x)) the cosine. Each is one 8x8 MUL.
inline int16_t interpolate_up(const int16_t* t, uint8_t i, uint8_t f) {
  const int16_t lo = flash_read_i16(t + i);
  const uint8_t step = (uint8_t)(flash_read_i16(t + i + 1) - lo);
  return (int16_t)(lo + (((uint16_t)step * f + 128u) >> 8));
}
inline int16_t interpolate_down(const int16_t* t, uint8_t i, uint8_t f) {
  const int16_t hi = flash_read_i16(t + 256 - i);
  const uint8_t step = (uint8_t)(hi - flash_read_i16(t + 255 - i));
  return (int16_t)(hi - (((uint16_t)step * f + 128u) >> 8));
}
// sin and cos of an angle: the table interpolated up (sine) and down (cosine) at the angle
// within its quadrant, then swapped and negated by the quadrant.
#if defined(__AVR__)
// Asm blocks with three LPM reads and one MUL per interpolation, (x + 128) >> 8 as the high
// byte plus bit 7 of the low byte; only the low bytes of the neighbours are needed for the
// step (<= 201). Byte 1 of the angle is the table index i, byte 0 the fraction, bits 16-17
// the quadrant. %[zero] is cleared first; Z points at the table, %[down] at entry 255.
#define WMRA_TABLE_UP_ASM(out)        /* out = t[i] interpolated up */ \
  "add   r30, %B[a]\n\t"                                               \
  "adc   r31, %[zero]\n\t"                                             \
  "add   r30, %B[a]\n\t"                                               \
  "adc   r31, %[zero]\n\t"                                             \
  "lpm   %A[" #out "], Z+\n\t"                                         \
  "lpm   %B[" #out "], Z+\n\t"                                         \
  "lpm   %[step], Z\n\t" /* low byte of t[i + 1] */                   \
  "sub   %[step], %A[" #out "]\n\t"                                    \
  "mul   %[step], %A[a]\n\t"                                           \
  "lsl   r0\n\t"                                                       \
  "adc   r1, %[zero]\n\t"                                              \
  "add   %A[" #out "], r1\n\t"                                         \
  "adc   %B[" #out "], %[zero]\n\t"
#define WMRA_TABLE_DOWN_ASM(out)      /* out = t[256 - i] interpolated down */ \
  "sub   %A[down], %B[a]\n\t"                                                  \
  "sbc   %B[down], %[zero]\n\t"                                                \
  "sub   %A[down], %B[a]\n\t"                                                  \
  "sbc   %B[down], %[zero]\n\t"                                                \
  "movw  r30, %[down]\n\t"                                                     \
  "lpm   %[step], Z\n\t" /* low byte of t[255 - i] */                         \
  "adiw  r30, 2\n\t"                                                           \
  "lpm   %A[" #out "], Z+\n\t"                                                 \
  "lpm   %B[" #out "], Z\n\t"                                                  \
  "neg   %[step]\n\t"                                                          \
  "add   %[step], %A[" #out "]\n\t"                                            \
  "mul   %[step], %A[a]\n\t"                                                   \
  "lsl   r0\n\t"                                                               \
  "adc   r1, %[zero]\n\t"                                                      \
  "sub   %A[" #out "], r1\n\t"                                                 \
  "sbc   %B[" #out "], %[zero]\n\t"
#define WMRA_NEGATE_ASM(x)   \
  "neg   %B[" #x "]\n\t"     \
  "neg   %A[" #x "]\n\t"     \
  "sbc   %B[" #x "], %[zero]\n\t"
inline SinCos sincos(Angle a) {
  const int16_t* up = sin_table();
  const int16_t* down = sin_table() + 255;
  int16_t s, c;
  uint8_t step, zero;
  asm("clr   %[zero]\n\t" WMRA_TABLE_UP_ASM(s) WMRA_TABLE_DOWN_ASM(c) "clr   __zero_reg__\n\t"
      "sbrs  %C[a], 0\n\t"  // quadrants 1, 3: (s, c) = (c, -s)
      "rjmp  1f\n\t"
      "movw  %[down], %[c]\n\t"
      "movw  %[c], %[s]\n\t"
      "movw  %[s], %[down]\n\t" WMRA_NEGATE_ASM(c)
      "1:\n\t"
      "sbrs  %C[a], 1\n\t"  // quadrants 2, 3: (s, c) = (-s, -c)
      "rjmp  2f\n\t" WMRA_NEGATE_ASM(s) WMRA_NEGATE_ASM(c)
      "2:"
      : [s] "=&r"(s), [c] "=&r"(c), [step] "=&r"(step), [zero] "=&r"(zero), "+z"(up), [down] "+r"(down)
      : [a] "r"(a.raw));
  return SinCos{Unit{s}, Unit{c}};
}
// the sine alone: interpolated up in quadrants 0, 2 and down in 1, 3, negated in 2, 3
inline Unit sin(Angle a) {
  const int16_t* up = sin_table();
  const int16_t* down = sin_table() + 255;
  int16_t s;
  uint8_t step, zero;
  asm("clr   %[zero]\n\t"
      "sbrc  %C[a], 0\n\t"
      "rjmp  1f\n\t" WMRA_TABLE_UP_ASM(s)
      "rjmp  2f\n"
      "1:\n\t" WMRA_TABLE_DOWN_ASM(s)
      "2:\n\t"
      "clr   __zero_reg__\n\t"
      "sbrs  %C[a], 1\n\t"
      "rjmp  3f\n\t" WMRA_NEGATE_ASM(s)
      "3:"
      : [s] "=&r"(s), [step] "=&r"(step), [zero] "=&r"(zero), "+z"(up), [down] "+r"(down)
      : [a] "r"(a.raw));
  return Unit{s};
}
#undef WMRA_TABLE_UP_ASM
#undef WMRA_TABLE_DOWN_ASM
#undef WMRA_NEGATE_ASM
#else
inline SinCos sincos(Angle a) {
  const uint8_t i = (uint8_t)(a.raw >> 8);
  const uint8_t f = (uint8_t)a.raw;
  const int16_t s0 = interpolate_up(sin_table(), i, f);
  const int16_t c0 = interpolate_down(sin_table(), i, f);
  switch ((uint8_t)(a.raw >> 16) & 3u) {
    case 0: return SinCos{Unit{s0}, Unit{c0}};
    case 1: return SinCos{Unit{c0}, Unit{(int16_t)-s0}};
    case 2: return SinCos{Unit{(int16_t)-s0}, Unit{(int16_t)-c0}};
    default: return SinCos{Unit{(int16_t)-c0}, Unit{s0}};
  }
}

inline Unit sin(Angle a) {
  const uint8_t i = (uint8_t)(a.raw >> 8);
  const uint8_t f = (uint8_t)a.raw;
  switch ((uint8_t)(a.raw >> 16) & 3u) {
    case 0: return Unit{interpolate_up(sin_table(), i, f)};
    case 1: return Unit{interpolate_down(sin_table(), i, f)};
    case 2: return Unit{(int16_t)-interpolate_up(sin_table(), i, f)};
    default: return Unit{(int16_t)-interpolate_down(sin_table(), i, f)};
  }
}
#endif

// atan(t) / (pi/4) * 2^15 for t = ratio / 2^16 in [0, 1]: an angle in [0, 2^15] counts.
inline uint16_t atan_octant(uint16_t ratio, bool one) {
  if (one) return 32768u;
  const uint16_t u = (uint16_t)(mul_uu(ratio, ratio) >> 16);  // t^2, UQ16
  // atan(t)/(pi/4) = t (k1 - u (k3 - u (k5 - u (k7 - u k9)))), coefficients in UQ16/UQ1.15
  uint16_t p = 1747;                                        // k9 = 0.0266512
  p = (uint16_t)(7127u - (mul_uu(u, p) >> 16));             // k7 = 0.1087452
  p = (uint16_t)(15054u - (mul_uu(u, p) >> 16));            // k5 = 0.2297086
  p = (uint16_t)(27570u - (mul_uu(u, p) >> 16));            // k3 = 0.4206854
  const uint16_t r = (uint16_t)(41716u - (hi16(mul_uu(u, p)) >> 1));  // k1 = 1.2730852, UQ1.15
  return (uint16_t)((mul_uu(ratio, r) + 0x8000u) >> 16);    // turns/8 in Q15
}

// atan2(y, x) as an Angle in (-pi, pi]; atan2(0, 0) = 0. Inputs are any int32 in the same unit.
inline Angle atan2(int32_t y, int32_t x) {
  if (x == 0 && y == 0) return Angle{0};
  uint32_t ax = x < 0 ? 0u - (uint32_t)x : (uint32_t)x;
  uint32_t ay = y < 0 ? 0u - (uint32_t)y : (uint32_t)y;
  const bool swap = ay > ax;
  uint32_t big = swap ? ay : ax;
  uint32_t small = swap ? ax : ay;
  // bring big into [2^15, 2^16) with small scaled alike, then ratio = small/big in UQ16
  while (big >= 65536u) {
    big >>= 1;
    small >>= 1;
  }
  while (big < 32768u) {
    big <<= 1;
    small <<= 1;
  }
  const uint16_t inv = half_reciprocal_uq16((uint16_t)big);  // 2^31 / big
  // ratio = small / big = small * (2^31 / big) / 2^31 -> UQ16 = small * inv / 2^15
  const uint32_t ratio_q31 = mul_uu((uint16_t)small, inv) + 0x4000u;
  const bool one = ratio_q31 >= 0x80000000u;
  int32_t octant = atan_octant(one ? 0 : hi16(ratio_q31 << 1), one);  // [0, 2^15] = [0, pi/4]
  int32_t a = swap ? 65536 - octant : octant;                         // [0, pi/2]
  if (x < 0) a = 131072 - a;                                          // [0, pi]
  return Angle{y < 0 ? -a : a};
}

// floor(sqrt(v)) for a 32-bit unsigned v: the root's bits from the top, each kept if the
// square still fits, one 16x16 hardware product a bit (the remainder form of the bitwise
// root needs 32-bit adds, compares and shifts for each, about twice the cycles on the AVR);
// a value below 2^16 has no root bits above 2^7.
inline uint16_t isqrt32(uint32_t v) {
  uint16_t bit = v < 0x10000ul ? 0x80 : 0x8000;
  uint16_t root = 0;
  for (; bit != 0; bit >>= 1) {
    const uint16_t trial = (uint16_t)(root | bit);
    if (mul_uu(trial, trial) <= v) root = trial;
  }
  return root;
}

// sqrt(v) rounded to nearest, for v < 2^32 - 2^16
inline uint16_t isqrt32_rounded(uint32_t v) {
  const uint16_t r = isqrt32(v);
  return v - mul_uu(r, r) > r ? (uint16_t)(r + 1) : r;
}

// sqrt(a^2 + b^2) of two Units, saturated at 32767: the length of a vector of direction cosines
inline Unit hypot(Unit a, Unit b) {
  const uint16_t ma = (uint16_t)(a.raw < 0 ? -a.raw : a.raw), mb = (uint16_t)(b.raw < 0 ? -b.raw : b.raw);
  const uint16_t r = isqrt32_rounded(mul_uu(ma, ma) + mul_uu(mb, mb));
  return Unit{(int16_t)(r > kUnitOne ? kUnitOne : r)};
}

// sqrt(1 - c^2) in Q15: a sine from its cosine, >= 0
inline Unit sqrt_one_minus_square(Unit c) {
  const uint16_t mc = (uint16_t)(c.raw < 0 ? -c.raw : c.raw);
  const uint16_t r = isqrt32_rounded(((uint32_t)1 << 30) - mul_uu(mc, mc));
  return Unit{(int16_t)(r > kUnitOne ? kUnitOne : r)};
}

}  // namespace fx
}  // namespace wmra
