// Joint-space moves: to the ready pose after homing, to a stored pose on `goto` or a long press.
// Every joint follows one line (core/joint_move.h) under a speed cap from the joints' and the
// hand's limits, the drives and the DC joints' lag; a person who takes over brakes it along
// its line. At the line's end the steppers settle onto their target steps.
#pragma once

#include <stdint.h>

#include "kinematics/fixed_trig.h"

namespace wmra {
namespace app {
namespace joint_moves {

// the ready pose, with J6 at the ready angle's turn nearest where J6 homed (core/ready_roll.h)
void plan_ready_pose();
void begin_ready();
// a move from the references to `angles` (fx::Angle raw, six)
void begin(const int32_t* angles);
// one tick of the move; cap_tick: the tick plan's kMoveSpeedCap; ramp_tick: its kStepperRamps
// (the steppers track the line there, as they do the stick's references)
void tick(bool cap_tick, bool ramp_tick);
// every stepper at rest on its target and every DC joint's pot within kArrivedTolerance_mdeg
bool arrived();
void brake();
bool braked_to_rest();  // braking, and the lead joint's speed 0

}  // namespace joint_moves
}  // namespace app
}  // namespace wmra
