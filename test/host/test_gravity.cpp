// The firmware's holding effort (firmware/core/gravity.h: a closed form in the arm's vertical
// plane, fixed point) against the simulator's gravity torques (sim/plant/arm_statics.cpp: every
// mass through the full modified-DH frames, double), over seeded random poses.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "config/gravity_config.h"
#include "core/base_inertia.h"
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

// a pose drawn within the joints' limits
std::array<double, 6> random_pose(std::mt19937& rng) {
  std::array<double, 6> q;
  for (int j = 0; j < 6; ++j) {
    std::uniform_real_distribution<double> in(arm::q_min_rad(j), arm::q_max_rad(j));
    q[j] = in(rng);
  }
  return q;
}

// the stall torque of each DC joint's drive at the joint, N m
double stall_nm(int d) { return config::kDcStallTorque_cNm / 100.0 * config::kDcGear_tenths[d] / 10.0; }

TEST(Gravity, HoldingEffortIsTheSimulatorsGravityOverTheStallTorque) {
  std::mt19937 rng(7);
  double worst = 0;
  for (int n = 0; n < 10000; ++n) {
    const std::array<double, 6> q = random_pose(rng);
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

// J5's gravity (core::wrist_gravity_q14) is the simulator's, as a fraction of the torque J5's
// motor plans its lifts with
TEST(Gravity, WristGravityIsTheSimulatorsOverJ5sPlannedTorque) {
  std::mt19937 rng(5);
  double worst = 0, largest = 0;
  for (int n = 0; n < 10000; ++n) {
    const std::array<double, 6> q = random_pose(rng);
    const plant::JointLoads loads = plant::joint_loads(q, true, true);
    const double firmware = core::wrist_gravity_q14(fixed_trig(q)) / 16384.0;
    const double expected = loads.gravity_nm[4] / core::gravity_detail::kJ5PlannedTorque_Nm;
    worst = std::max(worst, std::fabs(firmware - expected));
    largest = std::max(largest, std::fabs(expected));
    ASSERT_NEAR(firmware, expected, 0.002) << "pose " << n;
  }
  std::printf("wrist gravity about J5: worst error %.5f of J5's planned torque, largest %.3f of it\n", worst, largest);
}

// J1's stop plans with the firmware's inertia about the base axis: never below the simulator's
// (an under-estimate would ask J1's motor for more than it has), and not far above it.
TEST(Gravity, BaseInertiaBoundsTheSimulatorsFromAbove) {
  std::mt19937 rng(11);
  double worst_over = 0, worst_ratio = 1e9;
  for (int n = 0; n < 10000; ++n) {
    const std::array<double, 6> q = random_pose(rng);
    const double sim_gm2 = 1000 * plant::joint_loads(q, true, true).inertia_kgm2[0];
    const core::BaseLoad load = core::base_load(fixed_trig(q));
    const double fw_gm2 = load.inertia_gm2;
    // and the hand's distance from the base axis from above, within 12 % (max + min / 2)
    const plant::Frame hand = plant::arm_frames(q)[5];
    const double reach_mm = 1000 * std::hypot(hand.p[0], hand.p[1]);
    ASSERT_GE(load.hand_reach_mm + 1.0, reach_mm) << "pose " << n;
    EXPECT_LE(load.hand_reach_mm, 1.12 * reach_mm + 8) << "pose " << n;
    ASSERT_GE(fw_gm2, sim_gm2) << "pose " << n;
    // over by at most the links' own inertia (60) and the rounding of each distance up to 8 mm
    EXPECT_LE(fw_gm2, 1.04 * sim_gm2 + 80) << "pose " << n;
    worst_over = std::max(worst_over, fw_gm2 - sim_gm2);
    worst_ratio = std::min(worst_ratio, sim_gm2 / fw_gm2);
  }
  std::printf("base inertia: at most %.0f g m^2 over the simulator's, its share at least %.2f\n", worst_over, worst_ratio);
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
