// Closed-form inverse kinematics of the seed-2 arm: every joint solution of a frame-6 pose
// that lies within the joint limits (Appendix III of the thesis, with its two errors fixed:
// p_z minus d1 in the planar step, and theta6 = atan2(s6, c6), not the printed cotangent).
//
// Steps (the thesis's Eqs. III.1-III.27, corrected as above). The joint-5 origin is p5 = p - d6 z6, with z6 the third column of R.
//   q1    = atan2(p5y, p5x) or that + pi                         (2 branches)
//   s5    = s1 r13 - c1 r23,  c5 = +-sqrt((c1 r13 + s1 r23)^2 + r33^2)   (2 branches)
//   q6    = atan2(sign(c5) (s1 r12 - c1 r22), sign(c5) (c1 r21 - s1 r11))
//   Sigma = q2 + q3 + q4 from cS = s6 r31 + c6 r32, sS = -c1 (s6 r11 + c6 r12) - s1 (s6 r21 + c6 r22)
//   planar 2R: X = c1 p5x + s1 p5y - cS a4 - a1, Y = p5z - d1 - sS a4,
//   c3 = (X^2 + Y^2 - a2^2 - a3^2) / (2 a2 a3), q3 = +-acos(c3)      (2 branches)
//   q2 = atan2(Y, X) - atan2(a3 s3, a2 + a3 c3),  q4 = Sigma - q2 - q3
// Joint 6 spans +-360 deg, so each q6 appears once per turn that fits the limits.
// Degenerate poses (wrist over the base axis, c5 = 0) have infinitely many solutions and
// are reported as such instead of inventing one; a pose with no solution within the limits
// (out of reach, or reachable only outside them) is reported unreachable.
//
// Cost. The branches differ only in signs: turning q1 by pi negates c1 and s1, the other
// c5 negates c5, and with them s6, c6, cS and sS change sign. So atan2 is evaluated once
// for q1, q5, q6 and Sigma, and each branch takes its angles from those through the exact
// identities atan2(-y, x) = -atan2(y, x) and atan2(y, -x) = pi - atan2(y, x). Branches
// whose q1 or q5 is outside its limits are dropped before their planar step, which holds
// the only other square root and atan2 calls.
#pragma once

#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace kin {

// Within this arm's limits: both q1 branches fit only at exactly +-90 deg, the negative-c5
// branch never (|q5| <= 90 deg, and c5 = 0 is degenerate), two elbows, and q6 up to three
// turns (at q6 = 0 exactly, -360, 0 and 360 deg).
constexpr int kMaxIkSolutions = 2 * 2 * 3;

enum class IkStatus : uint8_t { ok, unreachable, degenerate };

inline const char* to_string(IkStatus s) {
  return s == IkStatus::ok ? "ok" : s == IkStatus::unreachable ? "unreachable" : "degenerate";
}

template <class N>
struct IkSolutions {
  JointAngles<N> q[kMaxIkSolutions];
  int count = 0;
  IkStatus status = IkStatus::ok;
};

template <class N>
struct JointLimits {
  using Angle = typename N::Angle;
  static constexpr Angle min[arm::kJoints] = {
      N::angle_deg(Ratio{arm::q_min_deg[0], 1}), N::angle_deg(Ratio{arm::q_min_deg[1], 1}),
      N::angle_deg(Ratio{arm::q_min_deg[2], 1}), N::angle_deg(Ratio{arm::q_min_deg[3], 1}),
      N::angle_deg(Ratio{arm::q_min_deg[4], 1}), N::angle_deg(Ratio{arm::q_min_deg[5], 1})};
  static constexpr Angle max[arm::kJoints] = {
      N::angle_deg(Ratio{arm::q_max_deg[0], 1}), N::angle_deg(Ratio{arm::q_max_deg[1], 1}),
      N::angle_deg(Ratio{arm::q_max_deg[2], 1}), N::angle_deg(Ratio{arm::q_max_deg[3], 1}),
      N::angle_deg(Ratio{arm::q_max_deg[4], 1}), N::angle_deg(Ratio{arm::q_max_deg[5], 1})};
  static bool within(int joint, Angle q) { return !(q < min[joint]) && !(q > max[joint]); }
};
template <class N> constexpr typename N::Angle JointLimits<N>::min[arm::kJoints];
template <class N> constexpr typename N::Angle JointLimits<N>::max[arm::kJoints];

