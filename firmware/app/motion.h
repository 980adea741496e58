// Resolved-rate motion: the stick's deflection (or a streamed velocity) as the hand's twist, the
// closed-form J^-1 into joint speeds, scaled within the joints' limits, the drives' speeds and
// the DC joints' lag, limited in acceleration, integrated into the joints' references. A drift
// correction pulls the hand back to the integrated commanded position; the gripper's servo
// follows the stick in its mode. A stream that stops arriving halts the joints.
#pragma once

#include <stdint.h>

#include "app/arm_control.h"
#include "control/joystick.h"
#include "kinematics/fixed_point.h"
#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace app {
namespace motion {

void start_gripper();
// the stick starts driving from rest where the references are
void start();

// One motion pass over `ticks` control ticks. keep_for_holding: the next tick updates the
// holding effort, which takes this pass's trig and commanded position.
void pass(const control::JoystickOutput& stick, const Requests& rq, uint8_t ticks, bool keep_for_holding);

// The trig for the holding effort: the last pass's kept one while the stick drives, otherwise of
// the references as they are; then the drift correction from it (while the stick drives).
const kin::JacobianTrig<kin::Fixed>& holding_trig(bool stick_drives);
const kin::JacobianTrig<kin::Fixed>& last_trig();
void update_drift(const kin::JacobianTrig<kin::Fixed>& trig);

// The stream: the iteration's velocity is fresh or not; a stream that was driving and stopped
// arriving halts the joints as a stop does, without latching (halt_lost_stream)
bool streaming();
void set_streaming(bool fresh);
void halt_lost_stream();
bool stream_halted();
// the ticks since the halt: true once the DC joints have had kStreamHalt_ms to come to rest
bool stream_halt_over(uint8_t ticks);

// the hand's position from the drift correction's FK, when it is younger than
// kHandPositionAge_ms (false: none that young)
bool recent_hand_position(kin::Vec3<fx::Real>& p_m);

}  // namespace motion
}  // namespace app
}  // namespace wmra
