// Step generation for the three stepper joints on Timer5's compare outputs (OC5A/B/C).
//
// Timer5 runs free at 250 kHz (4 us ticks: slow enough that the first step of J1's gentle
// ramp, sqrt(2/a) = 40 ms, fits the 16-bit compare register; fast enough for 20 kHz). Each
// channel's compare unit toggles its STEP pin high at the exact tick (hardware timing, no
// jitter); the compare interrupt then asks the channel's ramp for the next step, toggles the
// pin back low with a forced compare (the pulse lasts the ISR's entry plus the ramp call:
// > 5 us, above the DRV8825's 1.9 us), sets DIR and schedules the next rising edge relative to
// the last one, so rounding never accumulates. One interrupt per step.
// An edge that the ISR could not schedule in time (another ISR held it) goes out late rather
// than being lost: the next compare is never set behind the counter.
//
// The ramps (lib/control/step_ramp.h) are commanded from the main loop inside a Command scope:
// interrupts are off for its few hundred cycles (all of them, not just the channel's: an
// interrupt unmasked with its flag already set is not taken by simavr 1.6, and the step ISRs
// themselves run that long), and an idle channel is restarted at its end.
#pragma once

#include <stdint.h>

#include "control/step_ramp.h"

namespace wmra {
namespace steppers {

constexpr uint32_t kTickHz = 250000;
using Ramp = control::StepRamp<kTickHz>;
constexpr uint8_t kCount = 3;  // J1, J5, J6

void start();  // pins low, drivers disabled, timer running, no steps
void enable_drivers(bool on);  // DRV8825 EN (active low) of all three
// From any context, also an ISR: no more edges (STEP low, interrupts off), drivers disabled.
// The ramps are untouched; the main loop halts them when it sees the stop.
void kill();
bool running(uint8_t i);
Ramp& ramp(uint8_t i);  // read freely; change only inside a Command

class Command {
 public:
  explicit Command(uint8_t i);
  ~Command();  // starts the channel if it was idle and its ramp wants a step; interrupts back on
  Ramp& ramp();
  Command(const Command&) = delete;
  Command& operator=(const Command&) = delete;

 private:
  uint8_t i_;
  uint8_t sreg_;
};

}  // namespace steppers
}  // namespace wmra
