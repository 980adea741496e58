// Closed-form inverse Jacobian of the seed-2 arm: joint velocities from the velocity of the
// frame-6 origin (base frame) and the angular velocity of the hand, in the base frame
// (inverse_jacobian) or already in the frame turned by q1 (inverse_jacobian_q1, for a caller
// that builds it there: the rotation modes, core/stick_twist.h).
//
// Derivation (independent of the thesis's Appendix IV, whose column 5 has the wrong sign).
// Express the twist in the frame turned by q1 about the base axis (x' radial, y' tangential).
// There the joint axes are z1 = (0,0,1), z2 = z3 = z4 = (0,-1,0), z5 = (s234, 0, -c234) and
// z6 = (c234 c5, -s5, s234 c5), and the joint-5 origin O5 = (R5, 0, d1 + s2 a2 + s23 a3 + s234 a4).
//   1. O5 lies on the axes of joints 5 and 6, so its velocity v5 = v - d6 (w x z6) comes from
//      joints 1-4 alone: v5.y = R5 qd1, which gives qd1 = v5.y / R5.
//   2. The angular velocity less joint 1, w~ = w - qd1 z1, is sigma (0,-1,0) + qd5 z5 + qd6 z6 with
//      sigma = qd2 + qd3 + qd4. z5 and z6 are orthogonal, which gives
//      qd6 = (w~x c234 + w~z s234) / c5,  qd5 = w~x s234 - w~z c234,  sigma = -w~y - qd6 s5.
//   3. The in-plane velocity of O5 is a planar 3R arm with known sigma:
//      bx = -v5.x - sigma s234 a4 = qd2 s2 a2 + (qd2+qd3) s23 a3
//      bz =  v5.z - sigma c234 a4 = qd2 c2 a2 + (qd2+qd3) c23 a3
//      qd2 = (bz s23 - bx c23) / (a2 s3),  qd2 + qd3 = (bx c2 - bz s2) / (a3 s3).
// The pivots multiply to the determinant: det J = -c5 s3 a2 a3 R5. Every entry of
// adj(J)/det(J) has a denominator made of these three factors only, so the three damped
// reciprocals below are the whole of the division work (the thesis needs 126 products for
// the same map). Each reciprocal is damped inside its band (arm_model.h), which keeps joint
// velocities bounded and continuous through a singularity.
#pragma once

#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace kin {

enum class SingularStatus : uint8_t { ok, near_singular, singular };

inline const char* to_string(SingularStatus s) {
  return s == SingularStatus::ok ? "ok" : s == SingularStatus::near_singular ? "near_singular" : "singular";
}

template <class N>
struct Twist {
  Vec3<typename N::Real> v_m_s;    // linear velocity of the frame-6 origin, base frame
  Vec3<typename N::Real> w_rad_s;  // angular velocity, base frame
};

// The derivation's frame for the angular velocity: w_q1 = Rz(-q1) w, the frame turned by q1
// (x' radial, y' tangential, z' = z). The linear velocity stays in the base frame: v and the
// drift correction are commanded there, and J^-1 turns v once either way.
template <class N>
struct TwistQ1 {
  Vec3<typename N::Real> v_m_s;       // linear velocity of the frame-6 origin, base frame
  Vec3<typename N::Real> w_q1_rad_s;  // angular velocity, frame turned by q1
};

// w turned back by q1 (N::dot(a, x, b, y) is a x + b y): wx' = c1 w.x + s1 w.y, wy' = c1 w.y - s1 w.x
template <class N, class Trig>
Vec3<typename N::Real> angular_velocity_q1(const Trig& t, const Vec3<typename N::Real>& w) {
  return Vec3<typename N::Real>{N::dot(t.c1, w.x, t.s1, w.y), N::dot(t.c1, w.y, -t.s1, w.x), w.z};
}

template <class N, class Trig>
TwistQ1<N> twist_q1(const Trig& t, const Twist<N>& twist) {
  return TwistQ1<N>{twist.v_m_s, angular_velocity_q1<N>(t, twist.w_rad_s)};
}

