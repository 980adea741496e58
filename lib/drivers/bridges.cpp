#include "drivers/bridges.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "drivers/pins.h"
#include "kinematics/fixed_point.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace bridges {

namespace {

using board::ComparePin;
using board::Timer;

constexpr uint16_t kTop16 = (uint16_t)(board::kCpuHz / kPwmHz - 1);     // prescaler 1
constexpr uint8_t kTop8 = (uint8_t)(board::kCpuHz / 8 / kPwmHz - 1);    // prescaler 8
static_assert(kTop16 == 799 && kTop8 == 99, "20 kHz PWM");

constexpr const board::BridgePins& kPins(uint8_t j) {
  return j == 0 ? board::kBridgeJ2 : j == 1 ? board::kBridgeJ3 : board::kBridgeJ4;
}
constexpr bool eight_bit(ComparePin p) { return p.timer == Timer::t0 || p.timer == Timer::t2; }
constexpr uint8_t kComNonInverting = 2;

volatile bool g_off = true;  // all_off() until enable()

// Always inlined with a constant pin: every register address folds to a constant (a runtime
// lookup in the pin tables costs ~250 cycles a call).
// A side switched off: its output disconnected from the timer (what side() does for a duty of 0,
// without the product: the asm multiply does not fold with a constant operand).
__attribute__((always_inline)) inline void side_off(ComparePin p) { pins::set_com(p, 0); }
__attribute__((always_inline)) inline void side(ComparePin p, uint16_t duty_q15) {
  const uint16_t top = eight_bit(p) ? kTop8 : kTop16;
  // duty (top + 1) / 2^15 as the high half of duty 2 (top + 1): one 16 x 16 product
  const uint16_t ocr = fx::hi16(fx::mul_uu(duty_q15, (uint16_t)(2u * (top + 1u))));
  if (ocr == 0) {
    side_off(p);
    return;
  }
  if (eight_bit(p)) {
    pins::ocr8(p) = (uint8_t)ocr;
  } else {
    pins::ocr16(p) = ocr;
  }
  pins::set_com(p, kComNonInverting);
}

template <uint8_t kJoint>
void set_joint(int16_t duty_q15) {
  constexpr const board::BridgePins& b = kPins(kJoint);
  const uint16_t magnitude = duty_q15 < 0 ? (uint16_t)(0u - (uint16_t)duty_q15) : (uint16_t)duty_q15;  // 16-bit negation
  const uint8_t s = SREG;
  cli();  // the e-stop ISR writes the same TCCRnA registers, and g_off
  if (g_off) {
    SREG = s;
    return;
  }
  if (duty_q15 > 0) {
    side_off(b.right);
    side(b.left, magnitude);
  } else {
    side_off(b.left);
    side(b.right, magnitude);
  }
  SREG = s;
}

void start_timer(Timer t) {
  const m2560::TimerRegisters& r = m2560::timer_registers(t);
  if (t == Timer::t0 || t == Timer::t2) {
    pins::reg8(r.tccra) = (1 << WGM01) | (1 << WGM00);  // fast PWM, TOP = OCRA (mode 7)
    pins::reg8(r.ocr[0]) = kTop8;
    pins::reg8(r.tccrb) = (1 << WGM02) | (1 << CS01);   // /8 (same bit positions on Timer2)
  } else {
    pins::reg8(r.tccra) = (1 << WGM31);  // fast PWM, TOP = ICR (mode 14)
    pins::reg16(r.icr) = kTop16;
    pins::reg8(r.tccrb) = (1 << WGM33) | (1 << WGM32) | (1 << CS30);
  }
}

}  // namespace

void start() {
  for (uint8_t j = 0; j < kCount; ++j) {
    pins::write(kPins(j).left.pin, false);
    pins::write(kPins(j).right.pin, false);
    pins::output(kPins(j).left.pin);
    pins::output(kPins(j).right.pin);
  }
  start_timer(Timer::t0);
  start_timer(Timer::t2);
  start_timer(Timer::t3);
  start_timer(Timer::t4);
}

void set(uint8_t joint, int16_t duty_q15) {
  static_assert(kCount == 3, "one case per bridge");
  switch (joint) {
    case 0:
      set_joint<0>(duty_q15);
      break;
    case 1:
      set_joint<1>(duty_q15);
      break;
    case 2:
      set_joint<2>(duty_q15);
      break;
    default:
      break;
  }
}

// From the safety button's interrupt: unrolled into direct register writes (latency, S5)
void all_off() {
  const uint8_t s = SREG;
  cli();
  for (uint8_t j = 0; j < kCount; ++j) {
    pins::set_com(kPins(j).left, 0);
    pins::set_com(kPins(j).right, 0);
  }
  g_off = true;
  SREG = s;
}

void enable() { g_off = false; }

}  // namespace bridges
}  // namespace wmra
