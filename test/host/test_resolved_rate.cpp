// The firmware's resolved-rate core (firmware/core/resolved_rate.h) and the wrist axes that
// the rotation modes use: one common scale that keeps the hand's direction, joint speeds
// within their limits, the slow-down towards a singular factor that still lets the arm
// back out, and soft joint limits.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/joint_acceleration.h"
#include "core/resolved_rate.h"
#include "core/stick_twist.h"
#include "core/stream_limit.h"
#include "eigen_reference.h"
#include "kinematics/wrist_frame.h"

using namespace wmra;
using kin::Fixed;
using D = kin::Floating<double>;

namespace {

constexpr core::MotionLimits kLimits = core::motion_limits();

kin::JointAngles<Fixed> to_fixed(const ref::Joints& q) {
  kin::JointAngles<Fixed> a;
  for (int i = 0; i < 6; ++i) a.q[i] = fx::angle(q[i]);
  return a;
}

kin::Twist<Fixed> twist(double vx, double vy, double vz, double wx, double wy, double wz) {
  return {{fx::real(vx), fx::real(vy), fx::real(vz)}, {fx::real(wx), fx::real(wy), fx::real(wz)}};
}

// a base-frame twist, its w about the wrist axes as resolved_rate takes it
core::JointRates rates(const ref::Joints& q, const kin::Twist<Fixed>& t) {
  const auto qf = to_fixed(q);
  const auto trig = kin::arm_trig<Fixed>(qf);
  return core::resolved_rate(qf, trig, kin::twist_wrist<Fixed>(trig, t), kLimits);
}

double limit_rad_s(int j) { return config::kJointSpeedLimit_crad_s[j] / 100.0; }

// R5, the joint-5 origin's distance from the base axis (m)
double ref_r5(const ref::Joints& q) {
  return arm::a1_m + std::cos(q[1]) * arm::a2_m + std::cos(q[1] + q[2]) * arm::a3_m + std::cos(q[1] + q[2] + q[3]) * arm::a4_m;
}

TEST(WristAxes, MatchTheDhFrameFive) {
  std::mt19937_64 rng(31);
  double worst_double = 0, worst_fixed = 0;
  for (int n = 0; n < 2000; ++n) {
    const auto q = ref::random_joints(rng);
    const Eigen::Matrix3d r5 = ref::frames(q)[4].block<3, 3>(0, 0);
    kin::JointAngles<D> qd;
    for (int j = 0; j < 6; ++j) qd.q[j] = q[j];
    const auto a = kin::wrist_axes<D>(kin::arm_trig<D>(qd));
    const auto f = kin::wrist_axes<Fixed>(kin::arm_trig<Fixed>(to_fixed(q)));
    const kin::Vec3<double> axes[3] = {a.x5, a.y5, a.z5};
    const kin::Vec3<fx::Unit> axes_fixed[3] = {f.x5, f.y5, f.z5};
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d expected = r5.col(c);
      worst_double = std::max(worst_double, (Eigen::Vector3d(axes[c].x, axes[c].y, axes[c].z) - expected).norm());
      const Eigen::Vector3d fixed(fx::to_double(axes_fixed[c].x), fx::to_double(axes_fixed[c].y),
                                  fx::to_double(axes_fixed[c].z));
      worst_fixed = std::max(worst_fixed, (fixed - expected).norm());
    }
  }
  std::printf("wrist axes vs DH frame 5: double %.1e, fixed %.1e\n", worst_double, worst_fixed);
  EXPECT_LT(worst_double, 1e-12);
  EXPECT_LT(worst_fixed, 2e-4);
}

// Far from singular poses and limits, at hand speed, nothing is slowed: the output is J^-1 twist.
TEST(ResolvedRate, UnscaledAtHandSpeedInTheOpen) {
  const ref::Joints q = {0.2, 0.6, 1.0, -0.4, 0.5, 0.3};
  const auto t = twist(0.15, 0, 0, 0, 0, 0);
  const auto r = rates(q, t);
  const auto inv = kin::inverse_jacobian<Fixed>(to_fixed(q), t);
  EXPECT_EQ(r.slowed_by, 0);
  EXPECT_EQ(r.status, kin::SingularStatus::ok);
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(fx::to_double(r.qd_rad_s[j]), fx::to_double(inv.qd_rad_s[j]), 1e-4);
}

