#include "drivers/inputs.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "drivers/pins.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace inputs {

namespace {

StopHook g_stop;
volatile uint16_t g_armed;
volatile uint16_t g_last_closed;
volatile uint16_t g_switch_event;
volatile bool g_safety_event;

const board::Pin& switch_pin(uint8_t bit) {
  const board::LimitPins& l = board::kLimits[bit >> 1];
  return (bit & 1) ? l.high : l.low;
}
bool is_switch(uint8_t bit) { return !(bit & 1) || board::kLimits[bit >> 1].has_high; }

// every switch pin is on port B (PCINT0..7) or port D bits 0..3 (INT0..3)
constexpr bool on_interrupt_pin(const board::Pin& p) {
  return p.port == board::Port::B || (p.port == board::Port::D && p.bit <= 3);
}
constexpr bool all_on_interrupt_pins() {
  for (uint8_t j = 0; j < board::kJoints; ++j)
    if (!on_interrupt_pin(board::kLimits[j].low) || !on_interrupt_pin(board::kLimits[j].high)) return false;
  return true;
}
static_assert(all_on_interrupt_pins(), "limit switches on PCINT0..7 (port B) or INT0..3 (PD0..3)");
static_assert(board::kSafetyButton.port == board::Port::E && board::kSafetyButton.bit == 4, "safety button on INT4");

void on_switch_change() {
  const uint16_t closed = closed_switches();
  const uint16_t newly = (uint16_t)(closed & ~g_last_closed & g_armed);
  g_last_closed = closed;
  if (newly) {
    g_switch_event |= newly;
    g_stop();
  }
}

}  // namespace

// Unrolled at compile time: each switch is one constant-address pin read (sbis), also in the
// switch ISRs; a loop over the pin table costs ~700 cycles.
template <uint8_t kBit>
__attribute__((always_inline)) inline uint16_t closed_from(uint16_t closed) {
  constexpr const board::LimitPins& l = board::kLimits[kBit >> 1];
  constexpr bool kIsSwitch = !(kBit & 1) || l.has_high;
  if (kIsSwitch && !pins::read((kBit & 1) ? l.high : l.low)) closed |= (uint16_t)(1u << kBit);
  return closed_from<kBit + 1>(closed);
}
template <>
inline uint16_t closed_from<kSwitchBits>(uint16_t closed) {
  return closed;
}

uint16_t closed_switches() { return closed_from<0>(0); }
bool j6_zero_closed() { return closed_from<10>(0) != 0; }

bool safety_pressed() { return pins::read(board::kSafetyButton); }
bool joystick_button_down() { return !pins::read(board::kJoystickButton); }

void start(StopHook stop) {
  g_stop = stop;
  uint8_t pcint = 0;
  for (uint8_t bit = 0; bit < kSwitchBits; ++bit) {
    if (!is_switch(bit)) continue;
    const board::Pin& p = switch_pin(bit);
    pins::input_pullup(p);
    if (p.port == board::Port::B) pcint |= (uint8_t)(1 << p.bit);
  }
  pins::input_pullup(board::kSafetyButton);
  pins::input_pullup(board::kJoystickButton);
  g_last_closed = closed_switches();
  PCMSK0 = pcint;
  PCICR = (1 << PCIE0);
  // INT0..3: any edge (ISCn = 01); INT4: any edge
  EICRA = (1 << ISC00) | (1 << ISC10) | (1 << ISC20) | (1 << ISC30);
  EICRB = (1 << ISC40);
  EIFR = 0xFF;
  EIMSK = (1 << INT0) | (1 << INT1) | (1 << INT2) | (1 << INT3) | (1 << INT4);
}

void arm_switches(uint16_t mask) {
  const uint8_t s = SREG;
  cli();
  g_armed = mask;
  g_last_closed = closed_switches();  // only closings from now on count
  SREG = s;
}

bool take_safety_event() {
  const uint8_t s = SREG;
  cli();
  const bool e = g_safety_event;
  g_safety_event = false;
  SREG = s;
  return e;
}

bool enable_unless_stopped(void (*enable)()) {
  const uint8_t s = SREG;
  cli();
  const bool stopped = g_safety_event || g_switch_event != 0 || safety_pressed();
  if (!stopped) enable();
  SREG = s;
  return !stopped;
}

uint16_t take_switch_event() {
  const uint8_t s = SREG;
  cli();
  const uint16_t e = g_switch_event;
  g_switch_event = 0;
  SREG = s;
  return e;
}

}  // namespace inputs
}  // namespace wmra

using namespace wmra;

ISR(INT4_vect) {
  if (inputs::safety_pressed()) {
    inputs::g_stop();
    inputs::g_safety_event = true;
  }
}
ISR(PCINT0_vect) { inputs::on_switch_change(); }
ISR(INT0_vect) { inputs::on_switch_change(); }
ISR(INT1_vect, ISR_ALIASOF(INT0_vect));
ISR(INT2_vect, ISR_ALIASOF(INT0_vect));
ISR(INT3_vect, ISR_ALIASOF(INT0_vect));
