#include "drivers/steppers.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "drivers/pins.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace steppers {

namespace {

constexpr const board::StepperPins& kPins(uint8_t i) {
  return i == 0 ? board::kStepperJ1 : i == 1 ? board::kStepperJ5 : board::kStepperJ6;
}
constexpr uint8_t com_shift(uint8_t i) { return (uint8_t)m2560::com_shift(kPins(i).step.channel); }
constexpr uint8_t ocie_bit(uint8_t i) { return (uint8_t)(OCIE5A + (uint8_t)kPins(i).step.channel); }
constexpr uint8_t foc_bit(uint8_t i) { return (uint8_t)(FOC5A - (uint8_t)kPins(i).step.channel); }
constexpr uint8_t kComToggle = 1, kComClear = 2;
static_assert(m2560::pin_register(board::kStepperJ1.dir.port) < 0x40 && m2560::pin_register(board::kStepperJ5.dir.port) < 0x40 &&
                  m2560::pin_register(board::kStepperJ6.dir.port) < 0x40,
              "DIR and EN pins on low ports (sbi/cbi: atomic, also in the step ISR)");
// An edge is never scheduled less than this far ahead of the counter (8 us): the ISR's writes
// after computing it take far less, so the compare cannot be passed unseen.
constexpr uint16_t kMinLeadTicks = 2;

Ramp g_ramps[kCount];
volatile uint8_t g_running;  // bit i: channel i has an edge scheduled
volatile bool g_killed = true;

inline void set_com(uint8_t i, uint8_t com) {
  TCCR5A = (uint8_t)((TCCR5A & ~(3 << com_shift(i))) | (com << com_shift(i)));
}

inline void set_dir(uint8_t i, int8_t dir) {
  if (dir > 0) {
    pins::reg8(m2560::port_register(kPins(i).dir.port)) |= (uint8_t)(1 << kPins(i).dir.bit);
  } else {
    pins::reg8(m2560::port_register(kPins(i).dir.port)) &= (uint8_t)~(1 << kPins(i).dir.bit);
  }
}

// The edge `interval` ticks after `from` (the last edge, or now), or kMinLeadTicks from now if
// that is already too close or past. Late is judged by the time elapsed since `from`, not by the
// sign of (edge - now): an interval above 32767 ticks (a step slower than 7.6/s) would look late
// that way and go out at once, a burst of steps at the ISR's rate.
inline void schedule(uint8_t i, uint16_t from, uint16_t interval) {
  const uint16_t elapsed = (uint16_t)(TCNT5 - from);
  const bool late = interval < kMinLeadTicks || elapsed > (uint16_t)(interval - kMinLeadTicks);
  pins::ocr16(kPins(i).step) = late ? (uint16_t)(from + elapsed + kMinLeadTicks) : (uint16_t)(from + interval);
}

// One copy of the ramp's step for the three ISRs and the start (inlined into each, it cost
// ~1.2 KB of flash a copy; the call costs ~10 cycles a step).
__attribute__((noinline)) Ramp::Step next_step(Ramp& ramp) { return ramp.next(); }

// Runs with interrupts off (from the ISR, or from the main loop under cli). The compare unit
// toggles STEP high at the edge; a forced compare toggles it low again. Only OCR5x and TCCR5C
// are written per step: TCCR5A (the compare modes) changes only when a channel starts or stops.
template <uint8_t I>
inline void on_edge() {
  const Ramp::Step s = next_step(g_ramps[I]);
  TCCR5C = (uint8_t)(1 << foc_bit(I));  // the pulse ends now
  if (s.interval_ticks == 0) {
    set_com(I, 0);
    TIMSK5 &= (uint8_t)~(1 << ocie_bit(I));
    g_running &= (uint8_t)~(1 << I);
    return;
  }
  set_dir(I, s.dir);
  schedule(I, pins::ocr16(kPins(I).step), s.interval_ticks);
}

void start_channel(uint8_t i) {
  const Ramp::Step s = next_step(g_ramps[i]);
  if (s.interval_ticks == 0) return;
  set_dir(i, s.dir);
  schedule(i, TCNT5, s.interval_ticks);
  TIFR5 = (uint8_t)(1 << ocie_bit(i));  // a stale match flag must not fire at once
  set_com(i, kComToggle);
  TIMSK5 |= (uint8_t)(1 << ocie_bit(i));
  g_running |= (uint8_t)(1 << i);
}

}  // namespace

void start() {
  for (uint8_t i = 0; i < kCount; ++i) {
    pins::write(kPins(i).enable, true);
    pins::output(kPins(i).enable);
    pins::output(kPins(i).dir);
    pins::output(kPins(i).step.pin);
  }
  TCCR5B = 0;
  TCCR5A = 0;
  TIMSK5 = 0;
  TCNT5 = 0;
  TCCR5B = (1 << CS51) | (1 << CS50);  // normal mode, /64: 250 kHz
  static_assert(board::kCpuHz / 64 == kTickHz, "Timer5's prescaler gives kTickHz");
  kill();
}

void enable_drivers(bool on) {
  const uint8_t s = SREG;
  cli();
  for (uint8_t i = 0; i < kCount; ++i) pins::write(kPins(i).enable, !on);
  g_killed = !on;
  SREG = s;
}

// From the safety button's interrupt: the drivers off first (EN high), then the step trains.
// Unrolled at -O3 into direct register writes: the safety button's latency (S5) is this.
__attribute__((optimize("O3"))) void kill() {
  const uint8_t s = SREG;
  cli();
  for (uint8_t i = 0; i < kCount; ++i) pins::write(kPins(i).enable, true);
  TIMSK5 = 0;
  for (uint8_t i = 0; i < kCount; ++i) set_com(i, kComClear);
  TCCR5C = (1 << FOC5A) | (1 << FOC5B) | (1 << FOC5C);  // every STEP pin low
  for (uint8_t i = 0; i < kCount; ++i) set_com(i, 0);
  g_running = 0;
  g_killed = true;
  SREG = s;
}

bool running(uint8_t i) { return g_running & (1 << i); }
Ramp& ramp(uint8_t i) { return g_ramps[i]; }

Command::Command(uint8_t i) : i_(i), sreg_(SREG) { cli(); }

Command::~Command() {
  if (!g_killed && !(g_running & (1 << i_)) && g_ramps[i_].wants_step()) start_channel(i_);
  SREG = sreg_;
}

Ramp& Command::ramp() { return g_ramps[i_]; }

}  // namespace steppers
}  // namespace wmra

using namespace wmra;

ISR(TIMER5_COMPB_vect) { steppers::on_edge<0>(); }  // J1
ISR(TIMER5_COMPC_vect) { steppers::on_edge<1>(); }  // J5
ISR(TIMER5_COMPA_vect) { steppers::on_edge<2>(); }  // J6
static_assert(board::kStepperJ1.step.channel == board::Channel::b && board::kStepperJ5.step.channel == board::Channel::c &&
                  board::kStepperJ6.step.channel == board::Channel::a,
              "the vectors above follow the board's channels");
