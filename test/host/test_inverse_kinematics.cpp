// Inverse kinematics round trips in the IKFast style: for 10,000 seeded random poses within
// the joint limits, the generating joint angles must be among the solutions (no missed
// solution) and every solution must reproduce the pose (no wrong solution).
#include <gtest/gtest.h>

#include <cstdio>

#include "eigen_reference.h"
#include "kinematics/inverse_kinematics.h"

using namespace wmra;
using D = kin::Floating<double>;

namespace {

kin::Pose<D> pose_of(const ref::Joints& q) {
  const Eigen::Matrix4d t = ref::fk(q);
  kin::Pose<D> p;
  p.p_m = {t(0, 3), t(1, 3), t(2, 3)};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.R[i][j] = t(i, j);
  return p;
}

double pose_distance(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(InverseKinematicsDouble, RoundTripsWithNoMissedOrWrongSolutions) {
  std::mt19937_64 rng(21);
  int missed = 0, wrong = 0, total_solutions = 0;
  const int poses = 10000;
  for (int n = 0; n < poses; ++n) {
    const auto q = ref::random_joints(rng);
    const Eigen::Matrix4d target = ref::fk(q);
    const auto sols = kin::inverse_kinematics<D>(pose_of(q));
    ASSERT_EQ(sols.status, kin::IkStatus::ok);
    bool found = false;
    for (int k = 0; k < sols.count; ++k) {
      ref::Joints s;
      for (int j = 0; j < 6; ++j) s[j] = sols.q[k].q[j];
      if (pose_distance(ref::fk(s), target) > 1e-9) ++wrong;
      double diff = 0;
      for (int j = 0; j < 6; ++j) diff = std::max(diff, std::abs(s[j] - q[j]));
      found = found || diff < 1e-6;
    }
    missed += !found;
    total_solutions += sols.count;
  }
  std::printf("IK over %d poses: %d missed, %d wrong, %.2f solutions per pose\n", poses, missed, wrong,
              (double)total_solutions / poses);
  EXPECT_EQ(missed, 0);
  EXPECT_EQ(wrong, 0);
}

TEST(InverseKinematicsDouble, DigestTestVectorHasBothElbows) {
  const ref::Joints q = {0.4, 0.3, -0.5, 0.9, 0.7, 0.2};
  const auto sols = kin::inverse_kinematics<D>(pose_of(q));
  bool up = false, flipped = false;
  for (int k = 0; k < sols.count; ++k) {
    const double* s = sols.q[k].q;
    if (std::abs(s[1] - 0.3) < 1e-6 && std::abs(s[2] + 0.5) < 1e-6 && std::abs(s[5] - 0.2) < 1e-6) up = true;
    if (std::abs(s[1] + 0.2) < 2e-3 && std::abs(s[2] - 0.5) < 2e-3 && std::abs(s[3] - 0.4) < 2e-3) flipped = true;
  }
  EXPECT_TRUE(up);
  EXPECT_TRUE(flipped);  // (0.4, -0.2, 0.5, 0.4, 0.7, 0.2) in the digest, to its printed digits
}

TEST(InverseKinematicsDouble, UnreachableAndDegeneratePosesSaySo) {
  kin::Pose<D> far = pose_of({0, 0, 0.5, 0, 0.3, 0});
  far.p_m.x += 2.0;
  EXPECT_EQ(kin::inverse_kinematics<D>(far).status, kin::IkStatus::unreachable);
  EXPECT_EQ(kin::inverse_kinematics<D>(far).count, 0);
  // wrist point on the base axis: q1 is free. Keep an orientation, put p5 = (0, 0, 0.5).
  kin::Pose<D> over = pose_of({0.2, 1.2, 1.0, 0.6, 0.3, 0});
  over.p_m = {over.R[0][2] * arm::d6_m, over.R[1][2] * arm::d6_m, 0.5 + over.R[2][2] * arm::d6_m};
  EXPECT_EQ(kin::inverse_kinematics<D>(over).status, kin::IkStatus::degenerate);
  EXPECT_EQ(kin::inverse_kinematics<D>(over).count, 0);
}

TEST(InverseKinematicsDouble, ClosestSolutionIsTheGeneratingPose) {
  std::mt19937_64 rng(22);
  for (int n = 0; n < 1000; ++n) {
    const auto q = ref::random_joints(rng);
    const auto sols = kin::inverse_kinematics<D>(pose_of(q));
    kin::JointAngles<D> current;
    for (int j = 0; j < 6; ++j) current.q[j] = q[j];
    const int k = kin::closest_solution<D>(sols, current);
    ASSERT_GE(k, 0);
    for (int j = 0; j < 6; ++j) EXPECT_NEAR(sols.q[k].q[j], q[j], 1e-6);
  }
}

}  // namespace
