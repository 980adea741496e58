// The closed forms in double against the independent Eigen reference.
#include <gtest/gtest.h>

#include "eigen_reference.h"
#include "kinematics/inverse_jacobian.h"

using namespace wmra;
using D = kin::Floating<double>;

namespace {

kin::JointAngles<D> to_angles(const ref::Joints& q) {
  kin::JointAngles<D> a;
  for (int i = 0; i < 6; ++i) a.q[i] = q[i];
  return a;
}

constexpr int kPoses = 10000;

TEST(ReferenceJacobian, GeometricAgreesWithCentralDifferences) {
  std::mt19937_64 rng(1);
  double worst = 0;
  for (int n = 0; n < 1000; ++n) {
    const auto q = ref::random_joints(rng);
    worst = std::max(worst, (ref::geometric_jacobian(q) - ref::numeric_jacobian(q)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-8);
}

TEST(ForwardKinematicsDouble, MatchesDhProduct) {
  std::mt19937_64 rng(2);
  double worst = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    const auto t = ref::fk(q);
    const auto pose = kin::forward_kinematics<D>(to_angles(q));
    worst = std::max({worst, std::abs(pose.p_m.x - t(0, 3)), std::abs(pose.p_m.y - t(1, 3)), std::abs(pose.p_m.z - t(2, 3))});
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(pose.R[r][c] - t(r, c)));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(ForwardKinematicsDouble, ZeroPoseIsStretchedAlongX) {
  const auto pose = kin::forward_kinematics<D>(to_angles({0, 0, 0, 0, 0, 0}));
  EXPECT_NEAR(pose.p_m.x, 1.077, 1e-12);
  EXPECT_NEAR(pose.p_m.y, 0.0, 1e-12);
  EXPECT_NEAR(pose.p_m.z, 0.187, 1e-12);
  EXPECT_NEAR(pose.R[0][2], 1.0, 1e-12);  // tool axis along +x
}

TEST(InverseJacobianDouble, MatchesEigenInverseOfGeometricJacobian) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> v(-0.15, 0.15), w(-0.8, 0.8);
  double worst = 0, worst_det = 0;
  int checked = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    const ref::Mat6 j = ref::geometric_jacobian(q);
    const auto trig = kin::arm_trig<D>(to_angles(q));
    if (kin::singular_status<D>(kin::singular_factors<D>(trig)) == kin::SingularStatus::singular) continue;
    ref::Vec6 nu;
    nu << v(rng), v(rng), v(rng), w(rng), w(rng), w(rng);
    const ref::Vec6 expected = j.partialPivLu().solve(nu);
    const auto inv = kin::inverse_jacobian<D>(trig, kin::Twist<D>{{nu[0], nu[1], nu[2]}, {nu[3], nu[4], nu[5]}});
    ref::Vec6 got;
    for (int i = 0; i < 6; ++i) got[i] = inv.qd_rad_s[i];
    worst = std::max(worst, (got - expected).norm() / expected.norm());
    worst_det = std::max(worst_det, std::abs(kin::determinant<D>(inv.factors) - j.determinant()) / std::abs(j.determinant()));
    ++checked;
  }
  EXPECT_GT(checked, kPoses * 3 / 4);  // the rest lie inside a damping band
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_det, 1e-9);
}

// The wrist-axes entry (the rotation modes' J^-1): w given about x5, y5, z5 as the DH frame 5's
// columns, with no x5 component (R1's shape), no z5 component (R2's) or all three (a base-frame
// command), and the base-frame twist turned into it by twist_wrist, all against Eigen.
TEST(InverseJacobianDouble, WristAxesEntryMatchesEigen) {
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> v(-0.15, 0.15), w(-0.8, 0.8);
  double worst = 0, worst_turned = 0;
  int checked = 0;
  for (int n = 0; n < kPoses; ++n) {
    const auto q = ref::random_joints(rng);
    const ref::Mat6 j = ref::geometric_jacobian(q);
    const auto trig = kin::arm_trig<D>(to_angles(q));
    if (kin::singular_status<D>(kin::singular_factors<D>(trig)) == kin::SingularStatus::singular) continue;
    const Eigen::Matrix3d r5 = ref::frames(q)[4].block<3, 3>(0, 0);
    kin::TwistWrist<D> twist{{v(rng), v(rng), v(rng)}, {w(rng), w(rng), w(rng)}};
    if (n % 3 == 0) twist.w5_rad_s.x = 0;
    if (n % 3 == 1) twist.w5_rad_s.z = 0;
    const Eigen::Vector3d w_base = twist.w5_rad_s.x * r5.col(0) + twist.w5_rad_s.y * r5.col(1) + twist.w5_rad_s.z * r5.col(2);
    ref::Vec6 nu;
    nu << twist.v_m_s.x, twist.v_m_s.y, twist.v_m_s.z, w_base;
    const ref::Vec6 expected = j.partialPivLu().solve(nu);
    const auto inv = kin::inverse_jacobian_wrist<D>(trig, twist);
    const auto turned = kin::inverse_jacobian_wrist<D>(
        trig, kin::twist_wrist<D>(trig, kin::Twist<D>{twist.v_m_s, {w_base[0], w_base[1], w_base[2]}}));
    ref::Vec6 got, got_turned;
    for (int i = 0; i < 6; ++i) got[i] = inv.qd_rad_s[i], got_turned[i] = turned.qd_rad_s[i];
    worst = std::max(worst, (got - expected).norm() / expected.norm());
    worst_turned = std::max(worst_turned, (got_turned - expected).norm() / expected.norm());
    ++checked;
  }
  EXPECT_GT(checked, kPoses * 3 / 4);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_turned, 1e-9);
}

// The thesis's test vector, recomputed from the correct Jacobian (column 5's signs fixed)
TEST(InverseJacobianDouble, DigestTestVector) {
  const ref::Joints q = {0.4, 0.3, -0.5, 0.9, 0.7, 0.2};
  const ref::Mat6 j = ref::geometric_jacobian(q);
  EXPECT_NEAR(j.determinant(), 3.6725e-2, 1e-6);
  const auto inv = kin::inverse_jacobian<D>(to_angles(q), kin::Twist<D>{{0.1, 0, 0}, {0, 0, 0}});
  EXPECT_NEAR(kin::determinant<D>(inv.factors), 3.6725e-2, 1e-6);
  ref::Vec6 qd;
  for (int i = 0; i < 6; ++i) qd[i] = inv.qd_rad_s[i];
  const ref::Vec6 nu = j * qd;
  EXPECT_NEAR(nu[0], 0.1, 1e-12);
  EXPECT_NEAR(nu.tail<5>().norm(), 0.0, 1e-12);
}

}  // namespace
