// Step generation for the three stepper joints on Timer5's compare outputs (OC5A/B/C).
//
// Timer5 runs free at 250 kHz (4 us ticks: the slowest step, 50 ms, fits the 16-bit compare
// register; fast enough for 20 kHz). Each channel's compare unit toggles its STEP pin high at
// the exact tick (hardware timing, no jitter); the compare interrupt toggles it back low with a
// forced compare, counts the step and schedules the next edge one interval (Q8 ticks, the
// fraction carried) after the last, so rounding never accumulates. Nothing else: no ramp maths
// in the ISR (three channels at 20 kHz are 60,000 edges a second).
//
// The speed ramps (lib/control/step_rate.h) run in the main loop: service() (in the firmware
// every tick while homing or moving to a pose, every fourth one while the stick drives:
// firmware/app/tick_plan.h) counts the steps each channel made, moves each ramp's speed by
// at most a dt per tick it spans and hands the ISR the new interval and the steps left before it stops (a position move stops on
// its target in the ISR). Commands (rate(i).set_speed, move_to, stop) take effect at the next
// service(). An edge once scheduled keeps its time; a new interval applies from the edge after.
// An edge the ISR could not schedule in time (another ISR held it) goes out late rather than
// being lost.
#pragma once

#include <stdint.h>

#include "control/step_rate.h"

namespace wmra {
namespace steppers {

constexpr uint32_t kTickHz = 250000;
constexpr uint16_t kServiceHz = 1000;  // a ramp's time step: the 1 kHz control tick (service() may span several)
using Rate = control::StepRate<kTickHz, kServiceHz>;
constexpr uint8_t kCount = 3;  // J1, J5, J6

void start();  // pins low, drivers disabled, timer running, no steps
// DRV8825 EN (active low) of all three. On: the ramps halted (at rest) and service() re-armed.
void enable_drivers(bool on);
// The stop, from any context, also an ISR; the drivers stay enabled and hold. A train
// at or below its ramp's start/stop rate (StepRate::configure_stop) ends at once; a faster one
// runs on for at most a service period and then falls at the stop's deceleration to that rate
// and ends. Until resume() service() only stops: each ramp's commands give way to its stop, and
// no train is started.
void halt_trains();
void resume();
// From any context, also an ISR: no more edges (STEP low, interrupts off), drivers disabled: a
// hang's cut (watchdog.h) and the optional release after a stop. service() then only counts
// the steps made, and nothing is started until enable_drivers(true).
void kill();
bool at_rest();  // no train has an edge scheduled
bool running(uint8_t i);  // channel i has an edge scheduled
namespace detail {
extern Rate* const kRate[kCount];  // steppers.cpp's ramps: rate() is a pointer load, not a call
}
inline Rate& rate(uint8_t i) { return *detail::kRate[i]; }  // main loop only (the ISR never reads it)
// `ticks` control periods after the last: steps made counted into the ramps' positions, the
// ramps advanced, the ISRs given their new intervals.
void service(uint8_t ticks);
// Between services: only the steps made, counted into the ramps' positions.
void count();

}  // namespace steppers
}  // namespace wmra
