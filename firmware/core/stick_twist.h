// The hand's commanded twist from the (shaped) stick deflection, by mode (docs/arm-guide.md, using the arm):
//   XY  stick +X -> base +x, stick +Y -> base +y
//   XZ  stick +X -> base +x, stick +Y -> base +z
//   R1  stick X -> rotation about y5, stick Y -> about z5
//   R2  stick Y -> rotation about x5, stick X -> about y5
// Rotations turn the hand about the frame-6 origin (v = 0 there), so the origin stays put.
// Full deflection is the configured hand or wrist speed. The gripper mode moves no joint.
#pragma once

#include "config/modes_config.h"
#include "config/motion_config.h"
#include "kinematics/inverse_jacobian.h"

namespace wmra {
namespace core {

struct Stick {
  fx::Unit x;  // deflection in [-1, 1] after shaping (dead zone, disc, curve, ramp)
  fx::Unit y;
};

// The rotation modes' angular velocity as its components about the wrist axes x5, y5, z5
// (kin::TwistWrist), which J^-1 takes as they are: no trig here, and none in J^-1 to take them
// out of another frame again (inverse_jacobian.h).
// v in the base frame; the gripper mode's twist is zero.
inline kin::TwistWrist<kin::Fixed> stick_twist(config::Mode mode, Stick stick) {
  static constexpr fx::Real kHand = fx::real(config::kMaxHandSpeed_m_s);
  static constexpr fx::Real kWrist = fx::real(config::kMaxWristSpeed_rad_s);
  const fx::Unit sx = config::kStickXSign > 0 ? stick.x : -stick.x;
  const fx::Unit sy = config::kStickYSign > 0 ? stick.y : -stick.y;
  const fx::Real zero{0};
  // one return per mode, built from values in registers: a zeroed twist filled in by mode
  // was a 24-byte store loop and a copy
  switch (mode) {
    case config::Mode::xy:
      return kin::TwistWrist<kin::Fixed>{{sx * kHand, sy * kHand, zero}, {zero, zero, zero}};
    case config::Mode::xz:
      return kin::TwistWrist<kin::Fixed>{{sx * kHand, zero, sy * kHand}, {zero, zero, zero}};
    case config::Mode::r1:  // X about y5, Y about z5
      return kin::TwistWrist<kin::Fixed>{{zero, zero, zero}, {zero, sx * kWrist, sy * kWrist}};
    case config::Mode::r2:  // Y about x5, X about y5
      return kin::TwistWrist<kin::Fixed>{{zero, zero, zero}, {sy * kWrist, sx * kWrist, zero}};
    case config::Mode::gripper:
      break;
  }
  return kin::TwistWrist<kin::Fixed>{{zero, zero, zero}, {zero, zero, zero}};
}

}  // namespace core
}  // namespace wmra
