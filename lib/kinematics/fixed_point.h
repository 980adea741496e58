// Fixed-point number formats for the ATmega2560 (and bit-identical on the host).
//
// Design (why these formats): the AVR has an 8x8 hardware multiplier and no barrel
// shifter. A 16x16->32 product is one libgcc helper on MUL (~20 cycles); a shift by a
// multiple of 8 is a register move; any other shift of a 32-bit value is a loop. So:
//   Unit     int16  Q15   [-1, 1)       sines, cosines, rotation-matrix entries
//   Length   uint16 UQ16  [0, 1) metres link-length constants (every link is < 1 m)
//   Real     int32  Q23   +-256         positions (m), velocities (m/s, rad/s), rates
// Unit*Length is one 16x16 product, a Q31 Span; sums of them stay exact until they join a
// Real (shifted by 8 into Q23) or become a Unit (rounded into Q15).
// Unit*Real is a 32x16 product of 8x8 MULs (no int64 anywhere), shifted by 15 into Q23;
// a sum of two of them is one fused product (dot).
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

// floor(x * c / 2^16) for unsigned operands, exact: the top 32 bits of the 48-bit product
// (used by lib/control). On the AVR the eight 8x8 partial products are summed straight into
// the result bytes; byte 0 of the product never carries, so it is not formed.
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
#else
inline uint32_t mul_hi_u32xu16(uint32_t x, uint16_t c) { return (uint32_t)(((uint64_t)x * c) >> 16); }
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

// --- Unit * Real products: a 32x16 product whose lowest 8x8 partial product is left out.
// mul_q15(x, c) = floor((x c - lo8(x) lo8(c)) / 2^15) and
// dot_q15(a, x, b, y) = floor((a x + b y - lo8(x) lo8(a) - lo8(y) lo8(b)) / 2^15), with lo8
// the unsigned low byte and the result taken mod 2^32. The left-out terms are below 2^16,
// so the result is the exact floor or up to two steps of 2^-23 below it (four for dot); the host
// computes the same formula.
//
// On the AVR the seven remaining 8x8 partial products of the unsigned operands are summed
// into bytes 1-5 of the product: %[t] is byte 1, %[r] bytes 2-5. MUL, unlike MULS/MULSU,
// takes any register, so the compiler need not move the operands into r16-r23. The signs
// are put back afterwards, with the unsigned readings X, C of x, c:
// x c = X C - [c < 0] X 2^16 - [x < 0] C 2^32 (mod 2^48), a branch around each subtraction.
// mul_q15 of constants, at compile time (the same formula)
constexpr int32_t mul_q15_const(int32_t x, int16_t c) {
  return (int32_t)(((int64_t)x * c - (int64_t)(x & 0xFF) * (c & 0xFF)) >> 15);
}
#if defined(__AVR__)
#define WMRA_STR(x) #x
// r0:r1 = byte i of x times byte j of c
#define WMRA_MUL_ASM(x, i, c, j) "mul   %" #i "[" #x "], %" #j "[" #c "]\n\t"
// t:r += r0:r1 at byte 1, 2, 3 or 4 of the product
#define WMRA_ADD_AT1_ASM \
  "add   %[t], r0\n\t"   \
  "adc   %A[r], r1\n\t"  \
  "adc   %B[r], %[z]\n\t" WMRA_CARRY_TO_BYTE4_ASM
#define WMRA_ADD_AT2_ASM \
  "add   %A[r], r0\n\t"  \
  "adc   %B[r], r1\n\t" WMRA_CARRY_TO_BYTE4_ASM
#define WMRA_CARRY_TO_BYTE4_ASM \
  "adc   %C[r], %[z]\n\t"       \
  "adc   %D[r], %[z]\n\t"
#define WMRA_ADD_AT3_ASM \
  "add   %B[r], r0\n\t"  \
  "adc   %C[r], r1\n\t"  \
  "adc   %D[r], %[z]\n\t"
#define WMRA_ADD_AT4_ASM \
  "add   %C[r], r0\n\t"  \
  "adc   %D[r], r1\n\t"
// t:r = X C (bytes 1-5), partial products by byte position @k
#define WMRA_MUL32X16_SET_ASM(x, c)                         \
  WMRA_MUL_ASM(x, C, c, A) "movw  %A[r], r0\n\t" /* @2 */  \
  WMRA_MUL_ASM(x, D, c, B) "movw  %C[r], r0\n\t" /* @4 */  \
  WMRA_MUL_ASM(x, B, c, A) "mov   %[t], r0\n\t"  /* @1 */  \
  "add   %A[r], r1\n\t"                                    \
  "adc   %B[r], %[z]\n\t" WMRA_CARRY_TO_BYTE4_ASM WMRA_MUL32X16_REST_ASM(x, c)
// t:r += the partial products @1 (x0 c1), @2 (x1 c1), @3 (x3 c0, x2 c1)
#define WMRA_MUL32X16_REST_ASM(x, c)               \
  WMRA_MUL_ASM(x, A, c, B) WMRA_ADD_AT1_ASM       \
  WMRA_MUL_ASM(x, B, c, B) WMRA_ADD_AT2_ASM       \
  WMRA_MUL_ASM(x, D, c, A) WMRA_ADD_AT3_ASM       \
  WMRA_MUL_ASM(x, C, c, B) WMRA_ADD_AT3_ASM
