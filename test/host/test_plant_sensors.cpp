// Sensors, operator inputs and the arm's statics.
#include <gtest/gtest.h>

#include <cmath>

#include "kinematics/forward_kinematics.h"
#include "plant/arm_plant.h"

using namespace wmra::plant;
namespace arm = wmra::arm;

TEST(Potentiometer, JointRangeSpansTheConditionedVoltages) {
  Potentiometer p(arm::q_min_rad(1), arm::q_max_rad(1), 0, 0, NoiseStream(1, 0));
  EXPECT_DOUBLE_EQ(p.ideal_mv(arm::q_min_rad(1)), kPotLowMv);
  EXPECT_DOUBLE_EQ(p.ideal_mv(arm::q_max_rad(1)), kPotHighMv);
  EXPECT_NEAR(p.angle_of_mv(p.ideal_mv(0.3)), 0.3, 1e-12);
}

TEST(Potentiometer, QuantisedByTheAdc) {
  Potentiometer p(arm::q_min_rad(2), arm::q_max_rad(2), 0, 0, NoiseStream(1, 0));
  // one count of the ADC is this many radians at the joint
  const double rad_per_count = (arm::q_max_rad(2) - arm::q_min_rad(2)) / ((kPotHighMv - kPotLowMv) / kAdcRefMv * 1023);
  EXPECT_NEAR(rad_per_count, 0.00563, 0.00005);  // ~0.32 deg on J3
  int changes = 0, last = -1;
  for (double q = 0; q < 100 * rad_per_count; q += rad_per_count / 10) {
    p.reset(q);
    const int c = adc_counts_simavr(p.sample_mv());
    if (last >= 0 && c != last) {
      EXPECT_EQ(c, last + 1);
      ++changes;
    }
    last = c;
  }
  EXPECT_NEAR(changes, 100, 1);
}

TEST(Potentiometer, SeededNoiseOfTheConfiguredSize) {
  Potentiometer a(-1, 1, 1.5, 0, NoiseStream(7, 11)), b(-1, 1, 1.5, 0, NoiseStream(7, 11));
  a.reset(0.2);
  b.reset(0.2);
  double sum = 0, sum2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double va = a.sample_mv();
    ASSERT_EQ(va, b.sample_mv());  // same seed, same numbers
    const double e = va - a.ideal_mv(0.2);
    sum += e;
    sum2 += e * e;
  }
  EXPECT_NEAR(sum / n, 0, 0.05);
  EXPECT_NEAR(std::sqrt(sum2 / n), 1.5, 0.05);
}

TEST(Potentiometer, FaultsGoToTheRails) {
  Potentiometer p(-1, 1, 0, 0, NoiseStream(1, 0));
  p.set_fault(PotFault::open);
  p.reset(0.5);
  EXPECT_EQ(adc_counts_simavr(p.sample_mv()), 0);
  p.set_fault(PotFault::shorted);
  p.reset(0.5);
  EXPECT_EQ(adc_counts_simavr(p.sample_mv()), 1023);
}

TEST(Potentiometer, FilteredWithItsTimeConstant) {
  Potentiometer p(-1, 1, 0, 1e-3, NoiseStream(1, 0));
  p.reset(-1);
  for (int i = 0; i < 50; ++i) p.step(1, 20e-6);  // one time constant after a jump
  const double expected = kPotLowMv + (kPotHighMv - kPotLowMv) * (1 - std::exp(-1.0));
  EXPECT_NEAR(p.filtered_mv(), expected, 1e-6 * expected);
}

TEST(LimitSwitch, SeenHalfATimeConstantLogTwoAfterTheContact) {
  LimitSwitch s(LimitSwitch::Kind::high, 1.0, kLimitSwitchTauS);
  s.reset(0.9);
  double t = 0;
  while (!s.closed() && t < 1) {
    s.step(1.01, 1e-5);
    t += 1e-5;
  }
  EXPECT_NEAR(t, kLimitSwitchTauS * std::log(2.0), 2e-5);
  LimitSwitch low(LimitSwitch::Kind::low, -1.0, 0);
  low.step(-1.0, 1e-5);
  EXPECT_TRUE(low.closed());
  low.step(-0.99, 1e-5);
  EXPECT_FALSE(low.closed());
}

TEST(LimitSwitch, ZeroCamClosesEveryTurn) {
  LimitSwitch z(LimitSwitch::Kind::zero, 0.0, 0);
  for (double turn : {-2.0, -1.0, 0.0, 1.0}) {
    EXPECT_TRUE(z.contact_closed(turn * 2 * kPi + 0.9 * kZeroSwitchHalfWidthRad));
    EXPECT_FALSE(z.contact_closed(turn * 2 * kPi + 1.1 * kZeroSwitchHalfWidthRad));
  }
}

