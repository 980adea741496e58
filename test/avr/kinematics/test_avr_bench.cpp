// Cycle budgets of the kinematics on the ATmega2560, measured in simavr (deterministic).
#include <gtest/gtest.h>

#include <string>

#include "sim_run.h"

namespace {

using wmra::simrun::Timing;

class AvrBench : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    text_ = wmra::simrun::timings_of(AVR_RUN, BENCH_ELF, std::string(BENCH_OUT) + "/bench_ctest.json");
  }
  static Timing get(const std::string& name) { return wmra::simrun::timing(text_, name); }
  static std::string text_;
};
std::string AvrBench::text_;

TEST_F(AvrBench, FixedInverseJacobianIsFiveTimesFasterThanFloat) {
  const Timing fixed = get("jinv_fixed"), flt = get("jinv_float");
  ASSERT_GT(fixed.mean, 0);
  ASSERT_GT(flt.mean, 0);
  RecordProperty("jinv_fixed_cycles", std::to_string(fixed.mean));
  RecordProperty("jinv_float_cycles", std::to_string(flt.mean));
  EXPECT_GE(flt.mean / fixed.mean, 5.0);
}

// The gate (docs/performance.md): forward kinematics (pose of frame 6 from the joint angles) <= 2,500 cycles,
// gated on the worst case over the pose set
TEST_F(AvrBench, FixedForwardKinematicsWithinBudget) {
  const Timing fk = get("fk_fixed");
  ASSERT_GT(fk.max, 0);
  RecordProperty("fk_fixed_max_cycles", std::to_string(fk.max));
  EXPECT_LE(fk.max, 2500);
}

// The gate (docs/performance.md): inverse kinematics, all branches, <= 15,000 cycles (worst case over the set)
TEST_F(AvrBench, FixedInverseKinematicsWithinBudget) {
  const Timing ik = get("ik_fixed");
  ASSERT_GT(ik.max, 0);
  RecordProperty("ik_fixed_max_cycles", std::to_string(ik.max));
  EXPECT_LE(ik.max, 15000);
}

// The gate (docs/performance.md): the inverse Jacobian from the joint angles (its sines and cosines included)
// <= 3,000 cycles, gated on the worst case over the pose set
TEST_F(AvrBench, FixedInverseJacobianWithinBudget) {
  const Timing jinv = get("jinv_fixed");
  ASSERT_GT(jinv.max, 0);
  RecordProperty("jinv_fixed_max_cycles", std::to_string(jinv.max));
  EXPECT_LE(jinv.max, 3000);
}

}  // namespace