template <class N>
struct SingularFactors {
  typename N::Unit c5;  // cos q5: wrist
  typename N::Unit s3;  // sin q3: elbow stretched or folded
  typename N::Unit r5;  // R5 in metres: joint-5 origin on the base axis
};

template <class N>
struct JacobianInverse {
  typename N::Real qd_rad_s[arm::kJoints];
  SingularFactors<N> factors;
  SingularStatus status;
};

template <class N, class Trig>
SingularFactors<N> singular_factors(const Trig& t) {
  using K = ArmConstants<N>;
  const auto r5 = K::a1 + t.c2 * K::a2 + t.c23 * K::a3 + t.c234 * K::a4;
  return SingularFactors<N>{t.c5, t.s3, N::to_unit(r5)};
}

template <class N>
SingularStatus singular_status(const SingularFactors<N>& f) {
  static constexpr typename N::Band damp_c5 = N::band(arm::kSingularBands.damp_c5);
  static constexpr typename N::Band damp_s3 = N::band(arm::kSingularBands.damp_s3);
  static constexpr typename N::Band damp_r5 = N::band(arm::kSingularBands.damp_r5_m);
  static constexpr typename N::Band slow_c5 = N::band(arm::kSingularBands.slow_c5);
  static constexpr typename N::Band slow_s3 = N::band(arm::kSingularBands.slow_s3);
  static constexpr typename N::Band slow_r5 = N::band(arm::kSingularBands.slow_r5_m);
  if (N::inside(f.c5, damp_c5) || N::inside(f.s3, damp_s3) || N::inside(f.r5, damp_r5)) {
    return SingularStatus::singular;
  }
  if (N::inside(f.c5, slow_c5) || N::inside(f.s3, slow_s3) || N::inside(f.r5, slow_r5)) {
    return SingularStatus::near_singular;
  }
  return SingularStatus::ok;
}

// det J = -c5 s3 a2 a3 R5 (m^3), from the exact factors
template <class N>
typename N::Real determinant(const SingularFactors<N>& f) {
  static constexpr typename N::Unit a2a3 = N::unit(arm::a2 * arm::a3);
  return -(((f.c5 * f.s3) * a2a3) * N::to_real(f.r5));
}

// Step 3's planar 3R chain (both entries below): qd2, qd3 and qd4 from the in-plane velocity
// (bx, bz) of O5 and sigma; then the factors and the status
template <class N, class Trig>
void planar_chain(const Trig& t, const SingularFactors<N>& factors, typename N::Real bx, typename N::Real bz,
                  typename N::Real sigma, JacobianInverse<N>& out) {
  static constexpr typename N::Band damp_s3 = N::band(arm::kSingularBands.damp_s3);
  static constexpr typename N::Recip inv_a2 = N::recip_constant(arm::a2);
  static constexpr typename N::Recip inv_a3 = N::recip_constant(arm::a3);
  // a2 = a3 on this arm: then 1/(a2 s3) serves both qd2 and qd2 + qd3
  static constexpr bool equal_links = arm::a2.num * arm::a3.den == arm::a3.num * arm::a2.den;
  const auto inv_s3 = N::damped_reciprocal(t.s3, damp_s3);
  const auto inv_a2s3 = inv_s3 * inv_a2;
  const auto inv_a3s3 = equal_links ? inv_a2s3 : inv_s3 * inv_a3;
  const auto qd2 = N::dot(t.s23, bz, -t.c23, bx) * inv_a2s3;
  const auto qd23 = N::dot(t.c2, bx, -t.s2, bz) * inv_a3s3;

  out.qd_rad_s[1] = qd2;
  out.qd_rad_s[2] = qd23 - qd2;
  out.qd_rad_s[3] = sigma - qd23;
  out.factors.c5 = factors.c5;
  out.factors.s3 = factors.s3;
  out.factors.r5 = factors.r5;
  out.status = singular_status<N>(factors);
}

