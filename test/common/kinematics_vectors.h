// Deterministic inputs for the fixed-point kinematics and the text form of its outputs.
// Compiled both into an AVR image and into the host test, which compare the text byte for
// byte: the fixed-point code must give bit-identical results on both.
#pragma once

#include <stdint.h>

#include "kinematics/inverse_jacobian.h"
#include "kinematics/inverse_kinematics.h"

namespace wmra {
namespace vectors {

using kin::Fixed;

struct Lcg {
  uint32_t state;
  uint32_t next() {
    state = state * 1664525u + 1013904223u;
    return state;
  }
  // uniform in [lo, hi] (inclusive), from the top 24 bits
  int32_t in_range(int32_t lo, int32_t hi) {
    const uint32_t span = (uint32_t)(hi - lo) + 1u;
    return lo + (int32_t)((next() >> 8) % span);
  }
};

inline kin::JointAngles<Fixed> random_joint_angles(Lcg& rng) {
  kin::JointAngles<Fixed> q;
  for (int i = 0; i < arm::kJoints; ++i) {
    q.q[i].raw = rng.in_range(fx::angle_deg(Ratio{arm::q_min_deg[i], 1}).raw, fx::angle_deg(Ratio{arm::q_max_deg[i], 1}).raw);
  }
  return q;
}

// joystick-sized twists: up to 0.15 m/s and 0.8 rad/s per axis
inline kin::Twist<Fixed> random_twist(Lcg& rng) {
  const int32_t v = fx::real(Ratio{15, 100}).raw;
  const int32_t w = fx::real(Ratio{80, 100}).raw;
  kin::Twist<Fixed> t;
  t.v_m_s = {fx::Real{rng.in_range(-v, v)}, fx::Real{rng.in_range(-v, v)}, fx::Real{rng.in_range(-v, v)}};
  t.w_rad_s = {fx::Real{rng.in_range(-w, w)}, fx::Real{rng.in_range(-w, w)}, fx::Real{rng.in_range(-w, w)}};
  return t;
}

// One line per case: "F" pose (p as 3 x 8 hex digits, R as 9 x 4),
// "J" joint velocities (6 x 8), det (8) and status (1), "T" the joint velocities of the twist
// without its angular velocity (6 x 8), "Q" those of the twist with its w taken as in the frame
// turned by q1 (inverse_jacobian_q1, 6 x 8), and "I" the inverse kinematics of
// that pose: status (1), count (1) and each solution's angles (6 x 8). put(char) is the sink.
template <class Put>
void hex(Put& put, uint32_t v, uint8_t digits) {
  for (int8_t i = (int8_t)(digits - 1); i >= 0; --i) {
    const uint8_t n = (uint8_t)((v >> (4 * i)) & 0xF);
    put((char)(n < 10 ? '0' + n : 'a' + n - 10));
  }
}

template <class Put>
void emit_case(Put& put, const kin::JointAngles<Fixed>& q, const kin::Twist<Fixed>& twist) {
  const auto trig = kin::arm_trig<Fixed>(q);
  const auto pose = kin::forward_kinematics<Fixed>(trig);
  put('F');
  hex(put, (uint32_t)pose.p_m.x.raw, 8);
  hex(put, (uint32_t)pose.p_m.y.raw, 8);
  hex(put, (uint32_t)pose.p_m.z.raw, 8);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) hex(put, (uint16_t)pose.R[r][c].raw, 4);
  put(' ');
  const auto inv = kin::inverse_jacobian<Fixed>(trig, twist);
  put('J');
  for (int i = 0; i < arm::kJoints; ++i) hex(put, (uint32_t)inv.qd_rad_s[i].raw, 8);
  hex(put, (uint32_t)kin::determinant<Fixed>(inv.factors).raw, 8);
  put((char)('0' + (int)inv.status));
  // the same without angular velocity: J^-1's translation path (inverse_jacobian_of<.., false>)
  kin::Twist<Fixed> translation = twist;
  translation.w_rad_s = {fx::Real{0}, fx::Real{0}, fx::Real{0}};
  const auto inv_v = kin::inverse_jacobian<Fixed>(trig, translation);
  put('T');
  for (int i = 0; i < arm::kJoints; ++i) hex(put, (uint32_t)inv_v.qd_rad_s[i].raw, 8);
  // the entry the rotation modes use: w in the frame turned by q1
  const auto inv_q1 = kin::inverse_jacobian_q1<Fixed>(trig, kin::TwistQ1<Fixed>{twist.v_m_s, twist.w_rad_s});
  put('Q');
  for (int i = 0; i < arm::kJoints; ++i) hex(put, (uint32_t)inv_q1.qd_rad_s[i].raw, 8);
  put(' ');
  const auto ik = kin::inverse_kinematics<Fixed>(pose);
  put('I');
  put((char)('0' + (int)ik.status));
  hex(put, (uint32_t)ik.count, 1);
  for (int k = 0; k < ik.count; ++k)
    for (int j = 0; j < arm::kJoints; ++j) hex(put, (uint32_t)ik.q[k].q[j].raw, 8);
  put('\n');
}

constexpr uint32_t kSeed = 20261121u;
constexpr int kCases = 2000;

template <class Put>
void emit_all(Put& put) {
  Lcg rng{kSeed};
  for (int i = 0; i < kCases; ++i) {
    const auto q = random_joint_angles(rng);
    const auto twist = random_twist(rng);
    emit_case(put, q, twist);
  }
}

}  // namespace vectors
}  // namespace wmra