// t:r = X A + Y B (bytes 1-5), column by column: each column's products go into its byte
// and the next, and their carries into the byte above, which starts at zero (columns 3 and 4
// are the ADD_AT3 and ADD_AT4 steps, whose carries reach the top byte)
#define WMRA_COLUMN_ASM(lo, hi, carry) \
  "add   " lo ", r0\n\t"               \
  "adc   " hi ", r1\n\t"               \
  "adc   " carry ", %[z]\n\t"
#define WMRA_COLUMN1_ASM WMRA_COLUMN_ASM("%[t]", "%A[r]", "%B[r]")
#define WMRA_COLUMN2_ASM WMRA_COLUMN_ASM("%A[r]", "%B[r]", "%C[r]")
#define WMRA_DOT32X16_ASM(x, a, y, b)                                                  \
  "clr   %B[r]\n\t"                                                                    \
  "clr   %C[r]\n\t"                                                                    \
  "clr   %D[r]\n\t" WMRA_MUL_ASM(x, B, a, A) "mov   %[t], r0\n\t" /* @1 */           \
  "mov   %A[r], r1\n\t" WMRA_MUL_ASM(x, A, a, B) WMRA_COLUMN1_ASM                     \
  WMRA_MUL_ASM(y, B, b, A) WMRA_COLUMN1_ASM WMRA_MUL_ASM(y, A, b, B) WMRA_COLUMN1_ASM \
  WMRA_MUL_ASM(x, C, a, A) WMRA_COLUMN2_ASM /* @2 */                                 \
  WMRA_MUL_ASM(x, B, a, B) WMRA_COLUMN2_ASM WMRA_MUL_ASM(y, C, b, A) WMRA_COLUMN2_ASM \
  WMRA_MUL_ASM(y, B, b, B) WMRA_COLUMN2_ASM                                            \
  WMRA_MUL_ASM(x, D, a, A) WMRA_ADD_AT3_ASM /* @3 */                                 \
  WMRA_MUL_ASM(x, C, a, B) WMRA_ADD_AT3_ASM WMRA_MUL_ASM(y, D, b, A) WMRA_ADD_AT3_ASM \
  WMRA_MUL_ASM(y, C, b, B) WMRA_ADD_AT3_ASM                                            \
  WMRA_MUL_ASM(x, D, a, B) WMRA_ADD_AT4_ASM /* @4 */                                 \
  WMRA_MUL_ASM(y, D, b, B) WMRA_ADD_AT4_ASM
// - [x < 0] C 2^32
#define WMRA_REAL_SIGN_ASM(x, c, label)                              \
  "sbrs  %D[" #x "], 7\n\t"                                         \
  "rjmp  " WMRA_STR(label) "f\n\t"                                  \
  "sub   %C[r], %A[" #c "]\n\t"                                     \
  "sbc   %D[r], %B[" #c "]\n" WMRA_STR(label) ":\n\t"
// - [c < 0] X 2^16 - [x < 0] C 2^32
#define WMRA_SIGNS32X16_ASM(x, c, label_c, label_x)                  \
  "sbrs  %B[" #c "], 7\n\t"                                         \
  "rjmp  " WMRA_STR(label_c) "f\n\t"                                \
  "sub   %A[r], %A[" #x "]\n\t"                                     \
  "sbc   %B[r], %B[" #x "]\n\t"                                     \
  "sbc   %C[r], %C[" #x "]\n\t"                                     \
  "sbc   %D[r], %D[" #x "]\n" WMRA_STR(label_c) ":\n\t" WMRA_REAL_SIGN_ASM(x, c, label_x)
// r = bits 15-46 of the product: one left shift of bytes 1-5
#define WMRA_SHIFT_Q15_ASM \
  "lsl   %[t]\n\t"         \
  "rol   %A[r]\n\t"        \
  "rol   %B[r]\n\t"        \
  "rol   %C[r]\n\t"        \
  "rol   %D[r]"

