// Where S3's R2 turn (the hand about +x5 at 0.8 rad/s, the frame-6 origin still) is within the
// arm's reach: the joint rates of the turn from an independent Jacobian (Eigen, from the DH
// frames), integrated over the 1.6 s of the scenario, against what the firmware can give:
// each joint's speed limit, and for the DC joints the speed their drive plans at the load of
// the pose (update_holding in firmware/app/arm_control.cpp: the duty beyond the stiction's and
// the holding effort, less the PID's reserve, at the drive's full-duty speed), outside the
// singular slow-down bands, with the soft limits' slow-down zone (firmware/core/resolved_rate.h).
//
// The scenario's pose (turn_pose.h) is the one with the most margin on a grid of q2 (-40..130
// by 10 deg), q3 (-130..150 by 10), q4 (-155..155 by 10) and q5 (-75..75 by 15), q1 70 and q6 0:
// 741 of its 183,744 poses can turn for 1.6 s below 85 % of every limit, all with link 4
// folded back (|q4| >= 85 deg), which brings the payload near the base and lightens J2 and J3.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/joints_config.h"
#include "config/motion_config.h"
#include "core/gravity.h"
#include "eigen_reference.h"
#include "kinematics/arm_model.h"
#include "kinematics/forward_kinematics.h"
#include "turn_pose.h"

using namespace wmra;

namespace {

constexpr double kWrist_rad_s = 0.8, kTurn_s = 1.6, kStep_s = 0.005;
constexpr double kSoftMargin_rad = config::kSoftLimitMargin_deg * M_PI / 180, kSoftZone_rad = config::kSoftLimitZone_deg * M_PI / 180;

struct Reach {
  double worst_use = 0;       // the largest |qd_j| / what joint j can give, over joints and time
  int worst_joint = -1;
  double over_at_s = -1;      // when a joint first needed more than it can give (-1: never)
  bool singular_band = false;  // a singular factor entered its slow-down band
};

// the speed a DC joint's drive plans each way at this pose's load (arm_control.cpp update_holding)
double planned_rad_s(int d, const ref::Joints& q, bool positive) {
  kin::JointAngles<kin::Fixed> qf;
  for (int j = 0; j < 6; ++j) qf.q[j] = fx::angle(q[j]);
  const double holding = core::holding_effort(kin::arm_trig<kin::Fixed>(qf)).duty_q15[d] / 32768.0;
  const double usable = (1000 - config::kDcMinDuty_permille) / 1000.0;
  const double lifting = positive ? std::max(holding, 0.0) : std::max(-holding, 0.0);
  return std::max(usable - lifting, 0.0) * (1000 - config::kDcDutyReserve_permille) / 1000.0 *
         config::kDcFullDutySpeed_crad_s[d] / 100.0;
}

Reach turn_about_x5(const double (&q_deg)[6]) {
  ref::Joints q;
  for (int j = 0; j < 6; ++j) q[j] = q_deg[j] * M_PI / 180;
  Reach r;
  for (double t = 0; t < kTurn_s; t += kStep_s) {
    ref::Mat6 twist_to_q = ref::geometric_jacobian(q).inverse();
    Eigen::Matrix<double, 6, 1> twist;
    twist << Eigen::Vector3d::Zero(), kWrist_rad_s * ref::frames(q)[4].block<3, 1>(0, 0);
    const Eigen::Matrix<double, 6, 1> qd = twist_to_q * twist;
    for (int j = 0; j < 6; ++j) {
      const double limit = config::kJointSpeedLimit_crad_s[j] / 100.0;
      double can = limit;
      // within the soft-limit zone towards the stop, the limit falls linearly to 0 at the stop
      const double to_stop = qd[j] > 0 ? arm::q_max_rad(j) - kSoftMargin_rad - q[j] : q[j] - arm::q_min_rad(j) - kSoftMargin_rad;
      if (to_stop < kSoftZone_rad) can = std::max(to_stop, 0.0) / kSoftZone_rad * limit;
      if (j >= 1 && j <= 3) can = std::min(can, planned_rad_s(j - 1, q, qd[j] > 0));
      if (std::fabs(qd[j]) / can > r.worst_use) {
        r.worst_use = std::fabs(qd[j]) / can;
        r.worst_joint = j;
      }
      if (r.worst_use > 1 && r.over_at_s < 0) r.over_at_s = t;
    }
    const double r5 = arm::a1_m + std::cos(q[1]) * arm::a2_m + std::cos(q[1] + q[2]) * arm::a3_m +
                      std::cos(q[1] + q[2] + q[3]) * arm::a4_m;
    if (std::fabs(std::cos(q[4])) < to_double(arm::kSingularBands.slow_c5) ||
        std::fabs(std::sin(q[2])) < to_double(arm::kSingularBands.slow_s3) || std::fabs(r5) < to_double(arm::kSingularBands.slow_r5_m))
      r.singular_band = true;
    for (int j = 0; j < 6; ++j) q[j] += qd[j] * kStep_s;
  }
  return r;
}

TEST(TurnReach, R2FromTheScenarioPoseIsWithinEveryLimit) {
  const Reach r = turn_about_x5(test::kR2Pose_deg);
  std::printf("R2 from the scenario pose: at most %.2f of J%d's speed\n", r.worst_use, r.worst_joint + 1);
  EXPECT_LT(r.worst_use, 0.85);
  EXPECT_FALSE(r.singular_band);
}

// At the ready pose the turn needs J2 to lift arm and payload faster than its drive can and J4
// beyond its limit: the firmware must slow it (S3-R2 at the ready pose in test_motion_scenarios).
TEST(TurnReach, R2FromTheReadyPoseIsOutOfReach) {
  double ready_deg[6];
  for (int j = 0; j < 6; ++j) ready_deg[j] = config::kReadyPose_deg[j];
  const Reach r = turn_about_x5(ready_deg);
  std::printf("R2 from the ready pose: over a joint's limit after %.3f s\n", r.over_at_s);
  EXPECT_GE(r.over_at_s, 0);
  EXPECT_LT(r.over_at_s, 0.5) << "within the first of the scenario's 1.6 s";
}

}  // namespace
