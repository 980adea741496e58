// The firmware's holding effort (firmware/core/gravity.h: a closed form in the arm's vertical
// plane, fixed point) against the simulator's gravity torques (sim/plant/arm_statics.cpp: every
// mass through the full modified-DH frames, double), over seeded random poses.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "config/gravity_config.h"
#include "core/gravity.h"
#include "kinematics/arm_model.h"
#include "kinematics/forward_kinematics.h"
#include "plant/arm_statics.h"

namespace {

using namespace wmra;

kin::ArmTrig<kin::Fixed> fixed_trig(const std::array<double, 6>& q) {
  kin::JointAngles<kin::Fixed> a;
  for (int j = 0; j < 6; ++j) a.q[j] = fx::angle(q[j]);
  kin::ArmTrig<kin::Fixed> t;
  kin::fill_chain_trig<kin::Fixed>(a, t);
  return t;
}

// the stall torque of each DC joint's drive at the joint, N m
double stall_nm(int d) { return config::kDcStallTorque_cNm / 100.0 * config::kDcGear_tenths[d] / 10.0; }

TEST(Gravity, HoldingEffortIsTheSimulatorsGravityOverTheStallTorque) {
  std::mt19937 rng(7);
  double worst = 0;
  for (int n = 0; n < 10000; ++n) {
    std::array<double, 6> q;
    for (int j = 0; j < 6; ++j) {
      std::uniform_real_distribution<double> in(arm::q_min_rad(j), arm::q_max_rad(j));
      q[j] = in(rng);
    }
    const plant::JointLoads loads = plant::joint_loads(q, true, true);
    const core::HoldingEffort h = core::holding_effort(fixed_trig(q));
    for (int d = 0; d < 3; ++d) {
      const double expected = -loads.gravity_nm[d + 1] / stall_nm(d);
      const double error = std::fabs(h.duty_q15[d] / 32768.0 - expected);
      worst = std::max(worst, error);
      ASSERT_LE(error, 0.001) << "J" << d + 2 << " at pose " << n << ": " << h.duty_q15[d] / 32768.0 << " vs "
                              << expected;
    }
  }
  std::printf("holding effort: worst error %.5f of full duty over 10,000 poses\n", worst);
}

TEST(Gravity, StretchedForwardJ2HoldsMostAndJ4Least) {
  const core::HoldingEffort h = core::holding_effort(fixed_trig({0, 0, 0, 0, 0, 0}));
  EXPECT_GT(h.duty_q15[0], h.duty_q15[1]);
  EXPECT_GT(h.duty_q15[1], h.duty_q15[2]);
  EXPECT_GT(h.duty_q15[2], 0);  // the hand pulls every joint down: the drives push positive (up)
}

TEST(Gravity, ASelfLockingJointGetsTheEffortOnlyWhileItLifts) {
  static_assert(config::kDcSelfLocking, "the arm's worms do not back-drive");
  EXPECT_EQ(core::lifting_effort_q15(8000, 5), 8000);
  EXPECT_EQ(core::lifting_effort_q15(8000, -5), 0);
  EXPECT_EQ(core::lifting_effort_q15(-8000, -5), -8000);
  EXPECT_EQ(core::lifting_effort_q15(-8000, 5), 0);
  EXPECT_EQ(core::lifting_effort_q15(8000, 0), 0);
}

}  // namespace