TEST(BouncingContact, BouncesThenSettles) {
  BouncingContact c(1.5e-3, NoiseStream(3, 0));
  c.reset(false);
  c.set(true, 1.0);
  int flips = 0;
  bool last = false;
  for (double t = 1.0; t < 1.01; t += 1e-6) {
    const bool now = c.closed_at(t);
    if (now != last) ++flips;
    last = now;
  }
  EXPECT_GE(flips, 3);
  EXPECT_EQ(flips % 2, 1);
  EXPECT_TRUE(c.closed_at(1.0016));
  BouncingContact clean(0, NoiseStream(3, 0));
  clean.set(true, 1.0);
  EXPECT_FALSE(clean.closed_at(0.999));
  EXPECT_TRUE(clean.closed_at(1.0));
}

TEST(Joystick, DeflectionToVoltsAndUnplugged) {
  const double offsets[2] = {0, 0};
  JoystickAxes j(offsets, 0, NoiseStream(1, 1), NoiseStream(1, 2));
  j.set(1, -1);
  EXPECT_DOUBLE_EQ(j.sample_mv(0), kStickCentreMv + kStickFullScaleMv);
  EXPECT_DOUBLE_EQ(j.sample_mv(1), kStickCentreMv - kStickFullScaleMv);
  EXPECT_GT(adc_counts_simavr(j.sample_mv(0)), 0);
  EXPECT_LT(adc_counts_simavr(j.sample_mv(0)), 1023);
  j.set_unplugged(true);
  EXPECT_EQ(adc_counts_simavr(j.sample_mv(0)), 0);
}

// --- statics

TEST(ArmStatics, FramesAgreeWithTheKinematicsLibrary) {
  using D = wmra::kin::Floating<double>;
  NoiseStream rng(5, 0);
  for (int n = 0; n < 100; ++n) {
    Joints q;
    wmra::kin::JointAngles<D> a;
    for (int i = 0; i < kJoints; ++i) a.q[i] = q[i] = -2 + 4 * rng.uniform();
    const auto f = arm_frames(q)[5];
    const auto pose = wmra::kin::forward_kinematics<D>(a);
    EXPECT_NEAR(f.p[0], pose.p_m.x, 1e-12);
    EXPECT_NEAR(f.p[1], pose.p_m.y, 1e-12);
    EXPECT_NEAR(f.p[2], pose.p_m.z, 1e-12);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f.R[r][c], pose.R[r][c], 1e-12);
  }
}

TEST(ArmStatics, ShoulderTorqueOfTheStretchedArmMatchesTheThesis) {
  // Table 3.5: 34.32 N m at J2, 18.81 N m at J3 with the 1.2 kg load, arm stretched
  const auto l = joint_loads({0, 0, 0, 0, 0, 0}, true, true);
  EXPECT_NEAR(-l.gravity_nm[1], 34.32, 0.6);
  EXPECT_NEAR(-l.gravity_nm[2], 18.81, 0.4);
  EXPECT_NEAR(l.gravity_nm[0], 0, 1e-12);  // the base axis is vertical
}

namespace {
double potential_energy(const Joints& q) {
  const auto f = arm_frames(q);
  double u = 0;
  for (int j = 0; j < kJoints; ++j) {
    double z = f[j].p[2];
    for (int c = 0; c < 3; ++c) z += f[j].R[2][c] * kLinks[j].r_cm_m[c];
    u += kLinks[j].mass_kg * kGravityMs2 * z;
  }
  return u + kPayloadKg * kGravityMs2 * (f[5].p[2] + f[5].R[2][2] * kPayloadOffsetM);
}
}  // namespace

TEST(ArmStatics, GravityTorqueIsMinusTheGradientOfThePotentialEnergy) {
  NoiseStream rng(9, 0);
  for (int n = 0; n < 200; ++n) {
    Joints q;
    for (auto& v : q) v = -2 + 4 * rng.uniform();
    const auto l = joint_loads(q, true, true);
    for (int i = 0; i < kJoints; ++i) {
      Joints a = q, b = q;
      const double h = 1e-6;
      a[i] += h;
      b[i] -= h;
      EXPECT_NEAR(l.gravity_nm[i], -(potential_energy(a) - potential_energy(b)) / (2 * h), 1e-5);
    }
  }
}
