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

namespace wmra {
namespace core {

struct Stick {
  fx::Unit x;  // deflection in [-1, 1] after shaping (dead zone, disc, curve, ramp)
  fx::Unit y;
};

// The rotation modes' angular velocity w = ka a + kb b, with ka, kb the stick components in
// rad/s, in the frame turned by q1 where J^-1 takes it (kin::TwistQ1): not turned into the base
// frame and back. Only the mode's two axes, from wrist_frame.h's x5 = (s5 c234, c5, s5 s234),
// y5 = (c234 c5, -s5, s234 c5), z5 = (s234, 0, -c234), with their common factors taken out:
//   R1, ka y5 + kb z5:  p = c5 ka,  w = (c234 p + s234 kb, -s5 ka, s234 p - c234 kb)
//   R2, ka x5 + kb y5:  u = s5 ka + c5 kb,  w = (c234 u, c5 ka - s5 kb, s234 u)
// A function of its own: inlined, its registers made the translation modes save eighteen and
// keep a frame.
template <class Trig>
__attribute__((noinline)) kin::TwistQ1<kin::Fixed> rotation_twist(config::Mode mode, fx::Unit sx, fx::Unit sy, const Trig& t) {
  static constexpr fx::Real kWrist = fx::real(config::kMaxWristSpeed_rad_s);
  const fx::Real zero{0};
  if (mode == config::Mode::r1) {
    const fx::Real ka = sx * kWrist, kb = sy * kWrist;
    const fx::Real p = t.c5 * ka;
    return kin::TwistQ1<kin::Fixed>{{zero, zero, zero}, {fx::dot(t.c234, p, t.s234, kb), -(t.s5 * ka), fx::dot(t.s234, p, -t.c234, kb)}};
  }
  const fx::Real ka = sy * kWrist, kb = sx * kWrist;
  const fx::Real u = fx::dot(t.s5, ka, t.c5, kb);
  return kin::TwistQ1<kin::Fixed>{{zero, zero, zero}, {t.c234 * u, fx::dot(t.c5, ka, -t.s5, kb), t.s234 * u}};
}

// v in the base frame, w in the frame turned by q1 (kin::TwistQ1)
template <class Trig>
kin::TwistQ1<kin::Fixed> stick_twist(config::Mode mode, Stick stick, const Trig& t) {
  static constexpr fx::Real kHand = fx::real(config::kMaxHandSpeed_m_s);
  const fx::Unit sx = config::kStickXSign > 0 ? stick.x : -stick.x;
  const fx::Unit sy = config::kStickYSign > 0 ? stick.y : -stick.y;
  const fx::Real zero{0};
  // one return per mode, built from values in registers: a zeroed twist filled in by mode
  // was a 24-byte store loop and a copy
  switch (mode) {
    case config::Mode::xy:
      return kin::TwistQ1<kin::Fixed>{{sx * kHand, sy * kHand, zero}, {zero, zero, zero}};
    case config::Mode::xz:
      return kin::TwistQ1<kin::Fixed>{{sx * kHand, zero, sy * kHand}, {zero, zero, zero}};
    case config::Mode::r1:
    case config::Mode::r2:
      return rotation_twist(mode, sx, sy, t);
    case config::Mode::gripper:
      break;
  }
  return kin::TwistQ1<kin::Fixed>{{zero, zero, zero}, {zero, zero, zero}};
}

}  // namespace core
}  // namespace wmra
