// Fixed-point number formats for the ATmega2560 (and bit-identical on the host).
//
// Design (why these formats): the AVR has an 8x8 hardware multiplier and no barrel
// shifter. A 16x16->32 product is one libgcc helper on MUL (~20 cycles); a shift by a
// multiple of 8 is a register move; any other shift of a 32-bit value is a loop. So:
//   Unit     int16  Q15   [-1, 1)       sines, cosines, rotation-matrix entries
//   Length   uint16 UQ16  [0, 1) metres link-length constants (every link is < 1 m)
//   Real     int32  Q23   +-256         positions (m), velocities (m/s, rad/s), rates
// Unit*Length is one 16x16 product whose Q31 result is shifted by 8 into Q23.
// Unit*Real is a 32x16 product built from two 16x16 products (no int64 anywhere).
// Unit*Unit is one 16x16 product, doubled and rounded into Q15.
// Sines and cosines are saturated to +-32767, so Unit*Unit never meets -1 * -1.
#pragma once

#include <stdint.h>

#include "kinematics/ratio.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "fixed_point.h splits 32-bit words through a union and assumes little-endian"
#endif

namespace wmra {
namespace fx {

constexpr int32_t kUnitOne = 32767;  // the largest Unit; 1.0 itself is not representable

// --- raw 16x16 -> 32 products. On the AVR they are written out with MUL/MULS/MULSU
// --- (Atmel AVR201): left to itself avr-gcc folds the operands after inlining and falls
// --- back to 16x32 or 32x32 library calls that cost 3-5 times as much.
#if defined(__AVR__)
inline int32_t mul_ss(int16_t a, int16_t b) {
  int32_t r;
  uint8_t zero;
  asm("clr   %[z]\n\t"
      "muls  %B[a], %B[b]\n\t"
      "movw  %C[r], r0\n\t"
      "mul   %A[a], %A[b]\n\t"
      "movw  %A[r], r0\n\t"
      "mulsu %B[a], %A[b]\n\t"
      "sbc   %D[r], %[z]\n\t"
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "mulsu %B[b], %A[a]\n\t"
      "sbc   %D[r], %[z]\n\t"
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "clr   __zero_reg__"
      : [r] "=&r"(r), [z] "=&r"(zero)
      : [a] "a"(a), [b] "a"(b));
  return r;
}
inline int32_t mul_us(uint16_t a, int16_t b) {
  int32_t r;
  uint8_t zero;
  asm("clr   %[z]\n\t"
      "mulsu %B[b], %B[a]\n\t"
      "movw  %C[r], r0\n\t"
      "mul   %A[a], %A[b]\n\t"
      "movw  %A[r], r0\n\t"
      "mulsu %B[b], %A[a]\n\t"
      "sbc   %D[r], %[z]\n\t"
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "mul   %B[a], %A[b]\n\t"
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "clr   __zero_reg__"
      : [r] "=&r"(r), [z] "=&r"(zero)
      : [a] "a"(a), [b] "a"(b));
  return r;
}
inline uint32_t mul_uu(uint16_t a, uint16_t b) {
  uint32_t r;
  uint8_t zero;
  asm("clr   %[z]\n\t"
      "mul   %A[a], %A[b]\n\t"
      "movw  %A[r], r0\n\t"
      "mul   %B[a], %B[b]\n\t"
      "movw  %C[r], r0\n\t"
      "mul   %B[a], %A[b]\n\t"
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "mul   %A[a], %B[b]\n\t"
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "clr   __zero_reg__"
      : [r] "=&r"(r), [z] "=&r"(zero)
      : [a] "r"(a), [b] "r"(b));
  return r;
}
#else
inline int32_t mul_ss(int16_t a, int16_t b) { return (int32_t)a * b; }
inline int32_t mul_us(uint16_t a, int16_t b) { return (int32_t)a * b; }
inline uint32_t mul_uu(uint16_t a, uint16_t b) { return (uint32_t)a * b; }
#endif

union Word32 {
  int32_t s;
  uint32_t u;
  struct {
    uint16_t lo;
    int16_t hi;
  } h;
};

// the high half of a 32-bit word: x >> 16 as a register move
inline uint16_t hi16(uint32_t x) {
  Word32 w;
  w.u = x;
  return (uint16_t)w.h.hi;
}

// floor(x * c / 2^16), exact: the top 32 bits of the 48-bit product.
// On the AVR the eight 8x8 partial products of the unsigned operands are summed straight
// into the result bytes (byte 0 of the product never carries, so it is not formed). MUL,
// unlike MULS/MULSU, takes any register, which spares the compiler from moving both
// operands into r16-r23 for every product. The signs are put back exactly afterwards:
// with U the unsigned result, floor(x c / 2^16) = U - [c < 0] x - [x < 0] c 2^16 (mod 2^32).
#if defined(__AVR__)
inline uint32_t mul_hi_u32xu16(uint32_t x, uint16_t c) {
  uint32_t r;
  uint8_t t, z;
  asm("clr   %[z]\n\t"
      "mul   %A[x], %A[c]\n\t"  // @0
      "mov   %[t], r1\n\t"
      "mul   %C[x], %A[c]\n\t"  // @2
      "movw  %A[r], r0\n\t"
      "mul   %D[x], %B[c]\n\t"  // @4
      "movw  %C[r], r0\n\t"
      "mul   %B[x], %A[c]\n\t"  // @1
      "add   %[t], r0\n\t"
      "adc   %A[r], r1\n\t"
      "adc   %B[r], %[z]\n\t"
      "adc   %C[r], %[z]\n\t"
      "adc   %D[r], %[z]\n\t"
      "mul   %A[x], %B[c]\n\t"  // @1
      "add   %[t], r0\n\t"
      "adc   %A[r], r1\n\t"
      "adc   %B[r], %[z]\n\t"
      "adc   %C[r], %[z]\n\t"
      "adc   %D[r], %[z]\n\t"
      "mul   %D[x], %A[c]\n\t"  // @3
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "mul   %B[x], %B[c]\n\t"  // @2
      "add   %A[r], r0\n\t"
      "adc   %B[r], r1\n\t"
      "adc   %C[r], %[z]\n\t"
      "adc   %D[r], %[z]\n\t"
      "mul   %C[x], %B[c]\n\t"  // @3
      "add   %B[r], r0\n\t"
      "adc   %C[r], r1\n\t"
      "adc   %D[r], %[z]\n\t"
      "clr   __zero_reg__"
      : [r] "=&r"(r), [t] "=&r"(t), [z] "=&r"(z)
      : [x] "r"(x), [c] "r"(c));
  return r;
}

inline int32_t mul_hi_32x16(int32_t x, int16_t c) {
  Word32 r;
  r.u = mul_hi_u32xu16((uint32_t)x, (uint16_t)c);
  if (c < 0) r.u -= (uint32_t)x;
  if (x < 0) r.h.hi -= c;  // c 2^16: only the high half changes
  return r.s;
}

// floor(x * c / 2^16) for an unsigned c, exact.
inline int32_t mul_hi_32xu16(int32_t x, uint16_t c) {
  Word32 r;
  r.u = mul_hi_u32xu16((uint32_t)x, c);
  if (x < 0) r.h.hi -= (int16_t)c;
  return r.s;
}
#else
inline int32_t mul_hi_32x16(int32_t x, int16_t c) { return (int32_t)(((int64_t)x * c) >> 16); }
inline int32_t mul_hi_32xu16(int32_t x, uint16_t c) { return (int32_t)(((int64_t)x * c) >> 16); }
#endif

// constexpr conversions from real numbers (used for constants and on the host)
constexpr int32_t round_to_int32(double x) { return (int32_t)(x < 0 ? x - 0.5 : x + 0.5); }

struct Unit {
  int16_t raw;
};
struct Length {
  uint16_t raw;
};
struct Real {
  int32_t raw;
};

constexpr int16_t saturate_unit_raw(int64_t raw) {
  return (int16_t)(raw > kUnitOne ? kUnitOne : raw < -kUnitOne ? -kUnitOne : raw);
}
// exact conversions of rational constants (identical on the AVR and the host)
constexpr Unit unit(Ratio r) { return Unit{saturate_unit_raw(div_round(r.num * 32768, r.den))}; }
constexpr Length length(Ratio metres) { return Length{(uint16_t)div_round(metres.num * 65536, metres.den)}; }
constexpr Real real(Ratio r) { return Real{(int32_t)div_round(r.num * 8388608, r.den)}; }

// conversions of measured values at run time on the host (tools and tests)
inline Unit unit(double x) { return Unit{saturate_unit_raw(round_to_int32(x * 32768.0))}; }
inline Real real(double x) { return Real{round_to_int32(x * 8388608.0)}; }

constexpr double to_double(Unit u) { return u.raw / 32768.0; }
constexpr double to_double(Real r) { return r.raw / 8388608.0; }

// --- Unit arithmetic
inline Unit operator-(Unit a) { return Unit{(int16_t)-a.raw}; }
// Sums of rotation terms are bounded by 1 in exact arithmetic; rounding may step past it.
// The sum saturates at +-32767 (never -32768, which would break negation and Unit*Unit).
#if defined(__AVR__)
// add or sub, then on overflow (V set) the limit of the true result's sign, which is
// b's sign for a sum and the opposite of it for a difference; then -32768 -> -32767
#define WMRA_SATURATE_UNIT_ASM(op_lo, op_hi, skip_if_b_negative)                   \
  op_lo "  %A[r], %A[b]\n\t" op_hi "  %B[r], %B[b]\n\t"                          \
        "brvc 1f\n\t"                                                               \
        "ldi  %A[r], 0xFF\n\t"                                                      \
        "ldi  %B[r], 0x7F\n\t" skip_if_b_negative "  %B[b], 7\n\t"                \
        "rjmp 2f\n\t"                                                               \
        "ldi  %A[r], 0x01\n\t"                                                      \
        "ldi  %B[r], 0x80\n\t"                                                      \
        "rjmp 2f\n"                                                                  \
        "1:\n\t"                                                                    \
        "cpi  %B[r], 0x80\n\t"                                                      \
        "brne 2f\n\t"                                                               \
        "tst  %A[r]\n\t"                                                            \
        "brne 2f\n\t"                                                               \
        "ldi  %A[r], 0x01\n"                                                         \
        "2:"
inline Unit operator+(Unit a, Unit b) {
  int16_t r = a.raw;
  asm(WMRA_SATURATE_UNIT_ASM("add", "adc", "sbrs") : [r] "+d"(r) : [b] "r"(b.raw));
  return Unit{r};
}
inline Unit operator-(Unit a, Unit b) {
  int16_t r = a.raw;
  asm(WMRA_SATURATE_UNIT_ASM("sub", "sbc", "sbrc") : [r] "+d"(r) : [b] "r"(b.raw));
  return Unit{r};
}
#undef WMRA_SATURATE_UNIT_ASM
#else
inline Unit saturated_sum(int32_t sum) {
  return Unit{(int16_t)(sum > kUnitOne ? kUnitOne : sum < -kUnitOne ? -kUnitOne : sum)};
}
inline Unit operator+(Unit a, Unit b) { return saturated_sum((int32_t)a.raw + b.raw); }
inline Unit operator-(Unit a, Unit b) { return saturated_sum((int32_t)a.raw - b.raw); }
#endif
// Unit * Unit = (a b + 2^14) >> 15, rounded to nearest. |a|, |b| <= 32767 keeps the sum below 2^30.
// On the AVR the rounding and the shift by 15 are done inside the multiply.
#if defined(__AVR__)
inline Unit operator*(Unit a, Unit b) {
  int16_t r;
  uint8_t low, z;
  asm("clr   %[z]\n\t"
      "mul   %A[a], %A[b]\n\t"  // @0: only its high byte reaches byte 1
      "mov   %[low], r1\n\t"
      "muls  %B[a], %B[b]\n\t"  // @2
      "movw  %A[r], r0\n\t"
      "mulsu %B[a], %A[b]\n\t"  // @1, signed
      "sbc   %B[r], %[z]\n\t"
      "add   %[low], r0\n\t"
      "adc   %A[r], r1\n\t"
      "adc   %B[r], %[z]\n\t"
      "mulsu %B[b], %A[a]\n\t"  // @1, signed
      "sbc   %B[r], %[z]\n\t"
      "add   %[low], r0\n\t"
      "adc   %A[r], r1\n\t"
      "adc   %B[r], %[z]\n\t"
      "clr   __zero_reg__\n\t"
      "subi  %[low], 0xC0\n\t"  // + 2^14, i.e. 0x40 in byte 1
      "sbci  %A[r], 0xFF\n\t"
      "sbci  %B[r], 0xFF\n\t"
      "lsl   %[low]\n\t"         // >> 15: one left shift of bytes 1-3, keep bytes 2-3
      "rol   %A[r]\n\t"
      "rol   %B[r]"
      : [r] "=&d"(r), [low] "=&d"(low), [z] "=&r"(z)
      : [a] "a"(a.raw), [b] "a"(b.raw));
  return Unit{r};
}
#else
inline Unit operator*(Unit a, Unit b) { return Unit{(int16_t)(((int32_t)a.raw * b.raw + 16384) >> 15)}; }
#endif

// --- Real arithmetic
inline Real operator+(Real a, Real b) { return Real{a.raw + b.raw}; }
inline Real operator-(Real a, Real b) { return Real{a.raw - b.raw}; }
inline Real operator-(Real a) { return Real{-a.raw}; }
inline bool operator<(Real a, Real b) { return a.raw < b.raw; }
inline bool operator>(Real a, Real b) { return a.raw > b.raw; }

// Unit * Real: Q15 * Q23 = Q38; >>16 gives Q22, one doubling gives Q23 (the lost bit is
// 1.2e-7 of a metre or a rad/s).
inline Real operator*(Unit u, Real r) {
  const int32_t q22 = mul_hi_32x16(r.raw, u.raw);
  return Real{q22 + q22};
}
inline Real operator*(Real r, Unit u) { return u * r; }

// Unit * Length: Q15 * UQ16 = Q31, >>8 gives Q23.
inline Real operator*(Unit u, Length l) {
  Word32 p;
  p.s = mul_us(l.raw, u.raw);
  return Real{p.s >> 8};
}
inline Real operator*(Length l, Unit u) { return u * l; }

inline Real to_real(Length l) { return Real{(int32_t)l.raw << 7}; }
inline Real to_real(Unit u) { return Real{(int32_t)u.raw << 8}; }
inline Real operator+(Real a, Length b) { return a + to_real(b); }
inline Real operator+(Length a, Real b) { return to_real(a) + b; }

// Real -> Unit for values known to lie in (-1, 1) (positions of the wrist within 1 m,
// normalised ratios); saturates instead of wrapping.
inline Unit to_unit(Real r) {
  return Unit{saturate_unit_raw((r.raw + 0x80) >> 8)};
}

}  // namespace fx
}  // namespace wmra
