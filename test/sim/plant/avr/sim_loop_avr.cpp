// A control loop as the firmware will run it: a 1 kHz tick from Timer1 (fast PWM, TOP = ICR1,
// its overflow interrupt), sleep (idle) until the tick, then D49 high for a known busy time
// (4,000 cycles) and low again. Timer1 also drives the gripper's pin (OC1C, D13) with a 500 us
// pulse each period. Timer2 overflows into
// a naked handler that is a bare RETI (3 + 5 cycles from its vector, plus the 5-cycle response).
// A function with a 200-byte frame marks the stack's depth.
#include <avr/sleep.h>
#include <util/delay_basic.h>

#include "board_io.h"

using namespace wmra;

namespace {
volatile bool tick;

__attribute__((noinline)) uint8_t deep_frame(uint8_t seed) {
  volatile uint8_t buffer[200];
  for (uint8_t i = 0; i < sizeof buffer; ++i) buffer[i] = (uint8_t)(seed + i);
  return buffer[seed % sizeof buffer];
}
}  // namespace

ISR(TIMER1_OVF_vect) { tick = true; }
ISR(TIMER2_OVF_vect, ISR_NAKED) { reti(); }

int main() {
  io::output(board::kTimingProbe);
  ICR1 = 1999;  // 1 kHz at /8
  OCR1C = 999;  // high for 1,000 of 2,000 counts: 500 us
  io::output(board::kGripperServo.pin);
  TCCR1A = (1 << COM1C1) | (1 << WGM11);
  TCCR1B = (1 << WGM13) | (1 << WGM12) | (1 << CS11);
  TIMSK1 = 1 << TOIE1;
  TCCR2B = 1 << CS22;  // /64: overflow every 1,024 us
  TIMSK2 = 1 << TOIE2;
  set_sleep_mode(SLEEP_MODE_IDLE);
  sei();
  uint8_t x = deep_frame(3);
  for (;;) {
    while (!tick) {
      sleep_enable();
      sleep_cpu();
      sleep_disable();
    }
    tick = false;
    PORTL |= 1;
    _delay_loop_2(1000);  // 4,000 cycles
    PORTL &= (uint8_t)~1;
    x ^= 1;
  }
}
