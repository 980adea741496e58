// The BTS7960 half-bridge pairs of the DC joints J2, J3, J4. A positive duty drives the L input
// (joint positive), a negative one the R input; the other side is held low. Duty 0 disconnects
// the compare output, so the pin is a true 0 (fast PWM at OCR = 0 still makes a spike).
// 20 kHz on every side: Timers 3 and 4 count to ICR = 799 (800 duty steps), Timers 0 and 2 to
// OCRA = 99 (100 steps; see boards/wmra_mega/board.h).
#pragma once

#include <stdint.h>

namespace wmra {
namespace bridges {

constexpr uint8_t kCount = 3;  // J2, J3, J4
constexpr uint32_t kPwmHz = 20000;

void start();  // timers running, every output low, and off as after all_off()
void set(uint8_t joint, int16_t duty_q15);  // joint 0 = J2; duty in [-32767, 32767]; nothing while off
// Every output low and kept so: set() drives nothing until enable(). From any context, also the
// safety button's interrupt, which may land between the loop's reading of the button and its
// servos' run: that run must not drive again what the interrupt cut.
void all_off();
void enable();

}  // namespace bridges
}  // namespace wmra
