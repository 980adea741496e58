// The firmware's fixed-point instantiation against the Eigen reference:
// FK within 0.2 mm and 1 mrad, J^-1 within 1e-3 relative away from singularities, and
// bounded, continuous joint velocities through each singular factor.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "eigen_reference.h"
#include "kinematics/inverse_jacobian.h"

using namespace wmra;
using kin::Fixed;

namespace {

constexpr int kPoses = 10000;

kin::JointAngles<Fixed> to_fixed(const ref::Joints& q) {
  kin::JointAngles<Fixed> a;
  for (int i = 0; i < 6; ++i) a.q[i] = fx::angle(q[i]);
  return a;
}
// the joint angles the fixed-point code actually receives
ref::Joints quantised(const ref::Joints& q) {
  ref::Joints out;
  for (int i = 0; i < 6; ++i) out[i] = fx::to_radians(fx::angle(q[i]));
  return out;
}
kin::Twist<Fixed> to_fixed(const ref::Vec6& nu) {
  return kin::Twist<Fixed>{{fx::real(nu[0]), fx::real(nu[1]), fx::real(nu[2])},
                           {fx::real(nu[3]), fx::real(nu[4]), fx::real(nu[5])}};
}
ref::Vec6 to_eigen(const kin::JacobianInverse<Fixed>& inv) {
  ref::Vec6 v;
  for (int i = 0; i < 6; ++i) v[i] = fx::to_double(inv.qd_rad_s[i]);
  return v;
}
// twist as the fixed code sees it (after rounding to Q23)
ref::Vec6 quantised(const ref::Vec6& nu) {
  ref::Vec6 out;
  for (int i = 0; i < 6; ++i) out[i] = fx::to_double(fx::real(nu[i]));
  return out;
}

TEST(ForwardKinematicsFixed, WithinTwoTenthsOfAMillimetreAndOneMilliradian) {
  std::mt19937_64 rng(11);
  double worst_p = 0, worst_r = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    const Eigen::Matrix4d t = ref::fk(q);  // at the unquantised angles: input rounding counts
    const auto pose = kin::forward_kinematics<Fixed>(to_fixed(q));
    const Eigen::Vector3d p(fx::to_double(pose.p_m.x), fx::to_double(pose.p_m.y), fx::to_double(pose.p_m.z));
    worst_p = std::max(worst_p, (p - t.block<3, 1>(0, 3)).norm());
    Eigen::Matrix3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r(i, j) = fx::to_double(pose.R[i][j]);
    // angle of the rotation between the two frames, small-angle form (matrix need not be orthonormal)
    const Eigen::Matrix3d e = r * t.block<3, 3>(0, 0).transpose() - Eigen::Matrix3d::Identity();
    worst_r = std::max(worst_r, e.cwiseAbs().maxCoeff());
  }
  std::printf("fixed FK over %d poses: worst position error %.4f mm, worst rotation error %.4f mrad\n", kPoses,
              worst_p * 1e3, worst_r * 1e3);
  RecordProperty("fk_position_error_mm", std::to_string(worst_p * 1e3));
  RecordProperty("fk_rotation_error_mrad", std::to_string(worst_r * 1e3));
  EXPECT_LT(worst_p, 0.2e-3);
  EXPECT_LT(worst_r, 1e-3);
}

TEST(InverseJacobianFixed, WithinOneThousandthAwayFromSingularities) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> v(-0.15, 0.15), w(-0.8, 0.8);
  double worst = 0;
  int checked = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    ref::Vec6 nu;
    nu << v(rng), v(rng), v(rng), w(rng), w(rng), w(rng);
    const auto inv = kin::inverse_jacobian<Fixed>(to_fixed(q), to_fixed(nu));
    if (inv.status != kin::SingularStatus::ok) continue;
    const ref::Vec6 expected = ref::geometric_jacobian(quantised(q)).partialPivLu().solve(quantised(nu));
    worst = std::max(worst, (to_eigen(inv) - expected).norm() / expected.norm());
    ++checked;
  }
  std::printf("fixed J^-1 over %d poses with status ok: worst relative error %.2e\n", checked, worst);
  RecordProperty("jinv_relative_error", std::to_string(worst));
  EXPECT_GT(checked, kPoses / 2);
  EXPECT_LT(worst, 1e-3);
}

