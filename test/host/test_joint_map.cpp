// firmware/core/joint_map.h: the stepper joints' angle <-> step conversions over each joint's
// range, against exact arithmetic.
#include <gtest/gtest.h>

#include <cmath>

#include "config/joints_config.h"
#include "core/joint_map.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;

constexpr int kStepperJoint[3] = {0, 4, 5};  // J1, J5, J6 (config::kStepsPerJointTurn order)

// A reference taken from the step count (entering running, after homing or a joint move) must
// ask for no step: steps(angle(n)) == n for every step count within the joint's limits.
TEST(StepperMap, StepsOfTheAngleOfAStepCountIsThatCount) {
  for (int i = 0; i < 3; ++i) {
    const uint32_t per_turn = config::kStepsPerJointTurn[i];
    const core::StepperMap map = core::StepperMap::make(per_turn);
    const int j = kStepperJoint[i];
    const int32_t lo = (int32_t)std::floor(arm::q_min_rad(j) / (2 * arm::kPi) * per_turn);
    const int32_t hi = (int32_t)std::ceil(arm::q_max_rad(j) / (2 * arm::kPi) * per_turn);
    int32_t wrong = 0, first_wrong = 0;
    int32_t inexact = 0;  // angles further from the exact one than a count and Scale's 2^-14
    for (int32_t n = lo; n <= hi; ++n) {
      const fx::Angle a = map.angle(n);
      const double exact = (double)n * fx::kAngleTurn / per_turn;
      if (std::fabs(a.raw - exact) > 1 + std::fabs(exact) / 16384) ++inexact;
      if (map.steps(a) != n && wrong++ == 0) first_wrong = n;
    }
    EXPECT_EQ(wrong, 0) << "J" << j + 1 << ", first at " << first_wrong << " steps";
    EXPECT_EQ(inexact, 0) << "J" << j + 1;
  }
}

// steps() is the nearest step to any angle, not the one below it
TEST(StepperMap, StepsOfAnAngleIsTheNearestStep) {
  for (int i = 0; i < 3; ++i) {
    const uint32_t per_turn = config::kStepsPerJointTurn[i];
    const core::StepperMap map = core::StepperMap::make(per_turn);
    const int j = kStepperJoint[i];
    const int32_t lo = (int32_t)(arm::q_min_rad(j) / (2 * arm::kPi) * fx::kAngleTurn);
    const int32_t hi = (int32_t)(arm::q_max_rad(j) / (2 * arm::kPi) * fx::kAngleTurn);
    // excess: beyond half a step, one angle count (half_step is whole counts) and Scale's 2^-14
    double worst_steps = 0, worst_excess = 0;
    for (int32_t a = lo; a <= hi; a += 7) {
      const double exact = (double)a * per_turn / fx::kAngleTurn;
      const double error = std::fabs(map.steps(fx::Angle{a}) - exact);
      worst_steps = std::max(worst_steps, error);
      worst_excess = std::max(worst_excess, error - 0.5 - (double)per_turn / fx::kAngleTurn - std::fabs(exact) / 16384);
    }
    EXPECT_LE(worst_excess, 0) << "J" << j + 1 << ", worst " << worst_steps << " steps";
    EXPECT_GE(worst_steps, 0.45) << "J" << j + 1 << ": a stride of 7 counts meets half-step points";
  }
}

}  // namespace
