// The arm's switches: limit switches (INT0..3 and PCINT0..6), the safety button (INT4) and the
// joystick button (polled). All read low while closed (pull-ups on), except the safety button,
// which is normally closed and reads high while pressed or when its wire is broken.
//
// Reactions that cannot wait for the control loop happen in the interrupts: the safety button
// and the closing of an armed limit switch call the stop hook at once (outputs off); the
// loop then sees the latched flags and decides what follows.
#pragma once

#include <stdint.h>

namespace wmra {
namespace inputs {

// bit 2j: joint j+1's low switch, bit 2j+1: its high switch (J6: bit 10 is its zero switch)
constexpr uint8_t kSwitchBits = 11;
constexpr uint16_t kJ6ZeroSwitch = 1u << 10;

using StopHook = void (*)();
void start(StopHook stop);
uint16_t closed_switches();
bool j6_zero_closed();  // closed_switches() & kJ6ZeroSwitch, one pin read
bool safety_pressed();        // now (the pin)
bool joystick_button_down();  // now (the pin)
// Switches whose closing stops the arm from the interrupt (the loop changes it with the state).
void arm_switches(uint16_t mask);
// Latched by the interrupts until taken: the safety button was pressed / an armed switch closed.
bool take_safety_event();
uint16_t take_switch_event();
// Runs enable (the stop hook's outputs back on) with interrupts off, unless a stop is still to be
// taken: the safety button held, or its press or an armed switch's closing not yet taken (an
// interrupt after the loop took them: its supervisor sees it next iteration, and the outputs stay
// cut until then). Returns whether it ran.
bool enable_unless_stopped(void (*enable)());

}  // namespace inputs
}  // namespace wmra
