#include "drivers/system_tick.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>

#include "drivers/pins.h"
#include "drivers/watchdog.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace tick {

namespace {
volatile uint8_t g_pending;
volatile uint32_t g_ms;
volatile uint16_t g_pulse_counts;  // 0: off
bool g_pulse_high;                 // OC1C's level after its last toggle
static_assert(board::kGripperServo.timer == board::Timer::t1 && board::kGripperServo.channel == board::Channel::c,
              "the servo pulse is Timer1's compare C");
}  // namespace

void start() {
  TCCR1A = 0;
  TCCR1B = 0;
  TCNT1 = 0;
  OCR1A = kTickCounts;
  pins::output(board::kGripperServo.pin);  // low: COM1C stays off until a pulse is set
  TIFR1 = 0xFF;
  TIMSK1 = (1 << OCIE1A) | (1 << OCIE1C);
  TCCR1B = (1 << CS11);  // normal mode, /8
  set_sleep_mode(SLEEP_MODE_IDLE);
}

void start_phase_compare(uint16_t phase_us) {
  const uint8_t s = SREG;
  cli();
  // compare A holds the next tick's count: this tick's phase, moved on at the next tick
  OCR1B = (uint16_t)(OCR1A - kTickCounts + phase_us * kCountsPerUs);
  TIFR1 = (1 << OCF1B);
  TIMSK1 |= (1 << OCIE1B);
  SREG = s;
}

uint8_t wait() {
  for (;;) {
    cli();
    const uint8_t n = g_pending;
    if (n != 0) {
      g_pending = 0;
      sei();
      return n;
    }
    sleep_enable();
    sei();  // the instruction after sei runs before any interrupt: no tick is lost between
    sleep_cpu();
    sleep_disable();
  }
}

uint32_t now_ms() {
  cli();
  const uint32_t t = g_ms;
  sei();
  return t;
}

void set_servo_pulse_us(uint16_t us) {
  const uint16_t counts = us == 0 ? 0 : (uint16_t)(us < 500 ? 500 : us > 2500 ? 2500 : us) * kCountsPerUs;
  const uint8_t s = SREG;
  cli();
  g_pulse_counts = counts;
  if (counts != 0 && !(TCCR1A & (1 << COM1C0))) {
    OCR1C = (uint16_t)(TCNT1 + kTickCounts);  // the first pulse starts within a millisecond
    g_pulse_high = false;
    TIFR1 = (1 << OCF1C);
    TCCR1A |= (1 << COM1C0);  // toggle on compare
  }
  SREG = s;
}

}  // namespace tick
}  // namespace wmra

using namespace wmra;

ISR(TIMER1_COMPA_vect) {
  OCR1A += tick::kTickCounts;
  OCR1B += tick::kTickCounts;
  tick::g_ms = tick::g_ms + 1;
  const uint8_t pending = tick::g_pending;
  if (pending != 255) tick::g_pending = (uint8_t)(pending + 1);
  // The loop has stalled: entered by a jump, not a call, which would make this ISR save every
  // call-clobbered register on every tick. stalled() never returns, so this frame and the
  // registers it did not save never matter; r1 is cleared for its C code.
  if (pending == watchdog::kStallCut_ms) asm volatile("clr __zero_reg__\n\tjmp %x0" ::"i"(&watchdog::stalled));
}

// OC1C has just toggled. Switched off only after a falling edge, so the compare unit's output
// latch is low whenever it is reconnected; a pulse under way when it was switched off ends
// after the shortest width.
ISR(TIMER1_COMPC_vect) {
  const uint16_t pulse = tick::g_pulse_counts;
  tick::g_pulse_high = !tick::g_pulse_high;
  if (tick::g_pulse_high) {
    OCR1C += pulse != 0 ? pulse : 500 * tick::kCountsPerUs;
  } else if (pulse == 0) {
    TCCR1A &= (uint8_t)~((1 << COM1C1) | (1 << COM1C0));
  } else {
    OCR1C += (uint16_t)(tick::kFrameCounts - pulse);
  }
}