// Random poses and large twists: every joint within its speed limit (and soft limit), and
// the output parallel to J^-1 twist, so the hand keeps its direction.
TEST(ResolvedRate, OneCommonScaleKeepsDirectionAndLimits) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> v(-0.6, 0.6), w(-3, 3);
  double worst_over = 0, worst_angle = 0;
  int scaled = 0;
  for (int n = 0; n < 5000; ++n) {
    const auto q = ref::random_joints(rng);
    const auto t = twist(v(rng), v(rng), v(rng), w(rng), w(rng), w(rng));
    const auto r = rates(q, t);
    const auto inv = kin::inverse_jacobian<Fixed>(to_fixed(q), t);
    ref::Vec6 out, raw;
    for (int j = 0; j < 6; ++j) {
      out[j] = fx::to_double(r.qd_rad_s[j]);
      raw[j] = fx::to_double(inv.qd_rad_s[j]);
      worst_over = std::max(worst_over, std::abs(out[j]) - limit_rad_s(j));
    }
    if (out.norm() > 1e-3) {
      worst_angle = std::max(worst_angle, std::acos(std::min(1.0, out.dot(raw) / (out.norm() * raw.norm()))));
    }
    scaled += r.scale.raw < fx::kUnitOne;
  }
  std::printf("resolved rate over 5000 poses: %d scaled, worst excess over a joint limit %.2e rad/s, "
              "worst angle to J^-1 twist %.2e rad\n",
              scaled, worst_over, worst_angle);
  EXPECT_GT(scaled, 1000);
  EXPECT_LE(worst_over, 0.0);
  EXPECT_LT(worst_angle, 1e-3);
}

// The common scale is applied as core::scaled: s = kUnitOne (nothing limited) leaves J^-1's
// rates as they are, where the product took 2^-15 off them; a smaller s is the product. Against
// the product for every s (the arithmetic before), over random poses and twists from slow to
// beyond the limits: the unlimited rates differ by at most |qd| 2^-15 plus the product's floor
// and its two steps of rounding (fixed_point.h): three steps.
TEST(ResolvedRate, UnlimitedRatesAreJInverseItself) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> v(-0.6, 0.6), w(-3, 3), size(0.01, 1.0);
  int unlimited = 0, limited = 0;
  double worst_relative = 0;
  for (int n = 0; n < 5000; ++n) {
    const auto q = ref::random_joints(rng);
    const double k = size(rng) * size(rng);
    const auto t = twist(k * v(rng), k * v(rng), k * v(rng), k * w(rng), k * w(rng), k * w(rng));
    const auto r = rates(q, t);
    const auto trig = kin::arm_trig<Fixed>(to_fixed(q));
    const auto inv = kin::inverse_jacobian_wrist<Fixed>(trig, kin::twist_wrist<Fixed>(trig, t));  // the entry it takes
    const bool one = r.scale.raw == fx::kUnitOne;
    unlimited += one;
    limited += !one;
    for (int j = 0; j < 6; ++j) {
      const int32_t qd = inv.qd_rad_s[j].raw, product = (r.scale * inv.qd_rad_s[j]).raw;
      EXPECT_EQ(r.qd_rad_s[j].raw, one ? qd : product) << "pose " << n << " joint " << j + 1;
      const double difference = std::abs((double)r.qd_rad_s[j].raw - product);
      EXPECT_LE(difference, std::abs((double)qd) / 32768 + 3) << "pose " << n << " joint " << j + 1;
      if (std::abs(qd) >= 65536) worst_relative = std::max(worst_relative, difference / std::abs((double)qd));
    }
  }
  std::printf("%d unlimited, %d limited; worst difference to the product %.2e of |qd| (|qd| >= 2^-7 rad/s)\n", unlimited, limited, worst_relative);
  EXPECT_GT(unlimited, 1000);
  EXPECT_GT(limited, 1000);
}

