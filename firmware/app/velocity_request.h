// The serial link's velocity command (Requests: mm/s and mrad/s in the base frame) as the twist
// J^-1 takes: clamped to the hand's and the wrist's speed limits, w about the wrist axes.
#pragma once

#include "app/arm_control.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/inverse_jacobian.h"

namespace wmra {
namespace app {

kin::TwistWrist<kin::Fixed> velocity_twist(const Requests& rq, const kin::JacobianTrig<kin::Fixed>& trig);

}  // namespace app
}  // namespace wmra
