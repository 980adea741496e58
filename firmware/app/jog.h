// The jog in the firmware (bring-up, SPEC 7; the rule in core/jog.h): the jogged joint's
// reference speeds up, turns and slows at its acceleration limit while every other joint's
// stands, and the steppers' ramps follow their references.
#pragma once

#include <stdint.h>

#include "app/arm_control.h"

namespace wmra {
namespace app {
namespace jog {

// one control iteration of the jog state: the joint at its jog speed while the commands keep
// coming with the stick at rest, else slowing to a stop; closed_switches as inputs.h's bits
void tick(const Requests& rq, bool stick_rests, uint16_t closed_switches, uint8_t ticks);
// every reference stands (the jog is over once its commands have stopped)
bool at_rest();

}  // namespace jog
}  // namespace app
}  // namespace wmra