// J^-1 of v (base frame) and w in the frame turned by q1 (TwistQ1's members).
// kTurning = false: the twist has no angular velocity (the translation modes), and the terms
// of w are left out. Bit-identical to kTurning = true with w = 0: a product of a zero Real is
// zero, and dot(a, 0, b, y) = b y exactly (fixed_point.h; test_kinematics_fixed checks it,
// test/avr/kinematics on the AVR). It saves seven of J^-1's eleven fused products.
template <class N, bool kTurning, class Trig>
JacobianInverse<N> inverse_jacobian_of(const Trig& t, const Vec3<typename N::Real>& v, const Vec3<typename N::Real>& w) {
  static constexpr typename N::Band damp_c5 = N::band(arm::kSingularBands.damp_c5);
  static constexpr typename N::Band damp_r5 = N::band(arm::kSingularBands.damp_r5_m);
  static constexpr typename N::Unit d6 = N::unit(arm::d6);
  static constexpr typename N::Unit a4 = N::unit(arm::a4);

  // Results go into out as soon as they are known (fewer values kept aside), the factors
  // member by member (a struct copy is a byte loop on the AVR).
  const SingularFactors<N> factors = singular_factors<N>(t);
  JacobianInverse<N> out;

  // v in the frame turned by q1 (N::dot(a, x, b, y) is a x + b y); w is there already
  const typename N::Real zero{};
  const auto vx = N::dot(t.c1, v.x, t.s1, v.y);
  const auto vy = N::dot(t.c1, v.y, -t.s1, v.x);
  const auto wx = kTurning ? w.x : zero;
  const auto wy = kTurning ? w.y : zero;

  // 1. joint-5 origin velocity v5 = v - w x (d6 z6), with d6 z6 = (c234 c5d6, -s5d6, s234 c5d6);
  //    its y component is vy + c5d6 m with m = wx s234 - w.z c234
  const auto c5d6 = t.c5 * d6;
  const auto m = kTurning ? N::dot(t.s234, wx, -t.c234, w.z) : zero;
  const auto qd1 = (kTurning ? vy + m * c5d6 : vy) * N::damped_reciprocal(factors.r5, damp_r5);
  out.qd_rad_s[0] = qd1;

  // 2. wrist: angular velocity less joint 1 (qd5 = wx s234 - wz c234 = m + qd1 c234)
  const auto wz = kTurning ? w.z - qd1 : -qd1;
  out.qd_rad_s[4] = kTurning ? m + qd1 * t.c234 : qd1 * t.c234;
  const auto qd6 = (kTurning ? N::dot(t.c234, wx, t.s234, wz) : t.s234 * wz) * N::damped_reciprocal(t.c5, damp_c5);
  out.qd_rad_s[5] = qd6;
  const auto sigma = kTurning ? -wy - qd6 * t.s5 : -(qd6 * t.s5);

  // 3. planar shoulder-elbow-pitch chain, with v5x and v5z written out:
  //    bx = w.z s5d6 - vx + s234 g,  bz = v.z + wx s5d6 + c234 g,  g = wy c5d6 - sigma a4
  const auto s5d6 = t.s5 * d6;
  const auto g = kTurning ? N::dot(c5d6, wy, -a4, sigma) : -a4 * sigma;
  const auto bx = (kTurning ? N::dot(s5d6, w.z, t.s234, g) : t.s234 * g) - vx;
  const auto bz = (kTurning ? N::dot(s5d6, wx, t.c234, g) : t.c234 * g) + v.z;
  planar_chain<N>(t, factors, bx, bz, sigma, out);
  return out;
}

template <class N, bool kTurning, class Trig>
JacobianInverse<N> inverse_jacobian_of(const Trig& t, const TwistQ1<N>& twist) {
  return inverse_jacobian_of<N, kTurning>(t, twist.v_m_s, twist.w_q1_rad_s);
}

// The base-frame entry: w turned back by q1 first (the arithmetic J^-1 always did), then the same.
template <class N, bool kTurning, class Trig>
JacobianInverse<N> inverse_jacobian_of(const Trig& t, const Twist<N>& twist) {
  const typename N::Real zero{};
  return inverse_jacobian_of<N, kTurning>(
      t, TwistQ1<N>{twist.v_m_s, kTurning ? angular_velocity_q1<N>(t, twist.w_rad_s) : Vec3<typename N::Real>{zero, zero, zero}});
}