// Sweep one joint through the singular value of one factor: the status goes
// ok -> near_singular -> singular -> near_singular -> ok, the joint velocities stay bounded
// and no step between neighbouring samples jumps.
struct SweepResult {
  double max_qd = 0;
  double max_step = 0;
  bool saw[3] = {false, false, false};
};

SweepResult sweep(ref::Joints q, int joint, double centre, double half_width, const ref::Vec6& nu) {
  SweepResult r;
  ref::Vec6 previous = ref::Vec6::Zero();
  bool first = true;
  for (double d = -half_width; d <= half_width; d += 0.0005) {
    q[joint] = centre + d;
    const auto inv = kin::inverse_jacobian<Fixed>(to_fixed(q), to_fixed(nu));
    const ref::Vec6 qd = to_eigen(inv);
    r.saw[(int)inv.status] = true;
    r.max_qd = std::max(r.max_qd, qd.cwiseAbs().maxCoeff());
    if (!first) r.max_step = std::max(r.max_step, (qd - previous).cwiseAbs().maxCoeff());
    previous = qd;
    first = false;
  }
  return r;
}

// q4 at which the joint-5 origin crosses the base axis (R5 = 0), by bisection
double r5_zero_q4(const ref::Joints& q) {
  auto r5 = [&](double q4) {
    return arm::a1_m + std::cos(q[1]) * arm::a2_m + std::cos(q[1] + q[2]) * arm::a3_m +
           std::cos(q[1] + q[2] + q4) * arm::a4_m;
  };
  double lo = -1.5, hi = 1.5;
  EXPECT_LT(r5(lo) * r5(hi), 0) << "test pose must straddle R5 = 0";
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    ((r5(lo) < 0) == (r5(mid) < 0) ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

TEST(InverseJacobianFixed, BoundedAndContinuousThroughEachSingularFactor) {
  ref::Vec6 nu;
  nu << 0.15, 0.1, -0.1, 0.5, -0.4, 0.8;
  struct Case {
    const char* factor;
    ref::Joints q;
    int joint;
    double centre;
    double half_width;  // wide enough to leave the slow-down band
  };
  // the forearm folded back over the base: joint 4 then swings the wrist across the axis
  const ref::Joints over_base = {0.3, 1.2, 1.0, 0, 0.6, 0.2};
  const Case cases[] = {
      {"c5", {0.3, 0.4, 0.9, -0.5, 0, 0.2}, 4, arm::kPi / 2, 0.5},
      {"s3", {0.3, 0.4, 0, -0.5, 0.6, 0.2}, 2, 0.0, 0.5},
      {"r5", over_base, 3, r5_zero_q4(over_base), 1.4},
  };
  for (const auto& c : cases) {
    const SweepResult r = sweep(c.q, c.joint, c.centre, c.half_width, nu);
    std::printf("sweep through %s = 0: max |qd| %.2f rad/s, max step %.3f rad/s\n", c.factor, r.max_qd, r.max_step);
    EXPECT_TRUE(r.saw[0] && r.saw[1] && r.saw[2]) << c.factor;
    EXPECT_LT(r.max_qd, 100.0) << c.factor;
    EXPECT_LT(r.max_step, 2.0) << c.factor;
  }
}

// Without angular velocity J^-1 takes its translation path (seven fused products fewer): bit
// for bit the general path's result, over random poses (singular bands included) and twists.
TEST(InverseJacobianFixed, TranslationPathIsTheGeneralPathBitForBit) {
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> angle(-arm::kPi, arm::kPi), speed(-0.3, 0.3);
  int compared = 0, singular = 0;
  for (int i = 0; i < 200000; ++i) {
    ref::Joints q;
    for (int j = 0; j < 6; ++j) q[j] = angle(rng);
    const auto trig = kin::jacobian_trig<Fixed>(to_fixed(q));
    kin::Twist<Fixed> twist{{fx::real(speed(rng)), fx::real(speed(rng)), fx::real(speed(rng))},
                            {fx::Real{0}, fx::Real{0}, fx::Real{0}}};
    if (i % 4 == 0) twist.v_m_s.x = fx::Real{(int32_t)(rng() % 2001) - 1000};  // tiny and zero components
    const auto general = kin::inverse_jacobian_of<Fixed, true>(trig, twist);
    const auto translation = kin::inverse_jacobian_of<Fixed, false>(trig, twist);
    const auto dispatched = kin::inverse_jacobian<Fixed>(trig, twist);
    for (int j = 0; j < 6; ++j) {
      ASSERT_EQ(general.qd_rad_s[j].raw, translation.qd_rad_s[j].raw) << "case " << i << " joint " << j;
      ASSERT_EQ(general.qd_rad_s[j].raw, dispatched.qd_rad_s[j].raw) << "case " << i << " joint " << j;
    }
    ASSERT_EQ(general.status, translation.status);
    singular += general.status != kin::SingularStatus::ok;
    ++compared;
  }
  std::printf("%d cases bit-identical, %d of them near or in a singular band\n", compared, singular);
  EXPECT_GT(singular, 1000);
}

// The entry that takes w in the frame turned by q1 (the rotation modes' J^-1), against the
// base-frame entry given the same w turned into the base frame as the firmware did before
// (c1 wx - s1 wy, s1 wx + c1 wy, fused and floored: up to four steps of 2^-23 off each way and
// back), and both against the Eigen reference. The base-frame entry is the turned-frame one
// after w is turned back by q1, bit for bit.
TEST(InverseJacobianFixed, FrameTurnedByQ1EntryIsTheBaseFrameEntry) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> v(-0.15, 0.15), w(-0.8, 0.8);
  double worst_reference = 0, worst_base = 0, worst_apart = 0;
  int checked = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    const auto trig = kin::jacobian_trig<Fixed>(to_fixed(q));
    const kin::TwistQ1<Fixed> turned{{fx::real(v(rng)), fx::real(v(rng)), fx::real(v(rng))},
                                     {fx::real(w(rng)), fx::real(w(rng)), fx::real(w(rng))}};
    const auto& wq = turned.w_q1_rad_s;
    const kin::Twist<Fixed> base{turned.v_m_s,
                                 {fx::dot(trig.c1, wq.x, -trig.s1, wq.y), fx::dot(trig.s1, wq.x, trig.c1, wq.y), wq.z}};
    const auto q1_entry = kin::inverse_jacobian_q1<Fixed>(trig, turned);
    const auto base_entry = kin::inverse_jacobian<Fixed>(trig, base);
    const auto base_turned = kin::inverse_jacobian_q1<Fixed>(trig, kin::twist_q1<Fixed>(trig, base));
    for (int j = 0; j < 6; ++j) ASSERT_EQ(base_entry.qd_rad_s[j].raw, base_turned.qd_rad_s[j].raw) << "pose " << n;
    ASSERT_EQ(q1_entry.status, base_entry.status);
    if (q1_entry.status != kin::SingularStatus::ok) continue;
    // the reference: the base-frame twist from the turned one in double
    const double c1 = std::cos(fx::to_radians(fx::angle(q[0]))), s1 = std::sin(fx::to_radians(fx::angle(q[0])));
    const double wx = fx::to_double(wq.x), wy = fx::to_double(wq.y);
    ref::Vec6 nu;
    nu << fx::to_double(turned.v_m_s.x), fx::to_double(turned.v_m_s.y), fx::to_double(turned.v_m_s.z), c1 * wx - s1 * wy,
        s1 * wx + c1 * wy, fx::to_double(wq.z);
    const ref::Vec6 expected = ref::geometric_jacobian(quantised(q)).partialPivLu().solve(nu);
    worst_reference = std::max(worst_reference, (to_eigen(q1_entry) - expected).norm() / expected.norm());
    worst_base = std::max(worst_base, (to_eigen(base_entry) - expected).norm() / expected.norm());
    worst_apart = std::max(worst_apart, (to_eigen(q1_entry) - to_eigen(base_entry)).norm() / expected.norm());
    ++checked;
  }
  std::printf("J^-1 over %d poses, worst relative error: w in the frame turned by q1 %.2e, turned into the base "
              "frame first %.2e, the two apart %.2e\n",
              checked, worst_reference, worst_base, worst_apart);
  EXPECT_GT(checked, kPoses / 2);
  EXPECT_LT(worst_reference, 1e-3);
  EXPECT_LT(worst_base, 1e-3);
  EXPECT_LT(worst_apart, 1e-3);
}

