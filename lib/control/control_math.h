// Small integer helpers shared by the control blocks: saturation instead of wrap-around,
// magnitudes that survive INT32_MIN, and the few products the blocks need, built on the
// exact AVR multiply routines of kinematics/fixed_point.h (bit-identical on the host).
#pragma once

#include <stdint.h>

#include "kinematics/fixed_point.h"
#include "kinematics/flash.h"

namespace wmra {
namespace control {

constexpr int32_t kInt32Max = 2147483647;
constexpr int32_t kInt32Min = -2147483647 - 1;

constexpr int32_t clamp_i32(int32_t x, int32_t lo, int32_t hi) { return x < lo ? lo : x > hi ? hi : x; }
constexpr int16_t saturate_i16(int32_t x) { return (int16_t)clamp_i32(x, -32767, 32767); }
// |x| as unsigned: defined for INT32_MIN too
constexpr uint32_t magnitude_u32(int32_t x) { return x < 0 ? 0u - (uint32_t)x : (uint32_t)x; }
constexpr int8_t sign_of(int32_t x) { return (int8_t)(x > 0 ? 1 : x < 0 ? -1 : 0); }

// a + b and a - b saturated to the int32 range (the sums a controller forms from clamped
// terms stay far inside it; these only make the corner cases defined): the add and the
// overflow flag
inline int32_t add_saturated(int32_t a, int32_t b) {
  int32_t s;
  if (__builtin_add_overflow(a, b, &s)) return a < 0 ? kInt32Min + 1 : kInt32Max;
  return s;
}
inline int32_t sub_saturated(int32_t a, int32_t b) {
  int32_t s;
  if (__builtin_sub_overflow(a, b, &s)) return a < 0 ? kInt32Min + 1 : kInt32Max;
  return s;
}

// a - b of 16-bit operands saturated to +-32767, as saturate_i16(sub_saturated(a, b)) would
// give: a 16-bit subtraction and the overflow flag (no 32-bit arithmetic)
inline int16_t sub_saturated_i16(int16_t a, int16_t b) {
  int16_t s;
  if (__builtin_sub_overflow(a, b, &s)) return a < 0 ? (int16_t)-32767 : (int16_t)32767;
  return s == -32768 ? (int16_t)-32767 : s;
}
// |a - b| of 16-bit operands, exact: the difference of two int16 values fits 16 bits unsigned
inline uint16_t distance_u16(int16_t a, int16_t b) { return a < b ? (uint16_t)((uint16_t)b - (uint16_t)a) : (uint16_t)((uint16_t)a - (uint16_t)b); }

// a + b of counts that saturate at 255 rather than wrap
inline uint8_t add_saturated_u8(uint8_t a, uint8_t b) { return a > 255 - b ? (uint8_t)255 : (uint8_t)(a + b); }

// a * n for a product that fits int32 (modulo 2^32 otherwise), from two hardware 16x16
// products: avr-gcc calls its 32x32 library routine for int32 * uint8
inline int32_t mul_i32_u8(int32_t a, uint8_t n) {
  fx::Word32 w;
  w.s = a;
  return (int32_t)(((uint32_t)fx::mul_ss(w.h.hi, n) << 16) + fx::mul_uu(w.h.lo, n));
}

// floor(a * b / 2^16) for unsigned operands, exact (the AVR routine, or 64-bit on the host)
#if defined(__AVR__)
inline uint32_t mul_hi_u32xu16(uint32_t a, uint16_t b) { return fx::mul_hi_u32xu16(a, b); }
#else
inline uint32_t mul_hi_u32xu16(uint32_t a, uint16_t b) { return (uint32_t)(((uint64_t)a * b) >> 16); }
#endif

// floor(a * b / 2^32), exact, from two 32x16 products
inline uint32_t mul_hi_u32xu32(uint32_t a, uint32_t b) {
  fx::Word32 w;
  w.u = b;
  const uint32_t hi = mul_hi_u32xu16(a, (uint16_t)w.h.hi);  // a * bhi / 2^16
  const uint32_t lo = mul_hi_u32xu16(a, w.h.lo);           // a * blo / 2^16
  // a*b/2^32 = (hi*2^16 + (a*bhi mod 2^16) + lo) / 2^16: the low half of a*bhi is lost in hi,
  // so recover it from the full product's low bits
  const uint16_t hi_low = (uint16_t)((unsigned)(uint16_t)a * (unsigned)(uint16_t)w.h.hi);  // mod 2^16
  const uint32_t sum = (uint32_t)hi_low + lo;  // < 2^16 + 2^32: may carry
  const uint32_t carry_sum = (sum < lo) ? (1ul << 16) : 0;  // wrapped past 2^32
  return hi + (sum >> 16) + carry_sum;
}

// Constant shifts of 32-bit values by other than whole bytes are loops on the AVR (7 cycles a
// bit): these do them as a 1- or 2-bit shift and a byte move. floor(x / 2^k), for |x| < 2^(31-m).
inline int32_t shr7(int32_t x) { return (int32_t)((uint32_t)x << 1) >> 8; }                  // |x| < 2^30
inline int16_t shr14_to_i16(int32_t x) { return (int16_t)fx::hi16((uint32_t)x << 2); }       // |x| < 2^29
inline int16_t shr15_to_i16(int32_t x) { return (int16_t)fx::hi16((uint32_t)x << 1); }       // |x| < 2^30

// x >> n with n < 32, rounded to nearest
inline uint32_t shift_right_rounded(uint32_t x, uint8_t n) {
  if (n == 0) return x;
  --n;
  while (n >= 8) {  // whole bytes are register moves on the AVR
    x >>= 8;
    n -= 8;
  }
  x >>= n;
  return (x >> 1) + (x & 1u);
}

#if defined(__AVR__)
inline uint32_t flash_read_u32(const uint32_t* p) { return pgm_read_dword(p); }
#else
inline uint32_t flash_read_u32(const uint32_t* p) { return *p; }
#endif

// 2^16 / sqrt(u) for u = 1 + i/64, i = 0..192 (entry 0 saturates); checked in test_step_ramp
inline const uint16_t* rsqrt_table() {
  static const uint16_t table[193] WMRA_FLASH = {
    65535, 65030, 64535, 64052, 63579, 63117, 62664, 62222, 61788, 61363, 60947, 60540,
    60140, 59748, 59364, 58987, 58617, 58254, 57898, 57548, 57205, 56867, 56535, 56210,
    55889, 55574, 55265, 54960, 54661, 54366, 54076, 53791, 53510, 53233, 52961, 52693,
    52429, 52169, 51912, 51660, 51411, 51165, 50923, 50685, 50450, 50218, 49989, 49763,
    49541, 49321, 49104, 48890, 48679, 48470, 48265, 48061, 47861, 47663, 47467, 47273,
    47082, 46894, 46707, 46523, 46341, 46161, 45983, 45807, 45633, 45462, 45292, 45124,
    44957, 44793, 44630, 44470, 44310, 44153, 43997, 43843, 43691, 43540, 43390, 43243,
    43096, 42951, 42808, 42666, 42525, 42386, 42248, 42112, 41977, 41843, 41710, 41579,
    41449, 41320, 41192, 41065, 40940, 40816, 40693, 40571, 40450, 40330, 40211, 40093,
    39977, 39861, 39746, 39632, 39520, 39408, 39297, 39187, 39078, 38970, 38863, 38756,
    38651, 38546, 38443, 38340, 38238, 38136, 38036, 37936, 37837, 37739, 37642, 37545,
    37449, 37354, 37260, 37166, 37073, 36980, 36889, 36798, 36708, 36618, 36529, 36441,
    36353, 36266, 36179, 36093, 36008, 35924, 35840, 35756, 35673, 35591, 35509, 35428,
    35347, 35267, 35188, 35109, 35030, 34953, 34875, 34798, 34722, 34646, 34571, 34496,
    34421, 34347, 34274, 34201, 34128, 34056, 33985, 33913, 33843, 33772, 33703, 33633,
    33564, 33496, 33427, 33360, 33292, 33225, 33159, 33093, 33027, 32962, 32897, 32832,
    32768,
  };
  return table;
}

// 1/sqrt(x) for x >= 1 as r 2^(s-31), r in (2^15, 2^16): x is normalised into [2^30, 2^32) by
// s shifts of 2 bits, and 2^16/sqrt(x/2^30) interpolated in rsqrt_table (relative error
// below 7e-5, test_step_ramp). One table read pair and one 16x8 product.
inline uint16_t rsqrt_normalised(uint32_t x, uint8_t& s) {
  s = 0;
  while (x < (1ul << 22)) {
    x <<= 8;
    s += 4;
  }
  while (x < (1ul << 30)) {
    x <<= 2;
    ++s;
  }
  const uint16_t top = fx::hi16(x);
  const uint8_t i = (uint8_t)((top >> 8) - 64);
  const uint8_t f = (uint8_t)top;
  const uint16_t* t = rsqrt_table();
  const uint16_t t0 = fx::flash_read_u16(t + i);
  const uint16_t t1 = fx::flash_read_u16(t + i + 1);
  return (uint16_t)(t0 - (uint16_t)(fx::mul_uu((uint16_t)(t0 - t1), f) >> 8));
}

// floor(sqrt(v)) of a 64-bit value by Newton's iteration (compile-time and configuration-time
// use only: it divides)
constexpr uint64_t isqrt64(uint64_t v) {
  if (v < 2) return v;
  uint64_t x = v;
  uint64_t y = v / 2 + 1;
  while (y < x) {
    x = y;
    y = (x + v / x) / 2;
  }
  return x;
}

}  // namespace control
}  // namespace wmra