// Stretching the elbow (q3 -> 0) by pulling the hand outwards, slowly enough that no joint
// reaches its speed limit: the speed falls as (|s3| - damp) / (slow - damp), to zero at the
// edge of the damped band; joint speeds stay within their limits, and the opposite command
// is never slowed by the singularity.
// The elbow's slow-down, worked in double from the law resolved_rate.h states: the fraction
// (|s3| - damp) / (slow - damp) inside the slow band, and the approach rate |d s3/dt| at most
// sqrt((a' tau)^2 + 2 a' d) - a' tau (d = |s3| - damp, tau the brake lag, a' = 3/4 |c3| a with
// a the least of a_j |qd3| / |qd_j| over the joints: one common factor slows them all).
double elbow_scale(const ref::Joints& q, const Eigen::Matrix<double, 6, 1>& twist) {
  const double s3 = std::sin(q[2]), c3 = std::cos(q[2]);
  const double damp = to_double(arm::kSingularBands.damp_s3), slow = to_double(arm::kSingularBands.slow_s3);
  double scale = std::fabs(s3) < slow ? std::max(0.0, std::min(1.0, (std::fabs(s3) - damp) / (slow - damp))) : 1.0;
  const Eigen::Matrix<double, 6, 1> qd = ref::geometric_jacobian(q).partialPivLu().solve(twist);
  const double qd3 = qd[2];
  double a_joint = config::kJointAccelLimit_crad_s2[2] / 100.0;
  for (int j = 0; j < 6; ++j)
    if (std::fabs(qd[j]) > 0) a_joint = std::min(a_joint, config::kJointAccelLimit_crad_s2[j] / 100.0 * std::fabs(qd3) / std::fabs(qd[j]));
  const double a = 0.75 * std::fabs(c3) * a_joint, tau = config::kSingularBrakeLag_ms / 1000.0;
  const double d = std::max(0.0, std::fabs(s3) - damp);
  const double allowed = std::sqrt(a * tau * a * tau + 2 * a * d) - a * tau;
  if (std::fabs(c3 * qd3) > allowed) scale = std::min(scale, allowed / std::fabs(c3 * qd3));
  return scale;
}
// and the joints' speed limits
double speed_limit_scale(const ref::Joints& q, const Eigen::Matrix<double, 6, 1>& twist) {
  const Eigen::Matrix<double, 6, 1> qd = ref::geometric_jacobian(q).partialPivLu().solve(twist);
  double scale = 1.0;
  for (int j = 0; j < 6; ++j)
    if (std::fabs(qd[j]) > limit_rad_s(j)) scale = std::min(scale, limit_rad_s(j) / std::fabs(qd[j]));
  return scale;
}

// Driven outwards towards the stretch (sin q3 = 0) at two speeds, the arm slows as the law
// says and comes to a stop at the damped band; driven back in it is never slowed.
TEST(ResolvedRate, SlowsTowardsTheElbowSingularityAndLetsTheArmBackOut) {
  for (double speed_m_s : {0.02, 0.15}) {
    double previous_scale = 1.0;
    for (double q3 = 0.6; q3 > 0.0; q3 -= 0.005) {
      const ref::Joints q = {0.0, 0.3, q3, -0.3 - q3, 0.0, 0.0};
      // the hand moving outwards along the line from the shoulder: d/dt of the reach
      const Eigen::Vector3d p = ref::fk(q).block<3, 1>(0, 3);
      const Eigen::Vector3d shoulder(arm::a1_m, 0, arm::d1_m);
      const Eigen::Vector3d out_dir = (p - shoulder).normalized() * speed_m_s;
      const auto outwards = rates(q, twist(out_dir.x(), out_dir.y(), out_dir.z(), 0, 0, 0));
      const auto inwards = rates(q, twist(-out_dir.x(), -out_dir.y(), -out_dir.z(), 0, 0, 0));
      Eigen::Matrix<double, 6, 1> out_twist;
      out_twist << out_dir, Eigen::Vector3d::Zero();
      const double s = fx::to_double(outwards.scale);
      const double expected = std::min(elbow_scale(q, out_twist), speed_limit_scale(q, out_twist));
      EXPECT_EQ(outwards.slowed_by & ~(core::kSlowSingular | core::kSlowJointSpeed), 0) << q3;
      if (expected < 1.0) {
        EXPECT_LE(s, previous_scale + 1e-4) << q3;
        EXPECT_NEAR(s, expected, 2e-3 + 0.01 * expected) << q3 << " at " << speed_m_s << " m/s";
      } else if (!(outwards.slowed_by & core::kSlowJointSpeed)) {
        EXPECT_EQ(outwards.slowed_by & core::kSlowSingular, 0) << q3;
      }
      EXPECT_EQ(inwards.slowed_by & core::kSlowSingular, 0) << q3;
      for (int j = 0; j < 6; ++j) {
        EXPECT_LE(std::abs(fx::to_double(outwards.qd_rad_s[j])), limit_rad_s(j) + 1e-3);
        EXPECT_LE(std::abs(fx::to_double(inwards.qd_rad_s[j])), limit_rad_s(j) + 1e-3);
      }
      previous_scale = s;
    }
    EXPECT_LT(previous_scale, 1e-3);
  }
}

