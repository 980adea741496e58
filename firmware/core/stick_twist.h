// The hand's commanded twist from the (shaped) stick deflection, by mode (SPEC section 5):
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
#include "kinematics/wrist_frame.h"

namespace wmra {
namespace core {

struct Stick {
  fx::Unit x;  // deflection in [-1, 1] after shaping (dead zone, disc, curve, ramp)
  fx::Unit y;
};

template <class Trig>
kin::Twist<kin::Fixed> stick_twist(config::Mode mode, Stick stick, const Trig& t) {
  static constexpr fx::Real kHand = fx::real(config::kMaxHandSpeed_m_s);
  static constexpr fx::Real kWrist = fx::real(config::kMaxWristSpeed_rad_s);
  const fx::Unit sx = config::kStickXSign > 0 ? stick.x : -stick.x;
  const fx::Unit sy = config::kStickYSign > 0 ? stick.y : -stick.y;
  const fx::Real zero{0};
  kin::Twist<kin::Fixed> twist{{zero, zero, zero}, {zero, zero, zero}};
  switch (mode) {
    case config::Mode::xy:
      twist.v_m_s = {sx * kHand, sy * kHand, zero};
      break;
    case config::Mode::xz:
      twist.v_m_s = {sx * kHand, zero, sy * kHand};
      break;
    case config::Mode::r1:
    case config::Mode::r2: {
      // (about a) * ka + (about b) * kb, with ka, kb the stick components in rad/s, summed in
      // the frame turned by q1 and then turned into the base frame (one rotation, not two)
      const auto axes = kin::wrist_axes_turned<kin::Fixed>(t);
      const auto& a = mode == config::Mode::r1 ? axes.y5 : axes.x5;
      const auto& b = mode == config::Mode::r1 ? axes.z5 : axes.y5;
      const fx::Real ka = (mode == config::Mode::r1 ? sx : sy) * kWrist;
      const fx::Real kb = (mode == config::Mode::r1 ? sy : sx) * kWrist;
      const fx::Real wx = fx::dot(a.x, ka, b.x, kb), wy = fx::dot(a.y, ka, b.y, kb);
      twist.w_rad_s = {fx::dot(t.c1, wx, -t.s1, wy), fx::dot(t.s1, wx, t.c1, wy), fx::dot(a.z, ka, b.z, kb)};
      break;
    }
    case config::Mode::gripper:
      break;
  }
  return twist;
}

}  // namespace core
}  // namespace wmra