// atan2(sy y, sx x) from a = atan2(y, x), for signs sy, sx: exact in binary angles
template <class N>
typename N::Angle flipped(typename N::Angle a, bool negate_y, bool negate_x) {
  if (negate_x) a = N::half_turn() - a;
  if (negate_y) a = -a;
  return N::wrap(a);
}

// cos q3 of the planar shoulder-elbow triangle whose far corner is (x, y) from the shoulder
// (law of cosines); reachable is false when no elbow angle closes the triangle.
template <class N>
struct ElbowCosine {
  bool reachable;
  typename N::Unit c3;
};

template <class T>
ElbowCosine<Floating<T>> elbow_cosine(Floating<T>, T x, T y) {
  const T a2 = (T)arm::a2_m, a3 = (T)arm::a3_m;
  const T c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2 * a2 * a3);
  return {c3 >= -1 && c3 <= 1, c3};
}

// Fixed point: the squares in Q30 square metres, and the division by 2 a2 a3 a multiplication
// by its constant reciprocal. Every reachable point is within 0.7 m of the shoulder, so a
// coordinate of 1 m or more is out of reach before any arithmetic.
// x^2 from x = xh + xl, xh its Q15 rounding and |xl| <= 2^-16: x^2 = xh^2 + 2 xh xl + xl^2,
// the last term below 2^-32 and dropped; so the square keeps the full Q23 precision.
inline int32_t square_q30(fx::Real x) {
  const int16_t xh = (int16_t)((x.raw + 0x80) >> 8);
  const int16_t xl2 = (int16_t)(2 * (x.raw - ((int32_t)xh << 8)));  // 2 xl in Q23, |.| <= 256
  return (int32_t)xh * xh + (((int32_t)xh * xl2) >> 8);
}

inline ElbowCosine<Fixed> elbow_cosine(Fixed, fx::Real x, fx::Real y) {
  static constexpr Ratio kSides = arm::a2 * arm::a2 + arm::a3 * arm::a3;
  static constexpr int32_t kSidesQ30 = (int32_t)div_round(kSides.num << 30, kSides.den);
  static constexpr fx::Recip kInvTwoA2A3 = fx::recip_constant(Ratio{2, 1} * arm::a2 * arm::a3);
  static constexpr int32_t kOneMetre = (int32_t)1 << 23;
  if (x.raw >= kOneMetre - 0x80 || x.raw <= -kOneMetre || y.raw >= kOneMetre - 0x80 || y.raw <= -kOneMetre) {
    return {false, fx::Unit{0}};
  }
  // (x^2 + y^2 - a2^2 - a3^2) in Q23, at most 2 in magnitude, times 1/(2 a2 a3) = 4.08
  const fx::Real diff{(square_q30(x) + square_q30(y) - kSidesQ30) >> 7};
  const fx::Real c3 = diff * kInvTwoA2A3;
  const bool reachable = c3.raw >= -kOneMetre && c3.raw <= kOneMetre;
  return {reachable, fx::to_unit(c3)};
}