// At full hand speed the elbow's braking begins before the slow band: the approach rate of
// sin q3 at the band's edge is already one it can stop from within the band.
TEST(ResolvedRate, TheElbowBrakesBeforeTheSlowBandAtFullSpeed) {
  const double slow = to_double(arm::kSingularBands.slow_s3);
  const double q3 = std::asin(slow) + 0.01;  // just outside the slow band
  const ref::Joints q = {0.0, 0.3, q3, -0.3 - q3, 0.0, 0.0};
  const Eigen::Vector3d p = ref::fk(q).block<3, 1>(0, 3);
  const Eigen::Vector3d out_dir = (p - Eigen::Vector3d(arm::a1_m, 0, arm::d1_m)).normalized() * 0.15;
  const auto outwards = rates(q, twist(out_dir.x(), out_dir.y(), out_dir.z(), 0, 0, 0));
  EXPECT_NE(outwards.slowed_by & core::kSlowSingular, 0) << "braking before the band";
  const double rate = std::fabs(std::cos(q3) * fx::to_double(outwards.qd_rad_s[2]));
  const double a = 0.75 * std::cos(q3) * config::kJointAccelLimit_crad_s2[2] / 100.0, tau = config::kSingularBrakeLag_ms / 1000.0;
  const double d = std::sin(q3) - to_double(arm::kSingularBands.damp_s3);
  std::printf("at sin q3 = %.3f, 0.15 m/s outwards: d(sin q3)/dt %.3f /s, stops in %.3f of the %.3f to the damped band\n",
              std::sin(q3), rate, rate * tau + rate * rate / (2 * a), d);
  EXPECT_LE(rate * tau + rate * rate / (2 * a), d * 1.01);
}

// A joint driven towards its upper limit slows over the zone and stops at the soft stop,
// a margin inside the switch; driven away it is not slowed.
TEST(ResolvedRate, SoftJointLimitStopsBeforeTheSwitch) {
  const double stop = arm::q_max_rad(0) - arm::deg_to_rad(config::kSoftLimitMargin_deg);
  const double zone = arm::deg_to_rad(config::kSoftLimitZone_deg);
  for (double q1 = stop - 1.5 * zone; q1 < stop + 0.02; q1 += 0.01) {
    const ref::Joints q = {q1, 0.6, 1.0, -0.4, 0.5, 0.3};
    // the hand turning with the base, w = (0, 0, w), v = w x p: joint 1 alone
    const Eigen::Vector3d p = ref::fk(q).block<3, 1>(0, 3);
    const auto towards = rates(q, twist(-0.3 * p.y(), 0.3 * p.x(), 0, 0, 0, 0.3));
    const auto away = rates(q, twist(0.3 * p.y(), -0.3 * p.x(), 0, 0, 0, -0.3));
    const double qd1 = fx::to_double(towards.qd_rad_s[0]);
    const double allowed = limit_rad_s(0) * std::max(0.0, std::min(1.0, (stop - q1) / zone));
    EXPECT_LE(qd1, allowed + 2e-3) << q1;
    if (q1 >= stop) {
      EXPECT_NEAR(qd1, 0.0, 1e-4) << q1;
    }
    EXPECT_EQ(away.slowed_by & core::kSlowSoftLimit, 0) << q1;
    EXPECT_LT(fx::to_double(away.qd_rad_s[0]), -0.29) << q1;
  }
}

