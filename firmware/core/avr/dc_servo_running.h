// DcServo::update_running: DcServo::update_portable's common run (every second tick, not parked,
// the PID) in AVR assembly, tied to DcServo's layout by the offsetof checks below. It is the
// firmware's one hand-written fast path: the C of update_portable (dc_servo.h) is its
// specification, and test/avr/kinematics/fixed_products_avr.cpp checks on the chip that both give the same
// duty and state for the same inputs. Its gain, measured with armsim on scenarios/demo.txt,
// moves-to-a-pose.txt and profile.txt against the C path at -O3: about 200 cycles per control
// iteration (CPU load 1.1 to 1.4 points lower), the worst iteration unchanged; it stays while
// The CPU gate (docs/performance.md) under the worst load needs it.
// Included by dc_servo.h on the AVR only.
#pragma once

#include <stddef.h>

namespace wmra {
namespace core {
// --- update_running: update_portable's common run in AVR asm (ticks 2, not parked, the PID)
// avr-gcc's update kept ~20 values live through the PID's terms and sums: 18 registers pushed,
// `this` and the terms spilled to the stack. Here three asm stages, each reaching the servo's
// and the PID's fields through Z (this), pass their few values in registers:
//   front   e = reference - reading (saturated), still / direction / park in f, the integral
//           dropped when the reference stops, the holding effort's substitution (t), the
//           in-band count, the breakaway's flag;
//   terms   the reading's change (the D term's, per tick), P and the integral's step (di), t =
//           feedforward - D (Q15, 32 bits), as Pid::update_effort forms them for two ticks;
//   settle  the effort's limits, the conditional integration, the rounded clamped effort, the
//           remembered integral, then the duty (duty_for still, duty_moving moving) and applied_.
// Bit-identical to update_portable (test/avr/kinematics/fixed_products_avr.cpp: on the chip, random and
// edge vectors, every branch counted). A park leaves the front with f's bit 7 and the rest to C.
// r1 is the zero register outside the products (each clears it after); k their zero byte.

// r = a b, signed: fixed_point.h's mul_ss on bytes (a, b in r16-r23; rc the even one of r's top pair)
#define WMRA_DC_MUL_SS(ra, rb, rc, rd, al, ah, bl, bh)                                           \
  "clr   %[k]\n\t"                                                                               \
  "muls  " ah ", " bh "\n\t"                                                                     \
  "movw  " rc ", r0\n\t"                                                                         \
  "mul   " al ", " bl "\n\t"                                                                     \
  "movw  " ra ", r0\n\t"                                                                         \
  "mulsu " ah ", " bl "\n\t"                                                                     \
  "sbc   " rd ", %[k]\n\t"                                                                       \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "mulsu " bh ", " al "\n\t"                                                                     \
  "sbc   " rd ", %[k]\n\t"                                                                       \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "clr   __zero_reg__\n\t"
// r = a b, a unsigned, b signed: mul_us
#define WMRA_DC_MUL_US(ra, rb, rc, rd, al, ah, bl, bh)                                           \
  "clr   %[k]\n\t"                                                                               \
  "mulsu " bh ", " ah "\n\t"                                                                     \
  "movw  " rc ", r0\n\t"                                                                         \
  "mul   " al ", " bl "\n\t"                                                                     \
  "movw  " ra ", r0\n\t"                                                                         \
  "mulsu " bh ", " al "\n\t"                                                                     \
  "sbc   " rd ", %[k]\n\t"                                                                       \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "mul   " ah ", " bl "\n\t"                                                                     \
  "add   " rb ", r0\n\t"                                                                         \
  "adc   " rc ", r1\n\t"                                                                         \
  "adc   " rd ", %[k]\n\t"                                                                       \
  "clr   __zero_reg__\n\t"
// -x of a 16-bit register pair
#define WMRA_DC_NEG16(x) "neg   %B[" x "]\n\t" "neg   %A[" x "]\n\t" "sbc   %B[" x "], __zero_reg__\n\t"
// x = Pid::towards(effort_, the bound at Z+bound, rate_twice_); y the bound, m the step
#define WMRA_DC_TOWARDS(bound)                                                                   \
  "ldd   %A[x], Z+%[o_ef]\n\t"                                                                   \
  "ldd   %B[x], Z+%[o_ef]+1\n\t"                                                                 \
  "ldd   %A[y], Z+" bound "\n\t"                                                                 \
  "ldd   %B[y], Z+" bound "+1\n\t"                                                               \
  "ldd   %A[m], Z+%[o_rt]\n\t"                                                                   \
  "ldd   %B[m], Z+%[o_rt]+1\n\t"                                                                 \
  "sub   %A[x], %A[y]\n\t"                   /* from - to (its flags: from < to?) */            \
  "sbc   %B[x], %B[y]\n\t"                                                                       \
  "brlt  72f\n\t"                                                                                \
  "cp    %A[m], %A[x]\n\t"                   /* from >= to: the step below from - to? */        \
  "cpc   %B[m], %B[x]\n\t"                                                                       \
  "brlo  71f\n\t"                                                                                \
  "movw  %A[x], %A[y]\n\t"                   /* within the step: the bound */                   \
  "rjmp  74f\n"                                                                                  \
  "71:\n\t"                                                                                      \
  "sub   %A[x], %A[m]\n\t"                   /* (from - to) - step + to */                      \
  "sbc   %B[x], %B[m]\n\t"                                                                       \
  "add   %A[x], %A[y]\n\t"                                                                       \
  "adc   %B[x], %B[y]\n\t"                                                                       \
  "rjmp  74f\n"                                                                                  \
  "72:\n\t"                                                                                      \
  WMRA_DC_NEG16("x")                         /* to - from */                                    \
  "cp    %A[m], %A[x]\n\t"                                                                       \
  "cpc   %B[m], %B[x]\n\t"                                                                       \
  "brlo  73f\n\t"                                                                                \
  "movw  %A[x], %A[y]\n\t"                                                                       \
  "rjmp  74f\n"                                                                                  \
  "73:\n\t"                                                                                      \
  "sub   %A[m], %A[x]\n\t"                   /* step - (to - from) + to */                      \
  "sbc   %B[m], %B[x]\n\t"                                                                       \
  "add   %A[m], %A[y]\n\t"                                                                       \
  "adc   %B[m], %B[y]\n\t"                                                                       \
  "movw  %A[x], %A[m]\n"                                                                         \
  "74:\n\t"

inline __attribute__((always_inline)) int16_t DcServo::update_running(int16_t reference_units, int16_t measured_units,
                                                                      int16_t feedforward_q15, int16_t holding_q15) {
  constexpr control::Pid::Layout l = control::Pid::layout();
  static_assert(offsetof(DcServo, pid_) == 0, "the PID's fields at their own offsets");
  constexpr uint8_t kTail = 20;  // settle's duty reaches its fields from Z + kTail
  static_assert(l.min_duty >= kTail && offsetof(DcServo, moving_slope_q15_) + 1 - kTail <= 63 &&
                    offsetof(DcServo, broke_away_) <= 63 && offsetof(DcServo, start_units_) + 1 <= 63 &&
                    offsetof(DcServo, park_ticks_) + 1 <= 63 && offsetof(DcServo, holding_q15_) + 3 <= 63 &&
                    l.integral_limit + 3 <= 63,
                "update_running's fields within ldd's displacement (of Z, or of Z + kTail)");
  static_assert(l.bottom == l.top + 2, "the effort's bounds together");

  // front. e: the error; t: the feedforward (then the holding effort's), sign-extended; x: the
  // holding effort, then scratch; f: bit 0 still, bit 1 moving negative, bit 7 park
  int16_t e = reference_units, x = holding_q15, y;
  int32_t t = feedforward_q15;
  uint8_t f;
  asm volatile(
      "sub   %A[e], %A[m]\n\t"
      "sbc   %B[e], %B[m]\n\t"
      "brvc  1f\n\t"
      "sbrs  %B[e], 7\n\t"                // overflowed: the true sign is the result's inverse
      "rjmp  2f\n\t"
      "ldi   %A[e], 0xFF\n\t"
      "ldi   %B[e], 0x7F\n\t"
      "rjmp  3f\n"
      "2:\n\t"
      "ldi   %A[e], 0x01\n\t"
      "ldi   %B[e], 0x80\n\t"
      "rjmp  3f\n"
      "1:\n\t"
      "tst   %A[e]\n\t"                   // -32768 saturates to -32767
      "brne  3f\n\t"
      "cpi   %B[e], 0x80\n\t"
      "brne  3f\n\t"
      "inc   %A[e]\n"
      "3:\n\t"
      "clr   %[f]\n\t"
      "sbrc  %B[t], 7\n\t"
      "ldi   %[f], 2\n\t"                 // the motion's direction: the feedforward's, before the holding's
      "ldd   %A[y], Z+%[o_zb]\n\t"        // still: -zero band < feedforward < zero band
      "ldd   %B[y], Z+%[o_zb]+1\n\t"
      "cp    %A[t], %A[y]\n\t"
      "cpc   %B[t], %B[y]\n\t"
      "brge  4f\n\t"
      WMRA_DC_NEG16("y")
      "cp    %A[y], %A[t]\n\t"
      "cpc   %B[y], %B[t]\n\t"
      "brge  4f\n\t"
      "ori   %[f], 1\n\t"
      "ldd   __tmp_reg__, Z+%[o_ws]\n\t"
      "tst   __tmp_reg__\n\t"
      "brne  5f\n\t"
      "std   Z+%[o_i], __zero_reg__\n\t"  // the reference stopped: the moving effort's integral dropped
      "std   Z+%[o_i]+1, __zero_reg__\n\t"
      "std   Z+%[o_i]+2, __zero_reg__\n\t"
      "std   Z+%[o_i]+3, __zero_reg__\n\t"
      "inc   __tmp_reg__\n\t"
      "std   Z+%[o_ws], __tmp_reg__\n"
      "5:\n\t"
      "cp    %A[e], __zero_reg__\n\t"     // ahead (e != 0) the way the holding effort pushes: it
      "cpc   %B[e], __zero_reg__\n\t"     // is the feedforward (e > 0 with h > 0, e < 0 with h <= 0)
      "breq  6f\n\t"
      "sbrc  %B[e], 7\n\t"
      "rjmp  7f\n\t"
      "cp    __zero_reg__, %A[x]\n\t"
      "cpc   __zero_reg__, %B[x]\n\t"
      "brge  6f\n\t"
      "rjmp  8f\n"
      "7:\n\t"
      "cp    __zero_reg__, %A[x]\n\t"
      "cpc   __zero_reg__, %B[x]\n\t"
      "brlt  6f\n"
      "8:\n\t"
      "movw  %A[t], %A[x]\n\t"
      "clr   %C[t]\n\t"
      "sbrc  %B[t], 7\n\t"
      "com   %C[t]\n\t"
      "mov   %D[t], %C[t]\n"
      "6:\n\t"
      "movw  %A[y], %A[e]\n\t"            // |e| within the park band: counted in
      "sbrs  %B[e], 7\n\t"
      "rjmp  9f\n\t"
      WMRA_DC_NEG16("y")
      "9:\n\t"
      "ldd   %A[x], Z+%[o_pu]\n\t"
      "ldd   %B[x], Z+%[o_pu]+1\n\t"
      "cp    %A[x], %A[y]\n\t"
      "cpc   %B[x], %B[y]\n\t"
      "brlo  10f\n\t"
      "ldd   %A[x], Z+%[o_ib]\n\t"
      "ldd   %B[x], Z+%[o_ib]+1\n\t"
      "subi  %A[x], 0xFE\n\t"             // + 2 ticks
      "sbci  %B[x], 0xFF\n\t"
      "rjmp  11f\n"
      "4:\n\t"
      "std   Z+%[o_ws], __zero_reg__\n"   // moving
      "10:\n\t"
      "clr   %A[x]\n\t"
      "clr   %B[x]\n"
      "11:\n\t"
      "std   Z+%[o_ib], %A[x]\n\t"
      "std   Z+%[o_ib]+1, %B[x]\n\t"
      "ldd   %A[y], Z+%[o_pt]\n\t"
      "ldd   %B[y], Z+%[o_pt]+1\n\t"
      "cp    %A[x], %A[y]\n\t"
      "cpc   %B[x], %B[y]\n\t"
      "brlo  12f\n\t"
      "ori   %[f], 0x80\n\t"              // park: C's (e and the reading as they came)
      "rjmp  13f\n"
      "12:\n\t"
      "ldd   __tmp_reg__, Z+%[o_ba]\n\t"  // not yet broken away: the reading past the band its way?
      "tst   __tmp_reg__\n\t"
      "brne  13f\n\t"
      "ldd   %A[y], Z+%[o_su]\n\t"
      "ldd   %B[y], Z+%[o_su]+1\n\t"
      "sbrc  %[f], 1\n\t"
      "rjmp  14f\n\t"
      "movw  %A[x], %A[m]\n\t"            // reading - start > park band (int: 16 bits)
      "sub   %A[x], %A[y]\n\t"
      "sbc   %B[x], %B[y]\n\t"
      "ldd   %A[y], Z+%[o_pu]\n\t"
      "ldd   %B[y], Z+%[o_pu]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brge  13f\n\t"
      "rjmp  15f\n"
      "14:\n\t"
      "sub   %A[y], %A[m]\n\t"            // start - reading > park band
      "sbc   %B[y], %B[m]\n\t"
      "ldd   %A[x], Z+%[o_pu]\n\t"
      "ldd   %B[x], Z+%[o_pu]+1\n\t"
      "cp    %A[x], %A[y]\n\t"
      "cpc   %B[x], %B[y]\n\t"
      "brge  13f\n"
      "15:\n\t"
      "clr   __tmp_reg__\n\t"
      "inc   __tmp_reg__\n\t"
      "std   Z+%[o_ba], __tmp_reg__\n"
      "13:"
      : [e] "+d"(e), [t] "+r"(t), [x] "+d"(x), [y] "=&r"(y), [f] "=&d"(f)
      : [m] "r"(measured_units), "z"(this), [o_zb] "I"(l.zero_band), [o_ws] "I"(offsetof(DcServo, was_still_)),
        [o_i] "I"(l.integral), [o_pu] "I"(offsetof(DcServo, park_units_)), [o_ib] "I"(offsetof(DcServo, in_band_)),
        [o_pt] "I"(offsetof(DcServo, park_ticks_)), [o_ba] "I"(offsetof(DcServo, broke_away_)),
        [o_su] "I"(offsetof(DcServo, start_units_))
      : "memory");
  if (f & 0x80) return stop(e, measured_units);

  // terms: m the reading, then its change per tick; p P (Q23), di the integral's step (Q23),
  // t feedforward - D (Q15); x |e|, then |dm|, then with e D's product; y a gain or a limit
  // (the products' operands in r16-r23, where muls and mulsu reach them: named, as avr-gcc's
  // reload does not find three pairs of that class itself)
  register int16_t ea asm("r22") = e;
  register int16_t m asm("r18") = measured_units;
  register int16_t ya asm("r20");
  int32_t p, di;
  uint8_t k;
  asm volatile(
      "ldd   %A[y], Z+%[o_mp]\n\t"
      "ldd   %B[y], Z+%[o_mp]+1\n\t"
      "std   Z+%[o_mp], %A[m]\n\t"
      "std   Z+%[o_mp]+1, %B[m]\n\t"
      "sub   %A[m], %A[y]\n\t"            // the reading's change, saturated, halved (two ticks)
      "sbc   %B[m], %B[y]\n\t"
      "brvc  1f\n\t"
      "sbrs  %B[m], 7\n\t"
      "rjmp  2f\n\t"
      "ldi   %A[m], 0xFF\n\t"
      "ldi   %B[m], 0x7F\n\t"
      "rjmp  1f\n"
      "2:\n\t"
      "ldi   %A[m], 0x01\n\t"             // (-32768 halves as -32767 does: no case of its own)
      "ldi   %B[m], 0x80\n"
      "1:\n\t"
      "asr   %B[m]\n\t"
      "ror   %A[m]\n\t"
      "cp    %A[e], __zero_reg__\n\t"     // e = 0: no P, no integral's step
      "cpc   %B[e], __zero_reg__\n\t"
      "brne  3f\n\t"
      "clr   %A[p]\n\t"
      "clr   %B[p]\n\t"
      "movw  %C[p], %A[p]\n\t"
      "movw  %A[di], %A[p]\n\t"
      "movw  %C[di], %A[p]\n\t"
      "rjmp  20f\n"
      "3:\n\t"
      "movw  %A[x], %A[e]\n\t"
      "sbrs  %B[e], 7\n\t"
      "rjmp  4f\n\t"
      WMRA_DC_NEG16("x")
      "4:\n\t"
      "ldd   %A[y], Z+%[o_pl]\n\t"
      "ldd   %B[y], Z+%[o_pl]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brsh  5f\n\t"
      "clr   %A[p]\n\t"                   // P clamped: +-2^30
      "clr   %B[p]\n\t"
      "clr   %C[p]\n\t"
      "ldi   %[k], 0x40\n\t"
      "sbrc  %B[e], 7\n\t"
      "ldi   %[k], 0xC0\n\t"
      "mov   %D[p], %[k]\n\t"
      "rjmp  6f\n"
      "5:\n\t"
      "ldd   %A[y], Z+%[o_kpx]\n\t"
      "ldd   %B[y], Z+%[o_kpx]+1\n\t"
      "cp    %A[y], __zero_reg__\n\t"
      "cpc   %B[y], __zero_reg__\n\t"
      "breq  7f\n\t"
      WMRA_DC_MUL_US("%A[p]", "%B[p]", "%C[p]", "%D[p]", "%A[y]", "%B[y]", "%A[e]", "%B[e]")  // 16 Kp e
      "rjmp  6f\n"
      "7:\n\t"
      "ldd   %A[y], Z+%[o_kp]\n\t"        // Kp 16 past 16 bits (or Kp 0): e Kp, times 16
      "ldd   %B[y], Z+%[o_kp]+1\n\t"
      WMRA_DC_MUL_SS("%A[p]", "%B[p]", "%C[p]", "%D[p]", "%A[e]", "%B[e]", "%A[y]", "%B[y]")
      "ldi   %[k], 4\n"
      "8:\n\t"
      "lsl   %A[p]\n\t"
      "rol   %B[p]\n\t"
      "rol   %C[p]\n\t"
      "rol   %D[p]\n\t"
      "dec   %[k]\n\t"
      "brne  8b\n"
      "6:\n\t"
      "ldd   %A[y], Z+%[o_ki]\n\t"        // di = e Ki, clamped to the integral's limit past i_error_limit, twice
      "ldd   %B[y], Z+%[o_ki]+1\n\t"
      WMRA_DC_MUL_SS("%A[di]", "%B[di]", "%C[di]", "%D[di]", "%A[e]", "%B[e]", "%A[y]", "%B[y]")
      "ldd   %A[y], Z+%[o_il]\n\t"
      "ldd   %B[y], Z+%[o_il]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brsh  9f\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]\n\t"   // L - di < 0: L
      "cp    __tmp_reg__, %A[di]\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+1\n\t"
      "cpc   __tmp_reg__, %B[di]\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+2\n\t"
      "cpc   __tmp_reg__, %C[di]\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+3\n\t"
      "cpc   __tmp_reg__, %D[di]\n\t"
      "brge  10f\n\t"
      "ldd   %A[di], Z+%[o_l]\n\t"
      "ldd   %B[di], Z+%[o_l]+1\n\t"
      "ldd   %C[di], Z+%[o_l]+2\n\t"
      "ldd   %D[di], Z+%[o_l]+3\n\t"
      "rjmp  9f\n"
      "10:\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]\n\t"   // di + L < 0: -L (|di| <= 2^30: no overflow)
      "add   %A[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+1\n\t"
      "adc   %B[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+2\n\t"
      "adc   %C[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+3\n\t"
      "adc   %D[di], __tmp_reg__\n\t"
      "brpl  11f\n\t"
      "clr   %A[di]\n\t"
      "clr   %B[di]\n\t"
      "movw  %C[di], %A[di]\n"
      "11:\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]\n\t"
      "sub   %A[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+1\n\t"
      "sbc   %B[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+2\n\t"
      "sbc   %C[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_l]+3\n\t"
      "sbc   %D[di], __tmp_reg__\n"
      "9:\n\t"
      "lsl   %A[di]\n\t"
      "rol   %B[di]\n\t"
      "rol   %C[di]\n\t"
      "rol   %D[di]\n"
      "20:\n\t"
      "cp    %A[m], __zero_reg__\n\t"     // t = feedforward - D; dm = 0: no D
      "cpc   %B[m], __zero_reg__\n\t"
      "breq  21f\n\t"
      "movw  %A[x], %A[m]\n\t"
      "sbrs  %B[m], 7\n\t"
      "rjmp  22f\n\t"
      WMRA_DC_NEG16("x")
      "22:\n\t"
      "ldd   %A[y], Z+%[o_dl]\n\t"
      "ldd   %B[y], Z+%[o_dl]+1\n\t"
      "cp    %A[y], %A[x]\n\t"
      "cpc   %B[y], %B[x]\n\t"
      "brsh  23f\n\t"
      "ldi   %[k], 0x40\n\t"              // D clamped: +-2^22
      "sbrc  %B[m], 7\n\t"
      "rjmp  24f\n\t"
      "sub   %C[t], %[k]\n\t"
      "sbc   %D[t], __zero_reg__\n\t"
      "rjmp  21f\n"
      "24:\n\t"
      "add   %C[t], %[k]\n\t"
      "adc   %D[t], __zero_reg__\n\t"
      "rjmp  21f\n"
      "23:\n\t"
      "ldd   %A[y], Z+%[o_kd]\n\t"
      "ldd   %B[y], Z+%[o_kd]+1\n\t"
      WMRA_DC_MUL_SS("%A[x]", "%B[x]", "%A[e]", "%B[e]", "%A[m]", "%B[m]", "%A[y]", "%B[y]")  // D in x (low), e (high)
      "sub   %A[t], %A[x]\n\t"
      "sbc   %B[t], %B[x]\n\t"
      "sbc   %C[t], %A[e]\n\t"
      "sbc   %D[t], %B[e]\n"
      "21:"
      : [e] "+a"(ea), [m] "+a"(m), [t] "+r"(t), [p] "=&r"(p), [di] "=&r"(di), [x] "=&r"(x), [y] "=&a"(ya), [k] "=&d"(k)
      : "z"(this), [o_mp] "I"(l.m_prev), [o_pl] "I"(l.p_error_limit), [o_kpx] "I"(l.kp_x16), [o_kp] "I"(l.kp),
        [o_ki] "I"(l.ki), [o_il] "I"(l.i_error_limit), [o_l] "I"(l.integral_limit), [o_dl] "I"(l.d_change_limit),
        [o_kd] "I"(l.kd)
      : "memory");

  // settle: e hi, then the effort; x lo, then the duty's base; p P + the integral, then the duty's product; di the trial
  // integral, then P + it; y:m scratch (24-bit limit - t), then the duty
  const DcServo* z = this;
  asm volatile(
      WMRA_DC_TOWARDS("%[o_top]")
      "movw  %A[e], %A[x]\n\t"
      WMRA_DC_TOWARDS("%[o_top]+2")  // (bottom_ after top_)
      "mov   %[k], %A[di]\n\t"            // di = 0 (e or Ki 0): the integral held
      "or    %[k], %B[di]\n\t"
      "or    %[k], %C[di]\n\t"
      "or    %[k], %D[di]\n\t"
      "brne  1f\n\t"
      "rjmp  6f\n"
      "1:\n\t"
      "bst   %D[di], 7\n\t"               // T: di < 0, the error's sign
      "ldd   __tmp_reg__, Z+%[o_i]\n\t"   // trial = integral + di (within +-L and |di| <= 2L: no
      "add   %A[di], __tmp_reg__\n\t"     // overflow), clamped on di's side only
      "ldd   __tmp_reg__, Z+%[o_i]+1\n\t"
      "adc   %B[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+2\n\t"
      "adc   %C[di], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+3\n\t"
      "adc   %D[di], __tmp_reg__\n\t"
      "ldd   %A[y], Z+%[o_l]\n\t"         // y:m = L
      "ldd   %B[y], Z+%[o_l]+1\n\t"
      "ldd   %A[m], Z+%[o_l]+2\n\t"
      "ldd   %B[m], Z+%[o_l]+3\n\t"
      "brts  2f\n\t"
      "cp    %A[y], %A[di]\n\t"           // e > 0: L < trial: L
      "cpc   %B[y], %B[di]\n\t"
      "cpc   %A[m], %C[di]\n\t"
      "cpc   %B[m], %D[di]\n\t"
      "brge  3f\n\t"
      "movw  %A[di], %A[y]\n\t"
      "movw  %C[di], %A[m]\n"
      "3:\n\t"
      "add   %A[di], %A[p]\n\t"           // s = P + trial
      "adc   %B[di], %B[p]\n\t"
      "adc   %C[di], %C[p]\n\t"
      "adc   %D[di], %D[p]\n\t"
      "movw  %A[y], %A[e]\n\t"            // hi - t in 24 bits (y, m's low byte): |hi - t| < 2^23
      "clr   %A[m]\n\t"
      "sbrc  %B[e], 7\n\t"
      "com   %A[m]\n\t"
      "sub   %A[y], %A[t]\n\t"
      "sbc   %B[y], %B[t]\n\t"
      "sbc   %A[m], %C[t]\n\t"
      "ldi   %[k], 16\n\t"                // integrate if s <= (hi - t) 256 + 15: s < that + 1
      "cp    %A[di], %[k]\n\t"
      "cpc   %B[di], %A[y]\n\t"
      "cpc   %C[di], %B[y]\n\t"
      "cpc   %D[di], %A[m]\n\t"
      "brlt  5f\n\t"
      "rjmp  6f\n"
      "2:\n\t"
      "add   %A[y], %A[di]\n\t"           // e < 0: trial + L < 0: -L (trial less that sum)
      "adc   %B[y], %B[di]\n\t"
      "adc   %A[m], %C[di]\n\t"
      "adc   %B[m], %D[di]\n\t"
      "brpl  4f\n\t"
      "sub   %A[di], %A[y]\n\t"
      "sbc   %B[di], %B[y]\n\t"
      "sbc   %C[di], %A[m]\n\t"
      "sbc   %D[di], %B[m]\n"
      "4:\n\t"
      "add   %A[di], %A[p]\n\t"           // s = P + trial
      "adc   %B[di], %B[p]\n\t"
      "adc   %C[di], %C[p]\n\t"
      "adc   %D[di], %D[p]\n\t"
      "movw  %A[y], %A[x]\n\t"            // lo - t in 24 bits
      "clr   %A[m]\n\t"
      "sbrc  %B[x], 7\n\t"
      "com   %A[m]\n\t"
      "sub   %A[y], %A[t]\n\t"
      "sbc   %B[y], %B[t]\n\t"
      "sbc   %A[m], %C[t]\n\t"
      "cp    %B[di], %A[y]\n\t"           // integrate if s >= (lo - t) 256 (s's low byte against
      "cpc   %C[di], %B[y]\n\t"           // 0 borrows nothing)
      "cpc   %D[di], %A[m]\n\t"
      "brlt  6f\n"
      "5:\n\t"
      "sub   %A[di], %A[p]\n\t"           // integrate: the trial (s - P) stored, the sum is s
      "sbc   %B[di], %B[p]\n\t"
      "sbc   %C[di], %C[p]\n\t"
      "sbc   %D[di], %D[p]\n\t"
      "std   Z+%[o_i], %A[di]\n\t"
      "std   Z+%[o_i]+1, %B[di]\n\t"
      "std   Z+%[o_i]+2, %C[di]\n\t"
      "std   Z+%[o_i]+3, %D[di]\n\t"
      "add   %A[p], %A[di]\n\t"
      "adc   %B[p], %B[di]\n\t"
      "adc   %C[p], %C[di]\n\t"
      "adc   %D[p], %D[di]\n\t"
      "rjmp  7f\n"
      "6:\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]\n\t"   // held: the sum with the integral as it is
      "add   %A[p], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+1\n\t"
      "adc   %B[p], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+2\n\t"
      "adc   %C[p], __tmp_reg__\n\t"
      "ldd   __tmp_reg__, Z+%[o_i]+3\n\t"
      "adc   %D[p], __tmp_reg__\n"
      "7:\n\t"
      "lsl   %A[p]\n\t"                   // floor((sum + 128) / 256): bit 7 rounds up; |.| < 2^23,
      "adc   %B[p], __zero_reg__\n\t"     // in bytes B..D
      "adc   %C[p], __zero_reg__\n\t"
      "adc   %D[p], __zero_reg__\n\t"
      "clr   %[k]\n\t"                    // u = that + t (|u| < 2^24)
      "sbrc  %D[p], 7\n\t"
      "com   %[k]\n\t"
      "add   %A[t], %B[p]\n\t"
      "adc   %B[t], %C[p]\n\t"
      "adc   %C[t], %D[p]\n\t"
      "adc   %D[t], %[k]\n\t"
      "clr   %[k]\n\t"                    // u > hi: hi
      "sbrc  %B[e], 7\n\t"
      "com   %[k]\n\t"
      "cp    %A[e], %A[t]\n\t"
      "cpc   %B[e], %B[t]\n\t"
      "cpc   %[k], %C[t]\n\t"
      "cpc   %[k], %D[t]\n\t"
      "brlt  8f\n\t"
      "clr   %[k]\n\t"                    // u < lo: lo; else u
      "sbrc  %B[x], 7\n\t"
      "com   %[k]\n\t"
      "movw  %A[e], %A[x]\n\t"
      "cp    %A[t], %A[x]\n\t"
      "cpc   %B[t], %B[x]\n\t"
      "cpc   %C[t], %[k]\n\t"
      "cpc   %D[t], %[k]\n\t"
      "brlt  8f\n\t"
      "movw  %A[e], %A[t]\n"
      "8:\n\t"
      "std   Z+%[o_ef], %A[e]\n\t"
      "std   Z+%[o_ef]+1, %B[e]\n\t"
      "sbrc  %[f], 0\n\t"                 // moving: the integral's effort remembered its way
      "rjmp  9f\n\t"
      "ldd   %A[y], Z+%[o_i]+1\n\t"
      "ldd   %B[y], Z+%[o_i]+2\n\t"
      "sbrc  %[f], 1\n\t"
      "rjmp  10f\n\t"
      "std   Z+%[o_h], %A[y]\n\t"
      "std   Z+%[o_h]+1, %B[y]\n\t"
      "rjmp  9f\n"
      "10:\n\t"
      "std   Z+%[o_h]+2, %A[y]\n\t"
      "std   Z+%[o_h]+3, %B[y]\n"
      "9:\n\t"
      "adiw  r30, %[tail]\n\t"
      "sbrs  %[f], 0\n\t"
      "rjmp  13f\n\t"
      "movw  %A[y], %A[e]\n\t"            // still: the dead-zone inverse (duty_for) of a = |effort|
      "sbrs  %B[e], 7\n\t"
      "rjmp  11f\n\t"
      WMRA_DC_NEG16("y")
      "11:\n\t"
      "ldd   %A[m], Z+%[o_zb]\n\t"        // a = 0 or within the zero band: 0
      "ldd   %B[m], Z+%[o_zb]+1\n\t"
      "cp    %A[y], __zero_reg__\n\t"
      "cpc   %B[y], __zero_reg__\n\t"
      "breq  12f\n\t"
      "cp    %A[y], %A[m]\n\t"
      "cpc   %B[y], %B[m]\n\t"
      "brlo  12f\n\t"
      "ldd   %A[m], Z+%[o_sl]\n\t"        // min_duty + (slope a)'s bits 15..30
      "ldd   %B[m], Z+%[o_sl]+1\n\t"
      "ldd   %A[x], Z+%[o_md]\n\t"
      "ldd   %B[x], Z+%[o_md]+1\n\t"
      "rjmp  14f\n"
      "12:\n\t"
      "clr   %A[y]\n\t"
      "clr   %B[y]\n\t"
      "rjmp  16f\n"
      "13:\n\t"
      "movw  %A[y], %A[e]\n\t"            // moving: a = the effort the motion's way (duty_moving)
      "sbrs  %[f], 1\n\t"
      "rjmp  15f\n\t"
      WMRA_DC_NEG16("y")
      "15:\n\t"
      "ldd   __tmp_reg__, Z+%[o_ba]\n\t"  // not broken away, past the load's effort, below the
      "tst   __tmp_reg__\n\t"             // breakaway's: the breakaway's
      "brne  17f\n\t"
      "ldd   %A[m], Z+%[o_lift]\n\t"
      "ldd   %B[m], Z+%[o_lift]+1\n\t"
      "cp    %A[m], %A[y]\n\t"
      "cpc   %B[m], %B[y]\n\t"
      "brge  17f\n\t"
      "ldd   %A[m], Z+%[o_bre]\n\t"
      "ldd   %B[m], Z+%[o_bre]+1\n\t"
      "cp    %A[y], %A[m]\n\t"
      "cpc   %B[y], %B[m]\n\t"
      "brge  17f\n\t"
      "movw  %A[y], %A[m]\n"
      "17:\n\t"
      "ldd   %A[m], Z+%[o_ms]\n\t"        // friction + (moving slope a)'s bits 15..30
      "ldd   %B[m], Z+%[o_ms]+1\n\t"
      "ldd   %A[x], Z+%[o_fr]\n\t"
      "ldd   %B[x], Z+%[o_fr]+1\n"
      "14:\n\t"
      WMRA_DC_MUL_US("%A[p]", "%B[p]", "%C[p]", "%D[p]", "%A[m]", "%B[m]", "%A[y]", "%B[y]")
      "lsl   %B[p]\n\t"
      "rol   %C[p]\n\t"
      "rol   %D[p]\n\t"
      "movw  %A[y], %A[x]\n\t"
      "add   %A[y], %C[p]\n\t"
      "adc   %B[y], %D[p]\n\t"
      "sbrc  %[f], 0\n\t"                 // the sign: the effort's (still), the motion's (moving)
      "rjmp  18f\n\t"
      "sbrc  %[f], 1\n\t"
      "rjmp  19f\n\t"
      "rjmp  16f\n"
      "18:\n\t"
      "sbrs  %B[e], 7\n\t"
      "rjmp  16f\n"
      "19:\n\t"
      WMRA_DC_NEG16("y")
      "16:\n\t"
      "std   Z+%[o_ap], %A[y]\n\t"
      "std   Z+%[o_ap]+1, %B[y]\n\t"
      : [p] "+r"(p), [di] "+r"(di), [t] "+r"(t), [e] "=&r"(e), [x] "=&r"(x), [y] "=&a"(ya), [m] "=&a"(m), [k] "=&d"(k),
        "+z"(z)
      : [f] "r"(f), [tail] "I"(kTail), [o_ef] "I"(l.effort), [o_top] "I"(l.top), [o_rt] "I"(l.rate_twice),
        [o_i] "I"(l.integral), [o_l] "I"(l.integral_limit), [o_h] "I"(offsetof(DcServo, holding_q15_)),
        [o_md] "I"(l.min_duty - kTail), [o_zb] "I"(l.zero_band - kTail), [o_sl] "I"(l.slope - kTail),
        [o_ap] "I"(offsetof(DcServo, applied_) - kTail), [o_lift] "I"(offsetof(DcServo, lift_q15_) - kTail),
        [o_bre] "I"(offsetof(DcServo, breakaway_effort_q15_) - kTail), [o_fr] "I"(offsetof(DcServo, moving_friction_q15_) - kTail),
        [o_ms] "I"(offsetof(DcServo, moving_slope_q15_) - kTail), [o_ba] "I"(offsetof(DcServo, broke_away_) - kTail)
      : "memory");
  return ya;
}
#undef WMRA_DC_MUL_SS
#undef WMRA_DC_MUL_US
#undef WMRA_DC_NEG16
#undef WMRA_DC_TOWARDS

}  // namespace core
}  // namespace wmra