template <class N>
IkSolutions<N> inverse_kinematics(const Pose<N>& target) {
  using K = ArmConstants<N>;
  using L = JointLimits<N>;
  using Angle = typename N::Angle;
  static constexpr typename N::Band degenerate = N::band(arm::kIkDegenerate);

  IkSolutions<N> out;
  const auto& R = target.R;
  const auto p5x = target.p_m.x - R[0][2] * K::d6;
  const auto p5y = target.p_m.y - R[1][2] * K::d6;
  const auto p5z = target.p_m.z - R[2][2] * K::d6;

  // the first branch of q1 and the angles that the other branches flip
  const Angle phi = N::atan2(p5y, p5x);
  const auto sc1 = N::sincos(phi);
  const auto reach = sc1.c * p5x + sc1.s * p5y;  // distance of p5 from the base axis, >= 0
  const auto a_in = sc1.c * R[0][2] + sc1.s * R[1][2];
  const auto c5_abs = N::hypot(a_in, R[2][2]);
  if (N::inside(N::to_unit(reach), degenerate) || N::inside(c5_abs, degenerate)) {
    out.status = IkStatus::degenerate;
    return out;
  }
  const Angle q5_first = N::atan2(sc1.s * R[0][2] - sc1.c * R[1][2], c5_abs);
  const Angle q6_first = N::atan2(sc1.s * R[0][1] - sc1.c * R[1][1], sc1.c * R[1][0] - sc1.s * R[0][0]);
  const auto sc6 = N::sincos(q6_first);
  const auto cs_first = sc6.s * R[2][0] + sc6.c * R[2][1];
  const auto ss_first = -(sc1.c * (sc6.s * R[0][0] + sc6.c * R[0][1]) + sc1.s * (sc6.s * R[1][0] + sc6.c * R[1][1]));
  const Angle sigma_first = N::atan2(ss_first, cs_first);
  const auto cs_a4 = cs_first * K::a4;
  const auto ss_a4 = ss_first * K::a4;

  for (uint8_t b1 = 0; b1 < 2; ++b1) {
    const Angle q1 = flipped<N>(phi, b1, b1);
    if (!L::within(0, q1)) continue;
    for (uint8_t b5 = 0; b5 < 2; ++b5) {
      const Angle q5 = flipped<N>(q5_first, b1, b5);  // s5 follows q1, c5 the branch
      if (!L::within(4, q5)) continue;
      const bool flip6 = b1 != b5;  // s6, c6 and cS change sign; sS with c5 alone
      const Angle q6 = flipped<N>(q6_first, flip6, flip6);
      const Angle sigma = flipped<N>(sigma_first, b5, flip6);
      const auto x = (b1 ? -reach : reach) - (K::a1 + (flip6 ? -cs_a4 : cs_a4));
      const auto y = p5z - (K::d1 + (b5 ? -ss_a4 : ss_a4));
      const auto elbow = elbow_cosine(N{}, x, y);
      if (!elbow.reachable) continue;
      const auto s3_abs = N::sqrt_one_minus_square(elbow.c3);
      const Angle q3_first = N::atan2(s3_abs, elbow.c3);
      const Angle shoulder = N::atan2(y, x);
      const Angle beta_first = N::atan2(s3_abs * K::a3, K::a2 + elbow.c3 * K::a3);
      for (uint8_t b3 = 0; b3 < 2; ++b3) {
        const Angle q3 = b3 ? -q3_first : q3_first;
        const Angle q2 = N::wrap(shoulder - (b3 ? -beta_first : beta_first));
        const Angle q4 = N::wrap(sigma - q2 - q3);
        if (!L::within(1, q2) || !L::within(2, q3) || !L::within(3, q4)) continue;
        for (int8_t turn = -1; turn <= 1; ++turn) {
          const Angle q6_turn = turn < 0 ? q6 - N::full_turn() : turn > 0 ? q6 + N::full_turn() : q6;
          if (!L::within(5, q6_turn) || out.count == kMaxIkSolutions) continue;
          JointAngles<N>& s = out.q[out.count++];
          s.q[0] = q1;
          s.q[1] = q2;
          s.q[2] = q3;
          s.q[3] = q4;
          s.q[4] = q5;
          s.q[5] = q6_turn;
        }
      }
    }
  }
  if (out.count == 0) out.status = IkStatus::unreachable;
  return out;
}

// The solution nearest to the current joint angles (largest single-joint move smallest),
// or -1 when there is none.
template <class N>
int closest_solution(const IkSolutions<N>& solutions, const JointAngles<N>& current) {
  int best = -1;
  typename N::Angle best_move{};
  for (int k = 0; k < solutions.count; ++k) {
    typename N::Angle move{};
    for (int j = 0; j < arm::kJoints; ++j) {
      const auto d = N::abs(solutions.q[k].q[j] - current.q[j]);
      if (d > move) move = d;
    }
    if (best < 0 || move < best_move) {
      best = k;
      best_move = move;
    }
  }
  return best;
}

}  // namespace kin
}  // namespace wmra
