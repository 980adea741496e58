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

// Integer square root of a 64-bit value (compile-time and configuration-time use only).
constexpr uint64_t isqrt64(uint64_t v) {
  uint64_t root = 0;
  uint64_t bit = (uint64_t)1 << 62;
  while (bit > v) bit >>= 2;
  while (bit != 0) {
    if (v >= root + bit) {
      v -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return root;
}

}  // namespace control
}  // namespace wmra
