// The joint drives of the virtual arm against the motor data and physics they stand for.
#include <gtest/gtest.h>

#include <cmath>

#include "plant/arm_plant.h"

using namespace wmra::plant;

namespace {

constexpr double kDt = kPlantStepS;

void run_dc(DcJoint& d, double seconds, double inertia, double load) {
  for (int i = 0; i < (int)(seconds / kDt); ++i) d.step(kDt, inertia, load);
}

DcJoint dc_joint(int joint, bool self_locking = true) {
  return DcJoint(kGearRatio[joint], wmra::arm::q_min_rad(joint), wmra::arm::q_max_rad(joint), self_locking);
}

// steady state of the torque-speed line against friction: T_stall (V/12 - w/w0) = T_c + b w
double steady_output_speed(double volts) {
  const double slope = kDcStallTorqueNm / kDcNoLoadSpeedRadS;
  return (kDcStallTorqueNm * volts / kDcNominalV - kDcCoulombFrictionNm) / (slope + kDcViscousNmPerRadS);
}

}  // namespace

TEST(Bts7960, AveragesTheTwoSides) {
  EXPECT_DOUBLE_EQ(bts7960_voltage(0.5, 0), 6.0);
  EXPECT_DOUBLE_EQ(bts7960_voltage(0, 0.25), -3.0);
  EXPECT_DOUBLE_EQ(bts7960_voltage(0.75, 0.25), 6.0);
  EXPECT_DOUBLE_EQ(bts7960_voltage(1.5, -1), 12.0);  // duties are clamped
}

TEST(DcJoint, SteadySpeedFollowsTheMotorData) {
  for (double volts : {12.0, 6.0, -9.0}) {
    DcJoint d = dc_joint(3);
    d.set_voltage(volts);
    run_dc(d, 0.6, 0.0, 0.0);
    const double expected = std::copysign(steady_output_speed(std::fabs(volts)), volts) / kGearRatio[3];
    EXPECT_NEAR(d.qd(), expected, 0.005 * std::fabs(expected)) << volts << " V";
  }
  // no-load speed of the assembly at 12 V, less friction: 85 rpm within 12 %
  EXPECT_NEAR(steady_output_speed(12), kDcNoLoadSpeedRadS, 0.12 * kDcNoLoadSpeedRadS);
}

TEST(DcJoint, StallTorqueIsTheDatasheetsAtZeroSpeed) {
  DcJoint d = dc_joint(2);
  d.set_voltage(12);
  EXPECT_DOUBLE_EQ(d.motor_torque_nm(), kDcStallTorqueNm);
  EXPECT_DOUBLE_EQ(d.current_a(), kDcStallCurrentA);
}

TEST(DcJoint, TimeConstantFromInertiaAndSlope) {
  DcJoint d = dc_joint(3);
  d.set_voltage(12);
  const double tau = kDcAssemblyInertiaKgm2 / (kDcStallTorqueNm / kDcNoLoadSpeedRadS + kDcViscousNmPerRadS);
  run_dc(d, tau, 0.0, 0.0);
  const double final_speed = steady_output_speed(12) / kGearRatio[3];
  EXPECT_NEAR(d.qd() / final_speed, 1 - std::exp(-1.0), 0.02);
}

TEST(DcJoint, DeadBandFromStiction) {
  const double breakaway_v = kDcStaticFrictionNm / kDcStallTorqueNm * kDcNominalV;  // 1.3 V, 11 % duty
  DcJoint below = dc_joint(3), above = dc_joint(3);
  below.set_voltage(0.95 * breakaway_v);
  above.set_voltage(1.05 * breakaway_v);
  run_dc(below, 0.5, 0.1, 0.0);
  run_dc(above, 0.5, 0.1, 0.0);
  EXPECT_EQ(below.q(), 0.0);
  EXPECT_GT(above.q(), 0.001);
}

TEST(DcJoint, WormHoldsTheStretchedArmUnpowered) {
  const auto loads = joint_loads({0, 0, 0, 0, 0, 0}, true, true);
  ASSERT_LT(loads.gravity_nm[1], -30.0);  // the shoulder carries ~34 N m
  DcJoint held = dc_joint(1, true), free = dc_joint(1, false);
  run_dc(held, 2.0, loads.inertia_kgm2[1], loads.gravity_nm[1]);
  run_dc(free, 0.2, loads.inertia_kgm2[1], loads.gravity_nm[1]);
  EXPECT_EQ(held.q(), 0.0);
  EXPECT_LT(free.q(), -0.01);  // a back-drivable gear lets it fall (and shows the test can fail)
}

