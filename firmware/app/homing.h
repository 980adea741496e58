// Knowing where the stepper joints are: J1 and J5 home to their switches, J6 to the turn its
// recorded angle implies (or by widening sweeps); once homed, J6's zero switch is watched and
// its angle at rest recorded, and a limit switch that closes where a count says its joint is
// not at it means the count is wrong (position_lost: the steppers are homed again).
#pragma once

#include <stdint.h>

#include "kinematics/fixed_trig.h"

namespace wmra {
namespace app {
namespace homing {

void configure();
// J6's angle recorded in EEPROM at the last rest (nullptr: none): its count, and homing by it
void set_j6_recorded(const fx::Angle* j6_at_rest);
// J6's count is its angle before homing (its angle was recorded, and nothing has contradicted it)
bool j6_angle_exact();
void restart();
// a homing tick: the sequences on the switches (inputs.h's bits); g_arm.homed once all are done
void tick(uint16_t switches, uint8_t ticks);
// J6's zero switch and rest, over the ticks since the last watch; in_move: a move to a pose
// runs (its line may creep J6 slower than the rest band tells from rest: nothing is recorded)
void watch_wrist(uint8_t ticks, bool in_move);
// an armed limit switch closed (inputs.h's bits)
void on_switch_closed(uint16_t closed);

}  // namespace homing
}  // namespace app
}  // namespace wmra