// A closed limit switch (bits 2j low, 2j+1 high): its joint's drive only creeps towards it, so
// a twist that needs that joint moving that way stops (to the creep, all joints by one factor);
// one that moves it away, or turns other joints only (J^-1's rounding leaves a few steps of
// 2^-23 rad/s in the joints the twist does not turn: not slowed by them), goes at full speed.
TEST(ResolvedRate, NoMotionTowardsAClosedSwitch) {
  const ref::Joints q = {0.2, 0.6, 1.0, -0.4, 0.5, 0.3};
  const auto qf = to_fixed(q);
  const auto trig = kin::arm_trig<Fixed>(qf);
  const Eigen::Vector3d p = ref::fk(q).block<3, 1>(0, 3);
  // the hand turning with the base at 0.3 rad/s: joint 1 alone, up or down
  const auto up = kin::twist_wrist<Fixed>(trig, twist(-0.3 * p.y(), 0.3 * p.x(), 0, 0, 0, 0.3));
  const auto down = kin::twist_wrist<Fixed>(trig, twist(0.3 * p.y(), -0.3 * p.x(), 0, 0, 0, -0.3));
  const double creep_rad_s = fx::to_double(core::kCreepTowardsClosedSwitch_rad_s);
  for (int j = 0; j < 6; ++j) {
    for (int high = 0; high < 2; ++high) {
      SCOPED_TRACE("J" + std::to_string(j + 1) + (high ? "'s high switch" : "'s low switch"));
      core::DriveSpeeds drives = core::drives_at_speed_limits(kLimits);
      core::stop_towards_switches(drives, (uint16_t)(1u << (2 * j + high)));
      for (int k = 0; k < 6; ++k) {
        const int32_t limit = kLimits.joint[k].speed_rad_s.raw, creep = core::kCreepTowardsClosedSwitch_rad_s.raw;
        EXPECT_EQ(drives.positive_rad_s[k].raw, k == j && high ? creep : limit) << "J" << k + 1;
        EXPECT_EQ(drives.negative_rad_s[k].raw, k == j && !high ? creep : limit) << "J" << k + 1;
      }
      const auto towards = core::resolved_rate(qf, trig, high ? up : down, kLimits, &drives);
      const auto away = core::resolved_rate(qf, trig, high ? down : up, kLimits, &drives);
      if (j == 0) {
        EXPECT_LE(std::abs(fx::to_double(towards.qd_rad_s[0])), creep_rad_s);
        EXPECT_LT(fx::to_double(towards.scale), 2 * creep_rad_s / 0.3) << "the hand stops: every joint by one factor";
        EXPECT_EQ(towards.slowed_by & (core::kSlowLimitSwitch | core::kSlowDriveLoad), core::kSlowLimitSwitch);
      } else {
        EXPECT_EQ(towards.scale.raw, fx::kUnitOne);
      }
      EXPECT_EQ(away.scale.raw, fx::kUnitOne);
      EXPECT_NEAR(fx::to_double(away.qd_rad_s[0]), high ? -0.3 : 0.3, 1e-3);
    }
  }
  // a drive slowed by its load, not a switch, says so: J1's drive at a tenth of the turn's speed
  core::DriveSpeeds drives = core::drives_at_speed_limits(kLimits);
  drives.positive_rad_s[0] = drives.negative_rad_s[0] = fx::real(Ratio{3, 100});
  core::stop_towards_switches(drives, (uint16_t)(1u << 0 | 1u << 3));  // J1's low switch, J2's high one
  const auto slowed = core::resolved_rate(qf, trig, up, kLimits, &drives);
  EXPECT_NEAR(fx::to_double(slowed.scale), 0.1, 1e-3);
  EXPECT_EQ(slowed.slowed_by & (core::kSlowLimitSwitch | core::kSlowDriveLoad), core::kSlowDriveLoad);
}

// Each mode's full stick, through the resolved rate and back through the Eigen Jacobian:
// the hand moves along the mode's axis at the configured speed, and in the rotation modes
// the frame-6 origin stays put while the wrist turns about the frame-5 axis. (Joint speed
// limits are lifted here: whether a pose allows full wrist speed is another question.)
// A streamed velocity within its limit as a length: a longer one is scaled down to at most the
// limit (within 2 units of it) with its direction kept; one within the limit is left as it is.
TEST(StreamLimit, LengthWithinTheLimitDirectionKept) {
  std::mt19937 rng(22);
  std::uniform_int_distribution<int> component(-32768, 32767), small(-90, 90);
  const uint16_t limit = 150;
  for (int k = 0; k < 20000; ++k) {
    const bool within = k % 4 == 0;
    int16_t v[3];
    for (auto& c : v) c = (int16_t)(within ? small(rng) : component(rng));
    const Eigen::Vector3d before(v[0], v[1], v[2]);
    core::limit_length(v, limit);
    const Eigen::Vector3d after(v[0], v[1], v[2]);
    if (before.norm() <= limit) {
      ASSERT_EQ(after, before);
      continue;
    }
    ASSERT_LE(after.norm(), limit) << before.transpose();
    ASSERT_GT(after.norm(), limit - 2.0) << before.transpose();
    ASSERT_LT((after - after.norm() * before.normalized()).norm(), 1.8) << before.transpose();  // each component truncated by < 1
  }
  int16_t corner[3] = {-32768, -32768, -32768};  // the longest a command can be
  core::limit_length(corner, 800);
  EXPECT_EQ(corner[0], -461);  // 800 / sqrt(3), rounded towards zero
  EXPECT_EQ(corner[2], corner[0]);
}

