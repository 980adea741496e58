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

// (about a) * ka + (about b) * kb, with ka, kb the stick components in rad/s, summed in the
// frame turned by q1 and then turned into the base frame (one rotation, not two). A function
// of its own: inlined, its registers made the translation modes save eighteen and keep a frame.
template <class Trig>
__attribute__((noinline)) kin::Twist<kin::Fixed> rotation_twist(config::Mode mode, fx::Unit sx, fx::Unit sy, const Trig& t) {
  static constexpr fx::Real kWrist = fx::real(config::kMaxWristSpeed_rad_s);
  const fx::Real zero{0};
  const auto axes = kin::wrist_axes_turned<kin::Fixed>(t);
  const auto& a = mode == config::Mode::r1 ? axes.y5 : axes.x5;
  const auto& b = mode == config::Mode::r1 ? axes.z5 : axes.y5;
  const fx::Real ka = (mode == config::Mode::r1 ? sx : sy) * kWrist;
  const fx::Real kb = (mode == config::Mode::r1 ? sy : sx) * kWrist;
  const fx::Real wx = fx::dot(a.x, ka, b.x, kb), wy = fx::dot(a.y, ka, b.y, kb);
  return kin::Twist<kin::Fixed>{{zero, zero, zero},
                                {fx::dot(t.c1, wx, -t.s1, wy), fx::dot(t.s1, wx, t.c1, wy), fx::dot(a.z, ka, b.z, kb)}};
}

template <class Trig>
kin::Twist<kin::Fixed> stick_twist(config::Mode mode, Stick stick, const Trig& t) {
  static constexpr fx::Real kHand = fx::real(config::kMaxHandSpeed_m_s);
  const fx::Unit sx = config::kStickXSign > 0 ? stick.x : -stick.x;
  const fx::Unit sy = config::kStickYSign > 0 ? stick.y : -stick.y;
  const fx::Real zero{0};
  // one return per mode, built from values in registers: a zeroed twist filled in by mode
  // was a 24-byte store loop and a copy
  switch (mode) {
    case config::Mode::xy:
      return kin::Twist<kin::Fixed>{{sx * kHand, sy * kHand, zero}, {zero, zero, zero}};
    case config::Mode::xz:
      return kin::Twist<kin::Fixed>{{sx * kHand, zero, sy * kHand}, {zero, zero, zero}};
    case config::Mode::r1:
    case config::Mode::r2:
      return rotation_twist(mode, sx, sy, t);
    case config::Mode::gripper:
      break;
  }
  return kin::Twist<kin::Fixed>{{zero, zero, zero}, {zero, zero, zero}};
}

}  // namespace core
}  // namespace wmra
