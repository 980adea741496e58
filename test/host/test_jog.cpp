// The jog's speed (firmware/core/jog.h): the request capped, a stepper before homing slower, never
// into a closed switch of the joint, and where the angle is known the soft limits' slow-down to a
// stop at the soft limit and the drives' speeds.
#include <gtest/gtest.h>

#include "core/jog.h"

using namespace wmra;
using kin::Fixed;

namespace {

constexpr core::MotionLimits kLimits = core::motion_limits();
const core::DriveSpeeds kDrives = core::drives_at_speed_limits(kLimits);

kin::JointAngles<Fixed> pose_deg(double q1, double q2, double q3, double q4, double q5, double q6) {
  const double q[6] = {q1, q2, q3, q4, q5, q6};
  kin::JointAngles<Fixed> a;
  for (int i = 0; i < 6; ++i) a.q[i] = fx::angle(arm::deg_to_rad(q[i]));
  return a;
}
const kin::JointAngles<Fixed> kMidRange = pose_deg(0, 45, -30, 0, 0, 0);

double mrad_s(fx::Real r) { return r.raw / 8388.608; }

TEST(Jog, TheRequestWithinTheCapEachWay) {
  for (uint8_t j = 0; j < 6; ++j) {
    EXPECT_NEAR(mrad_s(core::jog_speed(j, 60, true, kMidRange, kLimits, kDrives, 0)), 60, 0.1) << "J" << j + 1;
    EXPECT_NEAR(mrad_s(core::jog_speed(j, -60, true, kMidRange, kLimits, kDrives, 0)), -60, 0.1) << "J" << j + 1;
    EXPECT_NEAR(mrad_s(core::jog_speed(j, 1000, true, kMidRange, kLimits, kDrives, 0)), config::kJogSpeed_mrad_s, 0.1);
    EXPECT_NEAR(mrad_s(core::jog_speed(j, -32768, true, kMidRange, kLimits, kDrives, 0)), -config::kJogSpeed_mrad_s, 0.1);
    EXPECT_EQ(core::jog_speed(j, 0, true, kMidRange, kLimits, kDrives, 0).raw, 0);
  }
}

// before homing a stepper's count is not its angle: slower, and the soft limits do not apply (the
// count may say anything), only its switches and a travel of kJogUnhomedTravel_deg from where
// its count stood at power-up
TEST(Jog, AStepperBeforeHomingSlowerAndStoppedByItsSwitchesAndItsTravel) {
  const kin::JointAngles<Fixed> at_limit_by_count = pose_deg(89, 45, -30, 0, 89, 0);
  const fx::Angle origin = fx::angle(arm::deg_to_rad(80));  // the count stood at 80 deg at power-up
  EXPECT_NEAR(mrad_s(core::jog_speed(0, 100, false, at_limit_by_count, kLimits, kDrives, 0, origin)), config::kJogUnhomedStepperSpeed_mrad_s, 0.1);
  EXPECT_NEAR(mrad_s(core::jog_speed(4, 100, false, at_limit_by_count, kLimits, kDrives, 0, origin)), config::kJogUnhomedStepperSpeed_mrad_s, 0.1);
  // J6 (no switch) up to the travel each way from its origin, and back from beyond it
  const double travel = config::kJogUnhomedTravel_deg;
  const fx::Angle zero{0};
  EXPECT_GT(core::jog_speed(5, 100, false, pose_deg(0, 45, -30, 0, 0, travel - 1), kLimits, kDrives, 0, zero).raw, 0);
  EXPECT_EQ(core::jog_speed(5, 100, false, pose_deg(0, 45, -30, 0, 0, travel + 0.1), kLimits, kDrives, 0, zero).raw, 0);
  EXPECT_LT(core::jog_speed(5, -100, false, pose_deg(0, 45, -30, 0, 0, travel + 0.1), kLimits, kDrives, 0, zero).raw, 0);
  EXPECT_EQ(core::jog_speed(5, -100, false, pose_deg(0, 45, -30, 0, 0, -travel - 0.1), kLimits, kDrives, 0, zero).raw, 0);
  EXPECT_EQ(core::jog_speed(0, 100, false, pose_deg(80 + travel + 0.1, 45, -30, 0, 0, 0), kLimits, kDrives, 0, origin).raw, 0);
  // where J6's angle is known (recorded) its soft limits apply instead, not the travel
  EXPECT_GT(core::jog_speed(5, 100, true, pose_deg(0, 45, -30, 0, 0, 300), kLimits, kDrives, 0).raw, 0);
  EXPECT_EQ(core::jog_speed(5, 100, true, pose_deg(0, 45, -30, 0, 0, 357), kLimits, kDrives, 0).raw, 0);
  EXPECT_EQ(core::jog_speed(0, 100, false, kMidRange, kLimits, kDrives, 1u << 1).raw, 0);  // J1's high switch closed
  EXPECT_LT(core::jog_speed(0, -100, false, kMidRange, kLimits, kDrives, 1u << 1).raw, 0);  // away from it
  EXPECT_EQ(core::jog_speed(4, -100, false, kMidRange, kLimits, kDrives, 1u << 8).raw, 0);  // J5's low switch
  EXPECT_GT(core::jog_speed(4, 100, false, kMidRange, kLimits, kDrives, 1u << 8).raw, 0);
}

TEST(Jog, NeverIntoAClosedSwitchOfTheJointEvenWhereItsAngleIsKnown) {
  for (uint8_t j = 0; j < 5; ++j) {
    const uint16_t low = (uint16_t)(1u << (2 * j)), high = (uint16_t)(1u << (2 * j + 1));
    EXPECT_EQ(core::jog_speed(j, -50, true, kMidRange, kLimits, kDrives, low).raw, 0) << "J" << j + 1;
    EXPECT_EQ(core::jog_speed(j, 50, true, kMidRange, kLimits, kDrives, high).raw, 0) << "J" << j + 1;
    EXPECT_GT(core::jog_speed(j, 50, true, kMidRange, kLimits, kDrives, low).raw, 0) << "J" << j + 1;
    // another joint's switch does not stop it
    EXPECT_GT(core::jog_speed(j, 50, true, kMidRange, kLimits, kDrives, (uint16_t)(0x3FF & ~(low | high))).raw, 0);
  }
  EXPECT_GT(core::jog_speed(5, 50, true, kMidRange, kLimits, kDrives, 0x7FF).raw, 0);  // J6: its zero switch is no limit
}

// a known angle: slowed over the soft-limit zone, stopped at the soft limit, free to leave it
TEST(Jog, SlowsToAStopAtTheSoftLimit) {
  const double margin = config::kSoftLimitMargin_deg;
  // J3 (DC, its pot) 1 deg inside its soft limit at 160 - margin
  const kin::JointAngles<Fixed> near = pose_deg(0, 45, 160 - margin - 1, 0, 0, 0);
  const double towards = mrad_s(core::jog_speed(2, 100, true, near, kLimits, kDrives, 0));
  EXPECT_GT(towards, 0);
  EXPECT_LT(towards, 100);
  const kin::JointAngles<Fixed> at = pose_deg(0, 45, 160 - margin, 0, 0, 0);
  EXPECT_NEAR(mrad_s(core::jog_speed(2, 100, true, at, kLimits, kDrives, 0)), 0, 0.5);
  EXPECT_NEAR(mrad_s(core::jog_speed(2, -100, true, at, kLimits, kDrives, 0)), -100, 0.1);
  // a drive that cannot lift its load slows the jog as it does the stick
  core::DriveSpeeds weak = kDrives;
  weak.positive_rad_s[1] = fx::real(0.02);
  EXPECT_NEAR(mrad_s(core::jog_speed(1, 100, true, kMidRange, kLimits, weak, 0)), 20, 0.5);
}

}  // namespace