TEST(DcJoint, LowersAtTheMotorsSpeedNotGravitys) {
  // gravity aids the motion: a self-locking worm still needs the motor to turn it
  const auto loads = joint_loads({0, 0, 0, 0, 0, 0}, true, true);
  DcJoint down = dc_joint(1);
  down.set_angle(1.5);  // room to lower (the load stays the stretched arm's)
  down.set_voltage(-6);
  run_dc(down, 1.5, loads.inertia_kgm2[1], loads.gravity_nm[1]);
  EXPECT_NEAR(down.qd(), -steady_output_speed(6) / kGearRatio[1], 0.005);
  // half voltage cannot lift the stretched arm, and the worm does not let it fall
  DcJoint weak = dc_joint(1);
  weak.set_voltage(6);
  run_dc(weak, 1.0, loads.inertia_kgm2[1], loads.gravity_nm[1]);
  EXPECT_EQ(weak.q(), 0.0);
  // full voltage lifts it, at what the torque left over gives
  DcJoint up = dc_joint(1);
  up.set_voltage(12);
  run_dc(up, 1.5, loads.inertia_kgm2[1], loads.gravity_nm[1]);
  const double left_over = kDcStallTorqueNm + loads.gravity_nm[1] / kGearRatio[1] - kDcCoulombFrictionNm;
  EXPECT_NEAR(up.qd(), left_over / (kDcStallTorqueNm / kDcNoLoadSpeedRadS + kDcViscousNmPerRadS) / kGearRatio[1], 0.01);
}

TEST(DcJoint, WormStopsTheArmWithTheMotor) {
  // unpowered, the arm's inertia cannot drive the worm: it stops as fast as the motor does
  const double link_inertia = 3.0;
  DcJoint worm = dc_joint(1, true), spur = dc_joint(1, false);
  for (DcJoint* d : {&worm, &spur}) {
    d->set_voltage(12);
    run_dc(*d, 1.0, link_inertia, 0);
    d->set_voltage(0);
  }
  const double tau = kDcAssemblyInertiaKgm2 / (kDcStallTorqueNm / kDcNoLoadSpeedRadS);
  run_dc(worm, 5 * tau, link_inertia, 0);
  run_dc(spur, 5 * tau, link_inertia, 0);
  EXPECT_EQ(worm.qd(), 0.0);
  EXPECT_GT(spur.qd(), 0.05);
}

TEST(DcJoint, HardStopPastTheLimit) {
  DcJoint d = dc_joint(3);
  d.set_voltage(12);
  run_dc(d, 3.0, 0.0, 0.0);
  EXPECT_NEAR(d.q(), wmra::arm::q_max_rad(3) + kHardStopBeyondLimitRad, 1e-9);
  EXPECT_TRUE(d.against_stop());
}

// --- stepper joints

namespace {

struct Ramp {
  double accel;  // microsteps/s^2
  double top;    // microsteps/s
};

// drives the indexer with an ideal ramp to `top` and holds it for `seconds`
StepperJoint run_ramp(int joint, Ramp r, double seconds, double inertia, double load, bool enabled = true) {
  const StepperMotorData& m = joint == 0 ? kNema23Ht23_397 : kNema17_42HS48;
  StepperJoint s(m, kGearRatio[joint], -10, 10, false, false);
  s.set_angle(0);
  s.set_enabled(enabled);
  long n = 0;
  const double t_top = r.top / r.accel;
  for (int i = 0; i < (int)(seconds / kDt); ++i) {
    const double t = i * kDt;
    const double target = t < t_top ? 0.5 * r.accel * t * t : 0.5 * r.accel * t_top * t_top + r.top * (t - t_top);
    while (n < (long)target) {
      s.microstep(1);
      ++n;
    }
    s.step(kDt, inertia, load);
  }
  return s;
}

// the largest acceleration the motor's holding torque gives its rotor and load, microsteps/s^2
double max_accel(int joint, double inertia) {
  const StepperMotorData& m = joint == 0 ? kNema23Ht23_397 : kNema17_42HS48;
  const double motor_inertia = m.rotor_inertia_kgm2 + inertia / (kGearRatio[joint] * kGearRatio[joint]);
  return m.holding_torque_nm / motor_inertia / StepperJoint::microstep_motor_rad();
}

}  // namespace

TEST(StepperJoint, CornerSpeedsFromTheWindingData) {
  EXPECT_NEAR(corner_speed_rad_s(kNema23Ht23_397), 9.0, 0.1);
  EXPECT_NEAR(corner_speed_rad_s(kNema17_42HS48), 28.8, 0.2);
}

