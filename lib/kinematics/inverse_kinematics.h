// Closed-form inverse kinematics of the seed-2 arm: every joint solution of a frame-6 pose
// that lies within the joint limits (Appendix III of the thesis, with its two errors fixed:
// p_z minus d1 in the planar step, and theta6 = atan2(s6, c6), not the printed cotangent).
//
// Steps (seed2-digest 4.2). The joint-5 origin is p5 = p - d6 z6, with z6 the third column of R.
//   q1    = atan2(p5y, p5x) or that + pi                         (2 branches)
//   s5    = s1 r13 - c1 r23,  c5 = +-sqrt((c1 r13 + s1 r23)^2 + r33^2)   (2 branches)
//   q6    = atan2(sign(c5) (s1 r12 - c1 r22), sign(c5) (c1 r21 - s1 r11))
//   Sigma = q2 + q3 + q4 from cS = s6 r31 + c6 r32, sS = -c1 (s6 r11 + c6 r12) - s1 (s6 r21 + c6 r22)
//   planar 2R: X = c1 p5x + s1 p5y - cS a4 - a1, Y = p5z - d1 - sS a4,
//   c3 = (X^2 + Y^2 - a2^2 - a3^2) / (2 a2 a3), q3 = +-acos(c3)      (2 branches)
//   q2 = atan2(Y, X) - atan2(a3 s3, a2 + a3 c3),  q4 = Sigma - q2 - q3
// Joint 6 spans +-360 deg, so each q6 appears once per turn that fits the limits.
// Degenerate poses (wrist over the base axis, c5 = 0) have infinitely many solutions and
// are reported as such instead of inventing one.
//
// This version runs in double on the host (armkin, tests); the firmware's fixed-point
// instantiation is still to be written.
#pragma once

#include <algorithm>
#include <cmath>

#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace kin {

constexpr int kMaxIkSolutions = 16;  // 2 x 2 x 2 branches, times two turns of joint 6

enum class IkStatus : uint8_t { ok, unreachable, degenerate };

template <class N>
struct IkSolutions {
  JointAngles<N> q[kMaxIkSolutions];
  int count = 0;
  IkStatus status = IkStatus::ok;
};

inline double wrap_pi(double a) {
  const double two_pi = 2 * arm::kPi;
  a = std::fmod(a, two_pi);
  if (a <= -arm::kPi) a += two_pi;
  if (a > arm::kPi) a -= two_pi;
  return a;
}

template <class N>
IkSolutions<N> inverse_kinematics(const Pose<N>& target, double degenerate_tolerance = 1e-9) {
  IkSolutions<N> out;
  const auto& R = target.R;
  const double px5 = target.p_m.x - R[0][2] * arm::d6_m;
  const double py5 = target.p_m.y - R[1][2] * arm::d6_m;
  const double pz5 = target.p_m.z - R[2][2] * arm::d6_m;
  if (std::hypot(px5, py5) < degenerate_tolerance) {
    out.status = IkStatus::degenerate;
    return out;
  }
  bool reachable_any = false;
  const double phi = std::atan2(py5, px5);
  for (int b1 = 0; b1 < 2; ++b1) {
    const double q1 = wrap_pi(phi + b1 * arm::kPi);
    const double c1 = std::cos(q1), s1 = std::sin(q1);
    const double s5 = s1 * R[0][2] - c1 * R[1][2];
    const double c5_abs = std::hypot(c1 * R[0][2] + s1 * R[1][2], R[2][2]);
    if (c5_abs < degenerate_tolerance) {
      out.status = IkStatus::degenerate;
      return out;
    }
    for (int b5 = 0; b5 < 2; ++b5) {
      const double c5 = b5 ? -c5_abs : c5_abs;
      const double q5 = std::atan2(s5, c5);
      const double q6 = std::atan2((s1 * R[0][1] - c1 * R[1][1]) / c5, (c1 * R[1][0] - s1 * R[0][0]) / c5);
      const double c6 = std::cos(q6), s6 = std::sin(q6);
      const double cs = s6 * R[2][0] + c6 * R[2][1];
      const double ss = -c1 * (s6 * R[0][0] + c6 * R[0][1]) - s1 * (s6 * R[1][0] + c6 * R[1][1]);
      const double sigma = std::atan2(ss, cs);
      const double x = c1 * px5 + s1 * py5 - cs * arm::a4_m - arm::a1_m;
      const double y = pz5 - arm::d1_m - ss * arm::a4_m;
      const double c3 = (x * x + y * y - arm::a2_m * arm::a2_m - arm::a3_m * arm::a3_m) / (2 * arm::a2_m * arm::a3_m);
      if (std::abs(c3) > 1) continue;
      reachable_any = true;
      for (int b3 = 0; b3 < 2; ++b3) {
        const double s3 = (b3 ? -1 : 1) * std::sqrt(1 - c3 * c3);
        const double q3 = std::atan2(s3, c3);
        const double q2 = wrap_pi(std::atan2(y, x) - std::atan2(arm::a3_m * s3, arm::a2_m + arm::a3_m * c3));
        const double q4 = wrap_pi(sigma - q2 - q3);
        const double q[5] = {q1, q2, q3, q4, q5};
        bool within = true;
        for (int j = 0; j < 5; ++j) within = within && q[j] >= arm::q_min_rad(j) && q[j] <= arm::q_max_rad(j);
        if (!within) continue;
        for (int turn = -2; turn <= 2; ++turn) {
          const double q6_turn = q6 + turn * 2 * arm::kPi;
          if (q6_turn < arm::q_min_rad(5) || q6_turn > arm::q_max_rad(5) || out.count == kMaxIkSolutions) continue;
          JointAngles<N>& s = out.q[out.count++];
          for (int j = 0; j < 5; ++j) s.q[j] = q[j];
          s.q[5] = q6_turn;
        }
      }
    }
  }
  if (!reachable_any) out.status = IkStatus::unreachable;
  return out;
}

// The solution nearest to the current joint angles (largest single-joint move smallest),
// or -1 when there is none.
template <class N>
int closest_solution(const IkSolutions<N>& solutions, const JointAngles<N>& current) {
  int best = -1;
  double best_move = 0;
  for (int k = 0; k < solutions.count; ++k) {
    double move = 0;
    for (int j = 0; j < arm::kJoints; ++j) move = std::max(move, std::abs(solutions.q[k].q[j] - current.q[j]));
    if (best < 0 || move < best_move) {
      best = k;
      best_move = move;
    }
  }
  return best;
}

}  // namespace kin
}  // namespace wmra