TEST(StickTwist, EveryModeMovesTheHandAsTheSpecSays) {
  core::MotionLimits limits = kLimits;
  for (auto& l : limits.joint) l.speed_rad_s = fx::real(10.0);
  const ref::Joints q = {0.2, 0.6, 1.0, -0.4, 0.5, 0.3};
  const auto qf = to_fixed(q);
  const auto trig = kin::arm_trig<Fixed>(qf);
  const Eigen::Matrix3d r5 = ref::frames(q)[4].block<3, 3>(0, 0);
  const fx::Unit full{(int16_t)fx::kUnitOne}, none{0};
  struct Case {
    config::Mode mode;
    core::Stick stick;
    Eigen::Vector3d v, w;
  };
  const double hand = to_double(config::kMaxHandSpeed_m_s), wrist = to_double(config::kMaxWristSpeed_rad_s);
  const Case cases[] = {
      {config::Mode::xy, {full, none}, {hand, 0, 0}, {0, 0, 0}},
      {config::Mode::xy, {none, full}, {0, hand, 0}, {0, 0, 0}},
      {config::Mode::xz, {none, full}, {0, 0, hand}, {0, 0, 0}},
      {config::Mode::r1, {full, none}, {0, 0, 0}, wrist * r5.col(1)},
      {config::Mode::r1, {none, full}, {0, 0, 0}, wrist * r5.col(2)},
      {config::Mode::r2, {none, full}, {0, 0, 0}, wrist * r5.col(0)},
      {config::Mode::r2, {full, none}, {0, 0, 0}, wrist * r5.col(1)},
      {config::Mode::gripper, {full, full}, {0, 0, 0}, {0, 0, 0}},
  };
  for (const auto& c : cases) {
    const auto r = core::resolved_rate(qf, trig, core::stick_twist(c.mode, c.stick), limits);
    ASSERT_EQ(r.slowed_by, 0) << "mode " << (int)c.mode;
    ref::Vec6 qd;
    for (int j = 0; j < 6; ++j) qd[j] = fx::to_double(r.qd_rad_s[j]);
    const ref::Vec6 nu = ref::geometric_jacobian(q) * qd;
    EXPECT_LT((nu.head<3>() - c.v).norm(), 2e-4) << (int)c.mode;  // m/s
    EXPECT_LT((nu.tail<3>() - c.w).norm(), 2e-3) << (int)c.mode;  // rad/s
  }
}