// The wrist-axes entry (the rotation modes' J^-1) in fixed point against Eigen, w about the DH
// frame 5's axes: R1's shape (no x5 component), R2's (no z5) and all three; and a zero w takes
// the translation path, bit for bit the other entries'.
TEST(InverseJacobianFixed, WristAxesEntryWithinTheAccuracyGate) {
  std::mt19937_64 rng(36);
  std::uniform_real_distribution<double> v(-0.15, 0.15), w(-0.8, 0.8);
  double worst[3] = {0, 0, 0};
  int checked = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    const auto trig = kin::jacobian_trig<Fixed>(to_fixed(q));
    const int shape = n % 3;
    kin::TwistWrist<Fixed> twist{{fx::real(v(rng)), fx::real(v(rng)), fx::real(v(rng))},
                                 {fx::real(w(rng)), fx::real(w(rng)), fx::real(w(rng))}};
    if (shape == 0) twist.w5_rad_s.x = fx::Real{0};
    if (shape == 1) twist.w5_rad_s.z = fx::Real{0};
    const auto inv = kin::inverse_jacobian_wrist<Fixed>(trig, twist);
    const kin::TwistWrist<Fixed> still{twist.v_m_s, {fx::Real{0}, fx::Real{0}, fx::Real{0}}};
    const auto translation = kin::inverse_jacobian_wrist<Fixed>(trig, still);
    const auto other = kin::inverse_jacobian_q1<Fixed>(trig, kin::TwistQ1<Fixed>{twist.v_m_s, still.w5_rad_s});
    for (int j = 0; j < 6; ++j) ASSERT_EQ(translation.qd_rad_s[j].raw, other.qd_rad_s[j].raw) << "pose " << n;
    if (inv.status != kin::SingularStatus::ok) continue;
    const ref::Joints qq = quantised(q);
    const Eigen::Matrix3d r5 = ref::frames(qq)[4].block<3, 3>(0, 0);
    const auto& w5 = twist.w5_rad_s;
    ref::Vec6 nu;
    nu << fx::to_double(twist.v_m_s.x), fx::to_double(twist.v_m_s.y), fx::to_double(twist.v_m_s.z),
        fx::to_double(w5.x) * r5.col(0) + fx::to_double(w5.y) * r5.col(1) + fx::to_double(w5.z) * r5.col(2);
    const ref::Vec6 expected = ref::geometric_jacobian(qq).partialPivLu().solve(nu);
    worst[shape] = std::max(worst[shape], (to_eigen(inv) - expected).norm() / expected.norm());
    ++checked;
  }
  std::printf("J^-1 of w about the wrist axes over %d poses, worst relative error: without x5 %.2e, without z5 %.2e, "
              "all three %.2e\n",
              checked, worst[0], worst[1], worst[2]);
  EXPECT_GT(checked, kPoses / 2);
  for (double e : worst) EXPECT_LT(e, 1e-3);
}

}  // namespace
