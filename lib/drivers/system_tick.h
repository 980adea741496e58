// The 1 kHz control tick and the gripper's servo pulse, both on Timer1.
//
// Timer1 runs free at 2 MHz (prescaler 8, normal mode). Compare A is moved on by 2,000 counts
// at each match: the tick. OC1C (D13) toggles on compare C, which is moved on by the pulse
// width after a rising edge and by the rest of the 20 ms servo frame after a falling one, so
// the pulse edges are exact in hardware and cost two short interrupts per frame. (Normal mode
// rather than CTC: its compare registers take effect at once, also in simavr.)
#pragma once

#include <stdint.h>

namespace wmra {
namespace tick {

constexpr uint16_t kFrameCounts = 40000;  // the servo frame: 20 ms at 2 MHz
constexpr uint16_t kTickCounts = 2000;    // 1 ms
constexpr uint16_t kCountsPerUs = 2;

void start();
// Sleeps (idle) until a tick is due; returns the ticks that elapsed (> 1: the loop overran).
uint8_t wait();
uint32_t now_ms();
// Compare B: a second 1 kHz event, phase_us (< 1000) after each tick's compare (from the tick
// under way or the next on), its interrupt enabled; its ISR is its user's (adc_scan.cpp). The
// tick's ISR moves it on, so that the user's ISR does only its job.
void start_phase_compare(uint16_t phase_us);
// Servo pulse width, us; 0 = no pulse (pin low).
void set_servo_pulse_us(uint16_t us);

}  // namespace tick
}  // namespace wmra