// The rotation modes' stick through the resolved rate (J^-1 of w about the wrist axes) and
// back through the Eigen Jacobian, over random poses and deflections: the wrist turns at the
// stick's two components times the mode's axes of the DH frame 5, the frame-6 origin stays put.
// Poses in a singular band or where a limit slows the motion are left out.
TEST(StickTwist, RotationModesTurnAboutTheFrameFiveAxes) {
  core::MotionLimits limits = kLimits;
  for (auto& l : limits.joint) l.speed_rad_s = fx::real(100.0);
  std::mt19937_64 rng(34);
  std::uniform_real_distribution<double> deflection(-1.0, 1.0);
  const double wrist = to_double(config::kMaxWristSpeed_rad_s);
  double worst_w = 0, worst_v = 0;
  int checked = 0;
  for (int n = 0; n < 4000; ++n) {
    const auto q = ref::random_joints(rng);
    const auto qf = to_fixed(q);
    const auto trig = kin::jacobian_trig<Fixed>(qf);
    const core::Stick stick{fx::unit(deflection(rng)), fx::unit(deflection(rng))};
    const double sx = config::kStickXSign * fx::to_double(stick.x), sy = config::kStickYSign * fx::to_double(stick.y);
    const bool r1 = n % 2 == 0;
    const auto twist = core::stick_twist(r1 ? config::Mode::r1 : config::Mode::r2, stick);
    for (const auto& v : {twist.v_m_s.x, twist.v_m_s.y, twist.v_m_s.z}) ASSERT_EQ(v.raw, 0) << "pose " << n;
    const auto r = core::resolved_rate(qf, trig, twist, limits);
    if (r.status != kin::SingularStatus::ok || r.slowed_by != 0) continue;
    const Eigen::Matrix3d r5 = ref::frames(q)[4].block<3, 3>(0, 0);
    const Eigen::Vector3d expected = r1 ? wrist * (sx * r5.col(1) + sy * r5.col(2)) : wrist * (sy * r5.col(0) + sx * r5.col(1));
    ref::Vec6 qd;
    for (int j = 0; j < 6; ++j) qd[j] = fx::to_double(r.qd_rad_s[j]);
    const ref::Vec6 nu = ref::geometric_jacobian(q) * qd;
    worst_w = std::max(worst_w, (nu.tail<3>() - expected).norm());
    worst_v = std::max(worst_v, nu.head<3>().norm());
    ++checked;
  }
  std::printf("rotation modes over %d poses: w vs wrist speed times the frame-5 axes worst %.1e rad/s, "
              "frame-6 origin's speed worst %.1e m/s\n",
              checked, worst_w, worst_v);
  EXPECT_GT(checked, 1000);
  EXPECT_LT(worst_w, 2e-3);
  EXPECT_LT(worst_v, 2e-4);
}

// The firmware's pass: J^-1's rates scaled by rate_scale's s inside the acceleration limit
// (in place) give resolved_rate's rates, and the references move as they did when the limit
// took resolved_rate's scaled rates (s = 1 there: nothing scaled again), with k and every
// joint's change within its limit. Random poses, twists, last velocities and limits, so that
// both s and k are below one often.
TEST(JointAcceleration, ScalingInItsPassIsTheResolvedRate) {
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> v(-0.6, 0.6), w(-3, 3), size(0.01, 1.0), last(-1.0, 1.0), change(0.0005, 0.05);
  const fx::Unit one{(int16_t)fx::kUnitOne};
  int scaled = 0, limited = 0, unlimited = 0;
  for (int n = 0; n < 5000; ++n) {
    const auto q = ref::random_joints(rng);
    const double k = size(rng) * size(rng);
    const auto t = twist(k * v(rng), k * v(rng), k * v(rng), k * w(rng), k * w(rng), k * w(rng));
    const auto qf = to_fixed(q);
    const auto trig = kin::arm_trig<Fixed>(qf);
    const auto wrist = kin::twist_wrist<Fixed>(trig, t);
    const core::JointRates r = core::resolved_rate(qf, trig, wrist, kLimits);
    auto inv = kin::inverse_jacobian_wrist<Fixed>(trig, wrist);
    const core::RateScale s = core::rate_scale(qf, trig, inv, kLimits, core::drives_at_speed_limits(kLimits));
    ASSERT_EQ(s.scale.raw, r.scale.raw) << n;
    fx::Real qd[6], qd_before[6], wanted[6], max_change[6];
    for (int j = 0; j < 6; ++j) {
      wanted[j] = r.qd_rad_s[j];
      max_change[j] = fx::real(change(rng));
      // every second case near the wanted rates (k = 1 mostly), the others anywhere
      const fx::Real near{wanted[j].raw + (int32_t)(last(rng) * max_change[j].raw)};
      qd[j] = qd_before[j] = n % 2 ? near : fx::real(last(rng) * fx::to_double(kLimits.joint[j].speed_rad_s));
    }
    const fx::Unit k_before = core::limit_joint_acceleration(qd_before, wanted, one, max_change);
    const fx::Unit k_now = core::limit_joint_acceleration(qd, inv.qd_rad_s, s.scale, max_change);
    EXPECT_EQ(k_now.raw, k_before.raw) << n;
    for (int j = 0; j < 6; ++j) {
      EXPECT_EQ(inv.qd_rad_s[j].raw, r.qd_rad_s[j].raw) << "pose " << n << " joint " << j + 1;
      EXPECT_EQ(qd[j].raw, qd_before[j].raw) << "pose " << n << " joint " << j + 1;
      EXPECT_EQ(wanted[j].raw, r.qd_rad_s[j].raw) << "s = 1 scales nothing: pose " << n;
    }
    scaled += s.scale.raw < fx::kUnitOne;
    limited += k_now.raw < fx::kUnitOne;
    unlimited += k_now.raw == fx::kUnitOne;
  }
  std::printf("%d of 5000 scaled by the resolved rate; %d limited by the acceleration, %d not\n", scaled, limited, unlimited);
  EXPECT_GT(scaled, 1000);
  EXPECT_GT(limited, 1000);
  EXPECT_GT(unlimited, 1000);
}

