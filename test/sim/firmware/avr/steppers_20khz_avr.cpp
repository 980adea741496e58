// Step generation (docs/performance.md, gates): three steppers at 20 kHz at once with the control loop running.
// The firmware's own step driver and ramps (lib/drivers/steppers, lib/control/step_rate.h);
// each channel moves kSteps steps (J1 and J6 positive, J5 negative) at up to 20 kHz, the
// ramps' top speed with the firmware's minimum interval. A 1 kHz loop on the firmware's tick
// stands in for the control iteration: D49 high for kLoadCycles of work, the three moves
// commanded again (as motion_tick commands the ramps every tick) and the ramps serviced.
// Not the firmware itself: its configured top speeds are 1.6, 15 and 1.5 kHz (J1, J5, J6).
#include <avr/interrupt.h>
#include <util/delay_basic.h>

#include "drivers/pins.h"
#include "drivers/steppers.h"
#include "drivers/system_tick.h"
#include "wmra_mega/board.h"

using namespace wmra;

namespace {

constexpr int32_t kSteps = 20000;  // per channel: ~0.2 s speeding up, ~0.8 s at 20 kHz, braking
constexpr uint32_t kTopSpeed_steps_s = 20000;
// 100,000 steps/s^2: 20 kHz within 2,000 steps, so that most of the move is at the top speed;
// the firmware's shortest and longest intervals (firmware/config/joints_config.h)
constexpr control::StepRateConstants kRate = control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, {100000, 12, 12500});
static_assert(kRate.status == control::RateStatus::ok, "ramp");
// the budget for one control iteration (8,000 cycles), as busy work: 4 cycles a count
constexpr uint16_t kLoadCycles = 8000;
constexpr int8_t kDir[steppers::kCount] = {+1, -1, +1};  // J1, J5, J6

void command_moves() {
  for (uint8_t i = 0; i < steppers::kCount; ++i) steppers::rate(i).move_to(kDir[i] * kSteps, kTopSpeed_steps_s);
}

}  // namespace

int main() {
  steppers::start();
  pins::write(board::kTimingProbe, false);
  pins::output(board::kTimingProbe);
  tick::start();
  for (uint8_t i = 0; i < steppers::kCount; ++i) steppers::rate(i).configure(kRate);
  sei();
  steppers::enable_drivers(true);
  for (;;) {
    const uint8_t ticks = tick::wait();
    pins::write(board::kTimingProbe, true);
    _delay_loop_2(kLoadCycles / 4);
    command_moves();
    steppers::service(ticks);
    pins::write(board::kTimingProbe, false);
  }
}
