// The stepper joints J1, J5, J6 (steppers 0, 1, 2): each ramp tracks its joint's reference
// (feedforward of the reference's speed plus a position loop on the step count), and J1's stop
// follows the arm's inertia about the base axis.
#pragma once

#include <stdint.h>

#include "control/step_rate.h"
#include "kinematics/fixed_point.h"
#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace app {
namespace stepper_drives {

void configure();
// each ramp's speed from its joint's reference and the step count's error
void track();
// the references of the stepper joints where their counts are
void references_from_counts();
fx::Angle angle(uint8_t i);  // from the count as the last count left it
// a stepper's steps for an angle of its joint, and back
int32_t steps_of(uint8_t i, fx::Angle a);
fx::Angle angle_of(uint8_t i, int32_t steps);

// J1's stop constants: for the largest inertia (homing, before the pose is known), or from the
// pose of `trig`, with the speed from which the hand stops within kStopTravel_mm
void use_largest_j1_stop();
void update_j1_stop(const kin::JacobianTrig<kin::Fixed>& trig);
// J5 against the wrist's gravity at the pose of `trig` (core::wrist_gravity_q14): where it takes
// more than the torque J5's motor plans with, J5 may not lift the wrist (its drive a creep that
// way, in limit_speeds, for the stick and the stream); and its reference speeds up a lift at
// most at what the torque left gives the wrist's inertia (g_arm.j5_max_change_per_tick)
void update_wrist_load(const kin::JacobianTrig<kin::Fixed>& trig);
// the steppers' drives (g_arm.drives) at their speed limits, J1's at most its stop speed, J5 not
// lifting what it cannot while the stick or a stream drives (resolved_rate), and no drive
// towards a closed switch
void limit_speeds(bool resolved_rate);

}  // namespace stepper_drives
}  // namespace app
}  // namespace wmra