// Each joint's change within its limit, to a step of 2^-23 rad/s (k (w - qd) is a floor: a
// negative change can come out one step larger than k allows), and the velocities on the
// straight path to the wanted ones: qd + k (w - qd), or w itself at k = 1.
TEST(JointAcceleration, EveryChangeWithinItsLimit) {
  std::mt19937_64 rng(36);
  std::uniform_real_distribution<double> speed(-1.0, 1.0), change(0.0005, 0.05);
  const fx::Unit one{(int16_t)fx::kUnitOne};
  for (int n = 0; n < 5000; ++n) {
    fx::Real qd[6], before[6], wanted[6], max_change[6];
    for (int j = 0; j < 6; ++j) {
      qd[j] = before[j] = fx::real(speed(rng));
      wanted[j] = fx::real(speed(rng));
      max_change[j] = fx::real(change(rng));
    }
    const fx::Unit k = core::limit_joint_acceleration(qd, wanted, one, max_change);
    for (int j = 0; j < 6; ++j) {
      EXPECT_LE(std::abs((int64_t)qd[j].raw - before[j].raw), max_change[j].raw + 1) << "case " << n << " joint " << j + 1;
      const int32_t expected = k.raw == fx::kUnitOne ? wanted[j].raw : before[j].raw + (k * (wanted[j] - before[j])).raw;
      EXPECT_EQ(qd[j].raw, expected) << "case " << n << " joint " << j + 1;
    }
  }
}

}  // namespace

// Never stuck (SPEC 5): a turn about y5, the axis of J6 (R1's and R2's stick X), leaves the elbow
// as it is, and goes on at full speed inside the elbow's slow and damped bands, where J^-1's
// rounding still gives sin q3 a small rate (that rate printed: moving_towards_zero's |f| / 32 s
// must stay above it).
TEST(ResolvedRate, RoundingOfAMotionThatLeavesTheElbowDoesNotStopIt) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> s3(0.015, 0.2);
  const double damp = to_double(arm::kSingularBands.damp_s3);
  double worst_rate = 0, worst_ratio = 0;
  int inside_damped = 0;
  for (int n = 0; n < 20000; ++n) {
    ref::Joints q = ref::random_joints(rng);
    q[2] = std::asin(s3(rng)) * (n % 2 ? 1 : -1);
    if (std::fabs(std::cos(q[4])) < 0.25 || ref_r5(q) < 0.2) continue;  // clear of the other factors' bands
    inside_damped += std::fabs(std::sin(q[2])) < damp;
    for (config::Mode mode : {config::Mode::r1, config::Mode::r2}) {
      for (double x : {-0.999, 0.999}) {
        const auto qf = to_fixed(q);
        const auto trig = kin::arm_trig<Fixed>(qf);
        const auto r = core::resolved_rate(qf, trig, core::stick_twist(mode, core::Stick{fx::unit(x), fx::Unit{0}}), kLimits);
        const double rate = std::fabs(std::cos(q[2]) * fx::to_double(r.qd_rad_s[2]));
        worst_rate = std::max(worst_rate, rate);
        worst_ratio = std::max(worst_ratio, rate / (std::fabs(std::sin(q[2])) / 32));
        ASSERT_EQ(r.slowed_by & core::kSlowSingular, 0) << "sin q3 " << std::sin(q[2]) << " mode " << (int)mode << " x " << x;
      }
    }
  }
  std::printf("a turn about y5 inside the elbow's slow band: d(sin q3)/dt at most %.2g /s from rounding, %.2f of |sin q3| / 32 s\n",
              worst_rate, worst_ratio);
  EXPECT_GT(inside_damped, 1000);
}
