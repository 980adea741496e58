// Inverse kinematics round trips in the IKFast style: for 10,000 seeded random poses within
// the joint limits, the generating joint angles must be among the solutions (no missed
// solution) and every solution must reproduce the pose (no wrong solution). The fixed-point
// instantiation must put the hand within 0.5 mm of the target.
#include <gtest/gtest.h>

#include <cstdio>

#include "eigen_reference.h"
#include "kinematics/inverse_kinematics.h"

using namespace wmra;
using D = kin::Floating<double>;
using kin::Fixed;

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
  EXPECT_TRUE(flipped);  // (0.4, -0.2, 0.5, 0.4, 0.7, 0.2) the test vector's other elbow, to its printed digits
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

kin::Pose<Fixed> fixed_pose_of(const Eigen::Matrix4d& t) {
  kin::Pose<Fixed> p;
  p.p_m = {fx::real(t(0, 3)), fx::real(t(1, 3)), fx::real(t(2, 3))};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.R[i][j] = fx::unit(t(i, j));
  return p;
}

ref::Joints radians(const kin::JointAngles<Fixed>& a) {
  ref::Joints q;
  for (int j = 0; j < 6; ++j) q[j] = fx::to_radians(a.q[j]);
  return q;
}

// Away from the singular factors (outside the bands where the firmware slows down, as for the
// J^-1 accuracy) and from the joint limits the solutions are well conditioned, so there the
// fixed-point IK must find the generating pose and as many solutions as double. Nearer a
// singular pose the rounding of the target (Q15 rotation entries) moves the solution in
// joint space by more, while the hand stays within the position bound.
bool well_conditioned(const ref::Joints& q) {
  const double margin = 0.01;  // rad from every limit
  for (int j = 0; j < 6; ++j)
    if (q[j] < arm::q_min_rad(j) + margin || q[j] > arm::q_max_rad(j) - margin) return false;
  const double r5 = arm::a1_m + std::cos(q[1]) * arm::a2_m + std::cos(q[1] + q[2]) * arm::a3_m +
                    std::cos(q[1] + q[2] + q[3]) * arm::a4_m;
  const auto& bands = arm::kSingularBands;
  return std::abs(std::sin(q[2])) > to_double(bands.slow_s3) && std::abs(std::cos(q[4])) > to_double(bands.slow_c5) &&
         std::abs(r5) > to_double(bands.slow_r5_m);
}

TEST(InverseKinematicsFixed, WithinHalfAMillimetreAndFindsTheGeneratingPose) {
  std::mt19937_64 rng(23);
  const int poses = 10000;
  double worst_mm = 0, worst_rot = 0;
  int checked = 0, missed = 0, count_differs = 0, no_solution = 0;
  for (int n = 0; n < poses; ++n) {
    const auto q = ref::random_joints(rng);
    const Eigen::Matrix4d target = ref::fk(q);
    const auto sols = kin::inverse_kinematics<Fixed>(fixed_pose_of(target));
    bool found = false;
    for (int k = 0; k < sols.count; ++k) {
      const auto s = radians(sols.q[k]);
      const Eigen::Matrix4d t = ref::fk(s);
      worst_mm = std::max(worst_mm, (t.block<3, 1>(0, 3) - target.block<3, 1>(0, 3)).norm() * 1e3);
      worst_rot = std::max(worst_rot, (t.block<3, 3>(0, 0) - target.block<3, 3>(0, 0)).cwiseAbs().maxCoeff());
      double diff = 0;
      for (int j = 0; j < 6; ++j) diff = std::max(diff, std::abs(s[j] - q[j]));
      found = found || diff < 2e-3;
    }
    no_solution += sols.count == 0;
    if (!well_conditioned(q)) continue;
    ++checked;
    missed += !found;
    count_differs += sols.count != kin::inverse_kinematics<D>(pose_of(q)).count;
  }
  std::printf("fixed IK over %d poses: worst position error %.4f mm, worst rotation entry error %.2e; "
              "%d well-conditioned: %d missed, %d with another solution count; %d poses without a solution\n",
              poses, worst_mm, worst_rot, checked, missed, count_differs, no_solution);
  RecordProperty("ik_fixed_position_error_mm", std::to_string(worst_mm));
  EXPECT_LT(worst_mm, 0.5);
  EXPECT_LT(worst_rot, 1e-3);
  EXPECT_GT(checked, poses / 2);
  EXPECT_EQ(missed, 0);
  EXPECT_EQ(count_differs, 0);
}

TEST(InverseKinematicsFixed, UnreachableAndDegeneratePosesSaySo) {
  kin::Pose<Fixed> far = fixed_pose_of(ref::fk({0, 0, 0.5, 0, 0.3, 0}));
  far.p_m.x = fx::real(2.0);
  EXPECT_EQ(kin::inverse_kinematics<Fixed>(far).status, kin::IkStatus::unreachable);
  EXPECT_EQ(kin::inverse_kinematics<Fixed>(far).count, 0);
  kin::Pose<Fixed> over = fixed_pose_of(ref::fk({0.2, 1.2, 1.0, 0.6, 0.3, 0}));
  over.p_m = {fx::to_real(over.R[0][2] * kin::ArmConstants<Fixed>::d6),
              fx::to_real(over.R[1][2] * kin::ArmConstants<Fixed>::d6), fx::real(0.5)};
  EXPECT_EQ(kin::inverse_kinematics<Fixed>(over).status, kin::IkStatus::degenerate);
  EXPECT_EQ(kin::inverse_kinematics<Fixed>(over).count, 0);
}

TEST(InverseKinematicsFixed, ClosestSolutionIsTheGeneratingPose) {
  std::mt19937_64 rng(24);
  for (int n = 0; n < 1000; ++n) {
    const auto q = ref::random_joints(rng);
    if (!well_conditioned(q)) continue;
    const auto sols = kin::inverse_kinematics<Fixed>(fixed_pose_of(ref::fk(q)));
    kin::JointAngles<Fixed> current;
    for (int j = 0; j < 6; ++j) current.q[j] = fx::angle(q[j]);
    const int k = kin::closest_solution<Fixed>(sols, current);
    ASSERT_GE(k, 0);
    const auto s = radians(sols.q[k]);
    for (int j = 0; j < 6; ++j) EXPECT_NEAR(s[j], q[j], 2e-3);
  }
}

}  // namespace
