// The serial link: state frames out at 50 Hz, commands in, a reply to every command
// (docs/telemetry.md, firmware/protocol/). Runs after each control iteration, outside its
// timing window; it parses a bounded number of bytes per tick, and garbage only moves its
// error counters.
#pragma once

#include <stdint.h>

#include "app/arm_control.h"

namespace wmra {
namespace app {
namespace link {

void start(uint8_t reset_cause, uint8_t calibration);
// After each iteration: commands into requests, a state frame when one is due. ticks: the 1 ms
// ticks this iteration covered (tick::wait()), so that the frame period and the velocity
// command's age are kept in time, not in iterations (at 665 iterations a second, counting
// iterations gave 33 frames a second instead of 50); loop_cycles: this iteration's length.
void poll(Requests& requests, uint8_t ticks, uint16_t loop_cycles);

}  // namespace link
}  // namespace app
}  // namespace wmra