TEST(StepperJoint, FollowsAStepTrainWithinItsTorque) {
  const auto loads = joint_loads({0, 0.5, 0.5, 0, 0.3, 0}, true, true);
  for (int j : kStepperJoints) {
    const Ramp r{0.5 * max_accel(j, loads.inertia_kgm2[j]), 20000};  // 20 kHz, the step rate's gate
    const StepperJoint s = run_ramp(j, r, 3.0, loads.inertia_kgm2[j], 0);
    EXPECT_EQ(s.microsteps_lost(), 0) << "J" << j + 1;
    EXPECT_NEAR(s.q(), s.q_commanded(), 0.02) << "J" << j + 1;
  }
}

TEST(StepperJoint, LosesStepsWhenAskedToAccelerateBeyondItsTorque) {
  const auto loads = joint_loads({0, 0, 0, 0, 0, 0}, true, true);  // stretched: J1 sees 3.2 kg m^2
  for (int j : kStepperJoints) {
    const double a = max_accel(j, loads.inertia_kgm2[j]);
    const StepperJoint below = run_ramp(j, Ramp{0.6 * a, 20000}, 3.0, loads.inertia_kgm2[j], 0);
    const StepperJoint beyond = run_ramp(j, Ramp{1.2 * a, 20000}, 3.0, loads.inertia_kgm2[j], 0);
    EXPECT_EQ(below.microsteps_lost(), 0) << "J" << j + 1;
    EXPECT_GE(beyond.microsteps_lost(), kMicrostepsPerElectricalPeriod) << "J" << j + 1;
    EXPECT_EQ(beyond.microsteps_lost() % kMicrostepsPerElectricalPeriod, 0);
    // what is lost is where the joint is not, within the rotor's swing in its well (< pi electrical)
    const double usteps_to_joint = StepperJoint::microstep_motor_rad() / kGearRatio[j];
    EXPECT_NEAR(beyond.q_commanded() - beyond.q(), -beyond.microsteps_slipped() * usteps_to_joint,
                kMicrostepsPerElectricalPeriod / 2 * usteps_to_joint);
  }
}

TEST(StepperJoint, LosesStepsAboveTheSpeedItsTorqueCarriesALoadTo) {
  // a constant load of 40 % of the holding torque at the motor: the pull-out torque
  // T_hold w_c / w falls to it at 2.5 w_c
  const int j = 5;
  const double load_motor = 0.4 * kNema17_42HS48.holding_torque_nm;
  const double limit_rad_s = corner_speed_rad_s(kNema17_42HS48) / 0.4;
  const double limit_usteps = limit_rad_s / StepperJoint::microstep_motor_rad();
  const double inertia = 1e-3;
  const double a = 0.1 * max_accel(j, inertia);
  const StepperJoint below = run_ramp(j, Ramp{a, 0.7 * limit_usteps}, 2.0, inertia, -load_motor);
  const StepperJoint beyond = run_ramp(j, Ramp{a, 1.2 * limit_usteps}, 2.0, inertia, -load_motor);
  EXPECT_EQ(below.microsteps_lost(), 0);
  EXPECT_GT(beyond.microsteps_lost(), 0);
}

TEST(StepperJoint, DisabledMotorDoesNotFollow) {
  const StepperJoint s = run_ramp(5, Ramp{1000, 1000}, 1.0, 1e-3, 0, false);
  EXPECT_GT(s.microsteps_commanded(), 0);
  EXPECT_NEAR(s.q(), 0.0, 1e-3);
}

TEST(Drv8825, StepsOnRisingEdgesWhileEnabled) {
  Drv8825 d;
  d.reset(true, false, false, 0);
  double t = 1e-3;
  EXPECT_EQ(d.update(true, false, true, t), 0);  // disabled: ignored
  EXPECT_EQ(d.steps_ignored(), 1);
  d.update(false, true, false, t += 1e-5);
  EXPECT_EQ(d.update(false, true, true, t += 1e-5), 1);
  d.update(false, false, false, t += 1e-5);
  EXPECT_EQ(d.update(false, false, true, t += 1e-5), -1);
  EXPECT_EQ(d.steps_taken(), 2);
  EXPECT_EQ(d.timing_violations(), 0);
}

TEST(Drv8825, CountsTimingViolations) {
  Drv8825 d;
  d.reset(false, false, false, 0);
  double t = 1e-3;
  d.update(false, false, true, t);
  d.update(false, false, false, t += 1e-6);      // high for 1 us < 1.9 us
  d.update(false, true, false, t += 1e-5);       // DIR changes...
  d.update(false, true, true, t += 0.25e-6);     // ...250 ns before the edge < 650 ns
  EXPECT_EQ(d.timing_violations(), 2);
}