template <class N>
bool turning(const Vec3<typename N::Real>& w) {
  return !(N::is_zero(w.x) && N::is_zero(w.y) && N::is_zero(w.z));
}
template <class N>
bool turning(const Twist<N>& twist) { return turning<N>(twist.w_rad_s); }
template <class N>
bool turning(const TwistQ1<N>& twist) { return turning<N>(twist.w_q1_rad_s); }

// Each path a function of its own, flattened: both inlined into one, avr-gcc allocated the
// turning path's registers worse, and unflattened it left the products out of line where
// they have many callers (the kinematics bench: ~300 and ~500 cycles more on the AVR; the
// firmware's stick gate, 106 cycles a tick more on average). J^-1's gate is 3,000 cycles, and
// it takes 2,974 at worst (docs/performance.md).
template <class N, bool kTurning, class Trig, class TwistT>
__attribute__((noinline, flatten)) JacobianInverse<N> inverse_jacobian_path(const Trig& t, const TwistT& twist) {
  return inverse_jacobian_of<N, kTurning>(t, twist);
}

template <class N, class Trig>
JacobianInverse<N> inverse_jacobian(const Trig& t, const Twist<N>& twist) {
  // if/return, not ?: (which copies the chosen result, a byte loop on the AVR)
  if (!turning(twist)) return inverse_jacobian_path<N, false>(t, twist);
  return inverse_jacobian_path<N, true>(t, twist);
}

// w in the frame turned by q1: the same paths without turning w back
template <class N, class Trig>
JacobianInverse<N> inverse_jacobian_q1(const Trig& t, const TwistQ1<N>& twist) {
  if (!turning(twist)) return inverse_jacobian_path<N, false>(t, twist);
  return inverse_jacobian_path<N, true>(t, twist);
}

// The rotation modes' twist: w as its components about the wrist frame's axes x5, y5, z5
// (wrist_frame.h), the axes the modes turn about (core/stick_twist.h); v in the base frame.
template <class N>
struct TwistWrist {
  Vec3<typename N::Real> v_m_s;     // linear velocity of the frame-6 origin, base frame
  Vec3<typename N::Real> w5_rad_s;  // angular velocity about x5, y5, z5
};

// A base-frame twist's w about the wrist axes (the telemetry's velocity command): turned back
// by q1, then w.x5 = s5 n + c5 wy', w.y5 = c5 n - s5 wy', w.z5 = s234 wx' - c234 wz' with
// n = c234 wx' + s234 wz' (the axes of wrist_frame.h in the frame turned by q1)
template <class N, class Trig>
TwistWrist<N> twist_wrist(const Trig& t, const Twist<N>& twist) {
  const Vec3<typename N::Real> w = angular_velocity_q1<N>(t, twist.w_rad_s);
  const auto n = N::dot(t.c234, w.x, t.s234, w.z);
  return TwistWrist<N>{twist.v_m_s, {N::dot(t.s5, n, t.c5, w.y), N::dot(t.c5, n, -t.s5, w.y), N::dot(t.s234, w.x, -t.c234, w.z)}};
}