inline int32_t mul_q15(int32_t x, int16_t c) {
  int32_t r;
  uint8_t t, z;
  asm("clr   %[z]\n\t" WMRA_MUL32X16_SET_ASM(x, c) "clr   __zero_reg__\n\t" WMRA_SIGNS32X16_ASM(x, c, 1, 2)
          WMRA_SHIFT_Q15_ASM
      : [r] "=&r"(r), [t] "=&r"(t), [z] "=&r"(z)
      : [x] "r"(x), [c] "r"(c));
  return r;
}
// floor of the same product / 2^16: bytes 2-5 as they are, without mul_q15's final shift
// (equal to mul_q15(x, c) >> 1; joint_map.h's scales with a negative exponent use it)
inline int32_t mul_q16(int32_t x, int16_t c) {
  int32_t r;
  uint8_t t, z;
  asm("clr   %[z]\n\t" WMRA_MUL32X16_SET_ASM(x, c) "clr   __zero_reg__\n\t" WMRA_SIGNS32X16_ASM(x, c, 1, 2)
      : [r] "=&r"(r), [t] "=&r"(t), [z] "=&r"(z)
      : [x] "r"(x), [c] "r"(c));
  return r;
}
inline int32_t dot_q15(int16_t a, int32_t x, int16_t b, int32_t y) {
  int32_t r;
  uint8_t t, z;
  asm("clr   %[z]\n\t" WMRA_DOT32X16_ASM(x, a, y, b) "clr   __zero_reg__\n\t"
          WMRA_SIGNS32X16_ASM(x, a, 1, 2) WMRA_SIGNS32X16_ASM(y, b, 3, 4) WMRA_SHIFT_Q15_ASM
      : [r] "=&r"(r), [t] "=&r"(t), [z] "=&r"(z)
      : [a] "r"(a), [x] "r"(x), [b] "r"(b), [y] "r"(y));
  return r;
}
#else
// x c less the product of the low bytes (see above)
inline int64_t product_without_low_bytes(int32_t x, int32_t c) {
  return (int64_t)x * c - (int64_t)(x & 0xFF) * (c & 0xFF);
}
inline int32_t mul_q15(int32_t x, int16_t c) { return (int32_t)(product_without_low_bytes(x, c) >> 15); }
inline int32_t mul_q16(int32_t x, int16_t c) { return (int32_t)(product_without_low_bytes(x, c) >> 16); }
inline int32_t dot_q15(int16_t a, int32_t x, int16_t b, int32_t y) {
  return (int32_t)((product_without_low_bytes(x, a) + product_without_low_bytes(y, b)) >> 15);
}
#endif
inline Real dot(Unit a, Real x, Unit b, Real y) { return Real{dot_q15(a.raw, x.raw, b.raw, y.raw)}; }

// Unit * Real: Q15 * Q23 = Q38, >>15 gives Q23.
inline Real operator*(Unit u, Real r) { return Real{mul_q15(r.raw, u.raw)}; }
inline Real operator*(Real r, Unit u) { return u * r; }

inline Real to_real(Unit u) { return Real{(int32_t)u.raw << 8}; }

// Real -> Unit for values known to lie in (-1, 1) (distances within 1 m, fractions), rounded;
// saturates instead of wrapping.
inline Unit to_unit(Real r) {
  if (r.raw >= (kUnitOne << 8) - 0x80) return Unit{(int16_t)kUnitOne};
  if (r.raw <= -(kUnitOne << 8)) return Unit{(int16_t)-kUnitOne};
  return Unit{(int16_t)((r.raw + 0x80) >> 8)};
}

// --- Span: Q31 metres in (-1, 1), a Unit * Length product (Q15 * UQ16, exact) or a sum of
// such products and Lengths along one link chain; the arm's chains stay below 1 m
// (arm_model.h). A Span joins Real arithmetic as Q23, floor(s / 2^8).
struct Span {
  int32_t raw;
};
inline Span operator*(Unit u, Length l) { return Span{mul_us(l.raw, u.raw)}; }
inline Span operator+(Span a, Span b) { return Span{a.raw + b.raw}; }
inline Span operator+(Length a, Span b) { return Span{(int32_t)((uint32_t)a.raw << 15) + b.raw}; }
inline Real to_real(Span s) { return Real{s.raw >> 8}; }
inline Real operator+(Span a, Real b) { return to_real(a) + b; }
inline Real operator-(Real a, Span b) { return a - to_real(b); }
inline Span operator-(Span a) { return Span{-a.raw}; }
inline Real operator*(Unit u, Span s) { return u * to_real(s); }

// Span -> Unit, rounded: (s + 2^15) >> 16, saturated at +-32767.
#if defined(__AVR__)
// Bytes 2-3 of s plus bit 15; the carry out of the top (V) saturates.
inline Unit to_unit(Span s) {
  int16_t q;
  uint8_t t, z;
  asm("clr   %[z]\n\t"
      "mov   %[t], %B[s]\n\t"
      "lsl   %[t]\n\t"  // bit 15 rounds up
      "movw  %A[q], %C[s]\n\t"
      "adc   %A[q], %[z]\n\t"
      "adc   %B[q], %[z]\n\t"
      "brvc  1f\n\t"
      "ldi   %A[q], 0xFF\n\t"  // 0x7FFF + 1 overflowed
      "ldi   %B[q], 0x7F\n"
      "1:\n\t"
      "cpi   %B[q], 0x80\n\t"  // -32768 -> -32767
      "cpc   %A[q], %[z]\n\t"
      "brne  2f\n\t"
      "ldi   %A[q], 0x01\n"
      "2:"
      : [q] "=&d"(q), [t] "=&r"(t), [z] "=&r"(z)
      : [s] "r"(s.raw));
  return Unit{q};
}
#else
inline Unit to_unit(Span s) {
  const int64_t q = ((int64_t)s.raw + 32768) >> 16;
  return Unit{(int16_t)(q > kUnitOne ? kUnitOne : q < -kUnitOne ? -kUnitOne : q)};
}
#endif

}  // namespace fx
}  // namespace wmra
