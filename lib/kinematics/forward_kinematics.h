// Forward kinematics of the seed-2 arm: pose of frame 6 in the base frame.
//
// Closed form of 0T6 = 0T1 1T2 2T3 3T4 4T5 5T6 (seed-2 Eqs. 4.1-4.7, with d1 in p_z,
// which the thesis's Appendix III drops). With L = a4 + c5 d6 and
// r = a1 + c2 a2 + c23 a3 + c234 L:
//   p = (c1 r + s1 s5 d6,  s1 r - c1 s5 d6,  d1 + s2 a2 + s23 a3 + s234 L)
// The test suite checks it against the product of the six modified-DH matrices.
#pragma once

#include "kinematics/arm_model.h"
#include "kinematics/numeric.h"

namespace wmra {
namespace kin {

template <class T>
struct Vec3 {
  T x, y, z;
};

template <class N>
struct JointAngles {
  typename N::Angle q[arm::kJoints];
};

// Sines and cosines of the joint angles and of the sums that the formulas use. The firmware's
// control iteration computes JacobianTrig once and shares it between J^-1 and the hand's
// position (which needs nothing of joint 6 either); the full pose needs PoseTrig (no s3), and
// the formulas take any of these structs that has the members they use.
template <class N>
struct PoseTrig {
  typename N::Unit c1, s1, c2, s2, c23, s23, c234, s234, c5, s5, c6, s6;
};
template <class N>
struct JacobianTrig {
  typename N::Unit c1, s1, c2, s2, s3, c23, s23, c234, s234, c5, s5;
};
template <class N>
struct ArmTrig {
  typename N::Unit c1, s1, c2, s2, s3, c23, s23, c234, s234, c5, s5, c6, s6;
};

// the sines and cosines that every set has; joint 1 last, since J^-1 uses it first (avr-gcc
// then keeps it in registers)
template <class N, class Trig>
void fill_chain_trig(const JointAngles<N>& j, Trig& t) {
  const auto q23 = j.q[1] + j.q[2];
  const auto sc2 = N::sincos(j.q[1]);
  t.c2 = sc2.c;
  t.s2 = sc2.s;
  const auto sc23 = N::sincos(q23);
  t.c23 = sc23.c;
  t.s23 = sc23.s;
  const auto sc234 = N::sincos(q23 + j.q[3]);
  t.c234 = sc234.c;
  t.s234 = sc234.s;
  const auto sc5 = N::sincos(j.q[4]);
  t.c5 = sc5.c;
  t.s5 = sc5.s;
  const auto sc1 = N::sincos(j.q[0]);
  t.c1 = sc1.c;
  t.s1 = sc1.s;
}
template <class N, class Trig>
void fill_roll_trig(const JointAngles<N>& j, Trig& t) {
  const auto sc6 = N::sincos(j.q[5]);
  t.c6 = sc6.c;
  t.s6 = sc6.s;
}

template <class N>
PoseTrig<N> pose_trig(const JointAngles<N>& j) {
  PoseTrig<N> t;
  fill_chain_trig<N>(j, t);
  fill_roll_trig<N>(j, t);
  return t;
}
template <class N>
void fill_jacobian_trig(const JointAngles<N>& j, JacobianTrig<N>& t) {
  t.s3 = N::sin(j.q[2]);
  fill_chain_trig<N>(j, t);
}
template <class N>
JacobianTrig<N> jacobian_trig(const JointAngles<N>& j) {
  JacobianTrig<N> t;
  fill_jacobian_trig<N>(j, t);
  return t;
}
template <class N>
ArmTrig<N> arm_trig(const JointAngles<N>& j) {
  ArmTrig<N> t;
  fill_chain_trig<N>(j, t);
  fill_roll_trig<N>(j, t);
  t.s3 = N::sin(j.q[2]);
  return t;
}

template <class N>
struct Pose {
  Vec3<typename N::Real> p_m;       // frame-6 origin, base frame
  typename N::Unit R[3][3];         // rotation base <- frame 6, row-major
};

template <class N>
struct ArmConstants {
  static constexpr typename N::Length a1 = N::length(arm::a1);
  static constexpr typename N::Length a2 = N::length(arm::a2);
  static constexpr typename N::Length a3 = N::length(arm::a3);
  static constexpr typename N::Length a4 = N::length(arm::a4);
  static constexpr typename N::Length d1 = N::length(arm::d1);
  static constexpr typename N::Length d6 = N::length(arm::d6);
};
template <class N> constexpr typename N::Length ArmConstants<N>::a1;
template <class N> constexpr typename N::Length ArmConstants<N>::a2;
template <class N> constexpr typename N::Length ArmConstants<N>::a3;
template <class N> constexpr typename N::Length ArmConstants<N>::a4;
template <class N> constexpr typename N::Length ArmConstants<N>::d1;
template <class N> constexpr typename N::Length ArmConstants<N>::d6;

// the frame-6 origin alone (the firmware's drift correction needs no rotation)
template <class N, class Trig>
Vec3<typename N::Real> hand_position(const Trig& t) {
  using K = ArmConstants<N>;
  static constexpr typename N::Unit d6 = N::unit(arm::d6);
  const auto L = K::a4 + t.c5 * K::d6;
  const auto r = K::a1 + t.c2 * K::a2 + t.c23 * K::a3 + t.c234 * L;
  const auto s5d6 = t.s5 * d6;  // the wrist's sideways offset, < 0.2 m: a Unit is precise enough
  return {t.c1 * r + N::to_real(t.s1 * s5d6), t.s1 * r - N::to_real(t.c1 * s5d6),
          K::d1 + t.s2 * K::a2 + t.s23 * K::a3 + t.s234 * L};
}

template <class N, class Trig>
Pose<N> forward_kinematics(const Trig& t) {
  Pose<N> pose;
  pose.p_m = hand_position<N>(t);

  // columns n, o, a of 0R6 (the thesis's Eqs. III.4-III.8), sharing the wrist terms
  const auto c234s5 = t.c234 * t.s5;
  const auto s234s5 = t.s234 * t.s5;
  const auto n_in = c234s5 * t.c6 - t.s234 * t.s6;  // component in the arm's vertical plane
  const auto o_in = c234s5 * t.s6 + t.s234 * t.c6;
  const auto c5c6 = t.c5 * t.c6;
  const auto c5s6 = t.c5 * t.s6;
  const auto c234c5 = t.c234 * t.c5;
  pose.R[0][0] = t.c1 * n_in - t.s1 * c5c6;
  pose.R[1][0] = t.s1 * n_in + t.c1 * c5c6;
  pose.R[2][0] = s234s5 * t.c6 + t.c234 * t.s6;
  pose.R[0][1] = t.s1 * c5s6 - t.c1 * o_in;
  pose.R[1][1] = -(t.s1 * o_in) - t.c1 * c5s6;
  pose.R[2][1] = t.c234 * t.c6 - s234s5 * t.s6;
  pose.R[0][2] = t.c1 * c234c5 + t.s1 * t.s5;
  pose.R[1][2] = t.s1 * c234c5 - t.c1 * t.s5;
  pose.R[2][2] = t.s234 * t.c5;
  return pose;
}

template <class N>
Pose<N> forward_kinematics(const JointAngles<N>& q) {
  return forward_kinematics<N>(pose_trig<N>(q));
}

}  // namespace kin
}  // namespace wmra