// J^-1 of a TwistWrist. With w = A x5 + B y5 + C z5, x5 = (s5 c234, c5, s5 s234),
// y5 = (c234 c5, -s5, s234 c5) and z5 = (s234, 0, -c234) in the frame turned by q1, the terms
// of inverse_jacobian_of collapse (the axes are orthonormal):
//   m = C,  c234 wx + s234 wz = s5 A + c5 B,  wy = c5 A - s5 B,
//   s5d6 wz + s234 c5d6 wy = s234 d6 A - c234 s5d6 C,  s5d6 wx + c234 c5d6 wy = c234 d6 A + s234 s5d6 C
// and so, with h = d6 A - a4 sigma:
//   qd1 = (vy + C c5d6) / R5,  qd5 = C + qd1 c234,  qd6 = (s5 A + c5 B - s234 qd1) / c5,
//   sigma = s5 (B - qd6) - c5 A,  bx = s234 h - c234 s5d6 C - vx,  bz = c234 h + s234 s5d6 C + v.z
// w is never formed in another frame: the rotation modes give A, B, C from the stick, and the
// products that turned them into w and J^-1's that took them out again are gone (with their
// rounding). A is 0 in R1 and C in R2 (a run-time test each: their terms are left out).
template <class N, class Trig>
JacobianInverse<N> inverse_jacobian_of_wrist(const Trig& t, const TwistWrist<N>& twist) {
  static constexpr typename N::Band damp_c5 = N::band(arm::kSingularBands.damp_c5);
  static constexpr typename N::Band damp_r5 = N::band(arm::kSingularBands.damp_r5_m);
  static constexpr typename N::Unit d6 = N::unit(arm::d6);
  static constexpr typename N::Unit a4 = N::unit(arm::a4);

  const SingularFactors<N> factors = singular_factors<N>(t);
  JacobianInverse<N> out;
  const auto& v = twist.v_m_s;
  const auto& w = twist.w5_rad_s;
  const bool about_x5 = !N::is_zero(w.x);
  const auto vx = N::dot(t.c1, v.x, t.s1, v.y);
  const auto vy = N::dot(t.c1, v.y, -t.s1, v.x);

  const auto qd1 = (vy + w.z * (t.c5 * d6)) * N::damped_reciprocal(factors.r5, damp_r5);
  out.qd_rad_s[0] = qd1;
  out.qd_rad_s[4] = w.z + qd1 * t.c234;
  const auto cos_part = N::dot(t.c5, w.y, -t.s234, qd1);
  const auto qd6 = (about_x5 ? cos_part + t.s5 * w.x : cos_part) * N::damped_reciprocal(t.c5, damp_c5);
  out.qd_rad_s[5] = qd6;
  const auto sigma = about_x5 ? N::dot(t.s5, w.y - qd6, -t.c5, w.x) : t.s5 * (w.y - qd6);
  const auto h = about_x5 ? N::dot(d6, w.x, -a4, sigma) : -a4 * sigma;
  const auto e = (t.s5 * d6) * w.z;
  const auto bx = N::dot(t.s234, h, -t.c234, e);
  const auto bz = N::dot(t.c234, h, t.s234, e);
  planar_chain<N>(t, factors, bx - vx, bz + v.z, sigma, out);
  return out;
}

template <class N, class Trig>
__attribute__((noinline, flatten)) JacobianInverse<N> inverse_jacobian_wrist_path(const Trig& t, const TwistWrist<N>& twist) {
  return inverse_jacobian_of_wrist<N>(t, twist);
}

// the translation path of a twist's v alone (w unused: v stands in for it)
template <class N, class Trig>
__attribute__((noinline, flatten)) JacobianInverse<N> inverse_jacobian_translation(const Trig& t, const Vec3<typename N::Real>& v) {
  return inverse_jacobian_of<N, false>(t, v, v);
}

// w about the wrist axes: without it the translation path, bit for bit the other entries' own
template <class N, class Trig>
JacobianInverse<N> inverse_jacobian_wrist(const Trig& t, const TwistWrist<N>& twist) {
  if (!turning<N>(twist.w5_rad_s)) return inverse_jacobian_translation<N>(t, twist.v_m_s);
  return inverse_jacobian_wrist_path<N>(t, twist);
}

// flatten: avr-gcc then inlines the trig set into the body before it splits structs into
// registers, which saves about 250 cycles over an inlined but separately optimised trig set.
// One flattened body per path: the trig set computed before the choice cost ~100 cycles more.
template <class N, bool kTurning>
__attribute__((flatten)) JacobianInverse<N> inverse_jacobian_of_angles(const JointAngles<N>& q, const Twist<N>& twist) {
  return inverse_jacobian_of<N, kTurning>(jacobian_trig<N>(q), twist);
}

template <class N>
JacobianInverse<N> inverse_jacobian(const JointAngles<N>& q, const Twist<N>& twist) {
  if (turning(twist)) return inverse_jacobian_of_angles<N, true>(q, twist);
  return inverse_jacobian_of_angles<N, false>(q, twist);
}

}  // namespace kin
}  // namespace wmra
