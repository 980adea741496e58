// The stop (docs/arm-guide.md, safety): how each stepper joint comes to rest with its driver enabled, derived from
// its motor's data and the load it carries; and what the firmware watches while the arm stands.
//
// A stopped stepper is held by its driver (IEC 60204-1 category 2): the arm stays where it
// stopped, whatever friction does, and the step count stays the joint's angle. Stopping the step
// train at once leaves the rotor and its load to the motor's magnetic spring, torque
// T_hold sin(e) at the electrical angle e = N_r x by which the rotor has run past the stopped
// field (N_r = 50 rotor teeth, x at the motor): from a speed w at the motor the spring takes the
// kinetic energy J w^2 / 2 while e stays below e_stop if J w^2 / 2 <= (T_hold / N_r)(1 - cos
// e_stop). e_stop is 120 deg, two thirds of the way to the half period (180 deg) past which the
// rotor slips to the next pole: a margin of a third on the energy for the inertia and torque
// figures below, the drive's own damping not counted. That is the start/stop rate; above it the
// train slows first, at the deceleration the torque share below gives, T_hold share / J. J is
// the rotor's inertia plus the load's worst (the arm stretched with the payload) through the
// gear: the stop never asks for more torque than the motor has, in any pose.
// Units are in the names; every value has a static_assert on its range.
#pragma once

#include <stdint.h>

#include "config/joints_config.h"

namespace wmra {
namespace config {

// --- the steppers' motors and loads, J1, J5, J6 (index 0, 1, 2)
// holding torque (datasheets: HT23-397 bipolar series 1.25 N m; 42HS48-1684 0.43 N m)
constexpr int16_t kStepperHoldingTorque_mNm[3] = {1250, 430, 430};
// rotor inertia, g cm^2 (not on the datasheets Torres's thesis gives: typical 56 mm NEMA 23, 48 mm NEMA 17;
// measure or take the motor maker's figure)
constexpr int16_t kStepperRotorInertia_gcm2[3] = {300, 68, 68};
// The largest inertia each joint moves, about its axis (g m^2): J1 with the arm stretched
// horizontally and the 1.2 kg payload (3.19 kg m^2 from the CAD masses), J5 the wrist and the
// payload (0.114), J6 the payload about its axis (0.0011). Too small a figure makes the stop
// ask for more torque than the motor has: the joint slips and the count is lost.
constexpr int32_t kStepperLoadInertia_gm2[3] = {3200, 115, 2};
// The share of the holding torque the stop plans with: the rest covers the drive's ripple
// between microsteps, the pull-out torque's fall with speed and what the figures above miss.
// J5's gravity load (up to 4.0 N m of its 4.3 N m at the joint with the payload) is carried by
// its gear, taken as self-locking: a back-drivable J5 gear needs a stronger motor or a brake.
constexpr int16_t kStopTorqueShare_permille = 700;

// --- while stopped
// A DC joint's pot that moves more than this while its bridge brakes (a slipping worm, a broken
// gear) is the moved_while_stopped fault; watched from kStandstillSettle_ms after the stop, when
// a joint stopped at speed has come to rest.
constexpr int16_t kStandstillMove_mdeg = 1000;
constexpr int16_t kStandstillSettle_ms = 100;
// The steppers' drivers released (EN high) this long after a stop, 0: never. A released joint
// may be moved by hand or by gravity, so it is homed again before it moves.
constexpr uint16_t kStepperReleaseAfterStop_ms = 0;

// --- derived: the stop's deceleration and start/stop rate per stepper
constexpr double kStopPi = 3.14159265358979;
constexpr double stop_sqrt(double x, double r = 1.0, int n = 60) { return n == 0 ? r : stop_sqrt(x, (r + x / r) / 2, n - 1); }
constexpr double stepper_gear(int i) { return kStepsPerJointTurn[i] / (200.0 * 32.0); }
// inertia at the motor, kg m^2
constexpr double stop_inertia_at_motor(int i) {
  return kStepperRotorInertia_gcm2[i] * 1e-7 + kStepperLoadInertia_gm2[i] * 1e-3 / (stepper_gear(i) * stepper_gear(i));
}
constexpr double stop_torque_nm(int i) { return kStepperHoldingTorque_mNm[i] * 1e-3 * kStopTorqueShare_permille / 1000.0; }
// steps per rad of motor angle (1/32 microsteps)
constexpr double kStepsPerMotorRad = 200.0 * 32.0 / (2 * kStopPi);
constexpr int32_t stop_decel_steps_s2(int i) { return (int32_t)(stop_torque_nm(i) / stop_inertia_at_motor(i) * kStepsPerMotorRad); }
constexpr double kStopSpringOneLessCos = 1.5;  // 1 - cos(e_stop), e_stop = 120 deg
constexpr int32_t start_stop_steps_s(int i) {
  return (int32_t)(stop_sqrt(2.0 * kStepperHoldingTorque_mNm[i] * 1e-3 * kStopSpringOneLessCos / (50.0 * stop_inertia_at_motor(i))) *
                   kStepsPerMotorRad);
}
constexpr int32_t kStopDecel_steps_s2[3] = {stop_decel_steps_s2(0), stop_decel_steps_s2(1), stop_decel_steps_s2(2)};
constexpr int32_t kStartStop_steps_s[3] = {start_stop_steps_s(0), start_stop_steps_s(1), start_stop_steps_s(2)};

// J1's load changes most with the pose (0.3 to 3.2 kg m^2, stretched or folded): while the pose
// is known its start/stop rate follows the arm's inertia about the base axis I (g m^2,
// core/base_inertia.h, J1's rotor through its gear added): the start/stop interval (Timer5
// ticks, 4 us) from interval^2 = kJ1StartStopInterval2_per_gm2_q8 I / 256. The constants above
// are these at the largest I.
constexpr double kJ1StepsPerRad = kStepsPerJointTurn[0] / (2 * kStopPi);
constexpr uint32_t kJ1StartStopInterval2_per_gm2_q8 =
    (uint32_t)(250000.0 * 250000.0 * 50.0 / (2.0 * kStepperHoldingTorque_mNm[0] * 1e-3 * kStopSpringOneLessCos * kJ1StepsPerRad *
                                               kJ1StepsPerRad * 1000.0) * 256.0 + 1);
// J1's stop at the hand, within kStopTravel_mm; the DC joints, braking on their shorted motors,
// take the rest of the stop's 10 mm. Two things carry the hand on when J1's train stops:
//   - the load's speed: J1 decelerating with its whole holding torque (the stopped field's
//     spring and the drive's damping come close to it in the simulator) stops within
//     w^2 r / (2 T_hold gear / I) at the hand;
//   - J1's lag behind its field while it accelerates: the torque I alpha that the field's spring
//     (stiffness k = T_hold N_r gear^2 at the joint, N_r = 50) gives at a lag of I alpha / k.
//     The rotor, stopped from behind the field, swings past it as far again: from a lag L and a
//     swing S of the speed alone the hand goes L + sqrt(L^2 + S^2) (the spring's energy).
// So J1's acceleration is bounded where the arm's inertia is large (L <= kJ1LagTravel_um at the
// hand: alpha <= k L / (I r)) and its speed by the rest, S = sqrt((kStopTravel_mm - L)^2 - L^2):
// w^2 (mrad/s)^2 = kJ1StopSpeed2_q4 16 / (I r). Without the lag's share a stop while J1 sped up
// at 1 m took the hand 18 mm.
constexpr int16_t kStopTravel_mm = 8;
constexpr int16_t kJ1LagTravel_um = 1000;
constexpr double kJ1SwingTravel_mm =
    stop_sqrt((kStopTravel_mm - kJ1LagTravel_um / 1000.0) * (kStopTravel_mm - kJ1LagTravel_um / 1000.0) -
              (kJ1LagTravel_um / 1000.0) * (kJ1LagTravel_um / 1000.0));
constexpr uint32_t j1_stop_speed2_q4(double travel_mm) {
  return (uint32_t)(2.0 * travel_mm * 1e-3 * kStepperHoldingTorque_mNm[0] * 1e-3 * stepper_gear(0) * 1e12 / 16.0);
}
constexpr uint32_t kJ1StopSpeed2_q4 = j1_stop_speed2_q4(kJ1SwingTravel_mm);
// J1's largest change of speed in a 1 ms tick, Q23 rad/s, times 16, over I (g m^2) r (mm):
// alpha = k L / (I r) with k in N m/rad, L in um and I r in g m^2 mm (1e-6 kg m^3): alpha rad/s^2
// = k L / (I r) exactly; per tick x 2^23 / 1000.
constexpr double kJ1Stiffness_Nm_per_rad = kStepperHoldingTorque_mNm[0] * 1e-3 * 50.0 * stepper_gear(0) * stepper_gear(0);
constexpr uint32_t kJ1LagAccelPerTick_q23_x16 = (uint32_t)(kJ1Stiffness_Nm_per_rad * kJ1LagTravel_um * 8388608.0 / 1000.0 / 16.0);
// J1's homing approach, at its speed, stops within kStopTravel_mm at the hand from any pose (the
// largest inertia at the farthest reach, 1.1 m: the pose is not known while it homes)
static_assert(kHomingFast_crad_s[0] * kHomingFast_crad_s[0] * 100.0 <=
                  j1_stop_speed2_q4(kStopTravel_mm) * 16.0 / (kStepperLoadInertia_gm2[0] * 1100.0),
              "kHomingFast_crad_s[0]: J1's homing approach must stop within kStopTravel_mm at the hand");
constexpr uint16_t kJ1RotorAtJoint_gm2 = (uint16_t)(kStepperRotorInertia_gcm2[0] * 1e-4 * stepper_gear(0) * stepper_gear(0) + 1);

// J1's acceleration follows the pose. Its ramp (kStepperAccel_crad_s2[0]) and its reference
// (kJointAccelLimit_crad_s2[0]) are set for the largest inertia; where the arm's inertia about
// the base axis (with J1's rotor) is a multiple m smaller, both go m times as fast, and the
// share of the motor's torque they ask stays the stretched arm's. The hand near the base axis
// needs J1 fast: at 0.5 rad/s^2 J1 needs up to 1.6 s to stop after the stick's release, and the
// hand runs on up to 111 mm.
constexpr uint8_t kJ1AccelMultiples[4] = {1, 2, 4, 6};
constexpr uint16_t kJ1WorstInertia_gm2 = (uint16_t)(kStepperLoadInertia_gm2[0] + kJ1RotorAtJoint_gm2);

// --- checks
constexpr bool stop_config_ok() {
  for (int i = 0; i < 3; ++i) {
    if (kStepperHoldingTorque_mNm[i] < 100 || kStepperHoldingTorque_mNm[i] > 10000) return false;
    if (kStepperRotorInertia_gcm2[i] < 10 || kStepperRotorInertia_gcm2[i] > 10000) return false;
    if (kStepperLoadInertia_gm2[i] < 1 || kStepperLoadInertia_gm2[i] > 100000) return false;
  }
  return true;
}
static_assert(stop_config_ok(),
              "kStepperHoldingTorque_mNm in [100, 10000], kStepperRotorInertia_gcm2 in [10, 10000], "
              "kStepperLoadInertia_gm2 in [1, 100000]");
static_assert(kStopTorqueShare_permille >= 200 && kStopTorqueShare_permille <= 900,
              "kStopTorqueShare_permille in [200, 900]: all of the holding torque is never there at speed");
static_assert(kStandstillMove_mdeg >= 200 && kStandstillMove_mdeg <= 5000,
              "kStandstillMove_mdeg in [200, 5000]: above a pot's noise, below a visible move");
static_assert(kJ1AccelMultiples[0] == 1 && kJ1AccelMultiples[1] > 1 && kJ1AccelMultiples[2] > kJ1AccelMultiples[1] &&
                  kJ1AccelMultiples[3] > kJ1AccelMultiples[2] && kJ1AccelMultiples[3] <= 10,
              "kJ1AccelMultiples: 1 (the largest inertia's) first, then rising, at most 10");
static_assert(kStopTravel_mm >= 3 && kStopTravel_mm <= 10, "kStopTravel_mm in [3, 10]: the stop's 10 mm less the DC joints' share");
static_assert(kJ1LagTravel_um >= 200 && 4 * kJ1LagTravel_um <= kStopTravel_mm * 1000,
              "kJ1LagTravel_um in [200, kStopTravel_mm / 4]: the most of the stop's travel left to J1's speed");
static_assert(kStandstillSettle_ms >= 10 && kStandstillSettle_ms <= 500, "kStandstillSettle_ms in [10, 500]");
static_assert(kStepperReleaseAfterStop_ms == 0 || kStepperReleaseAfterStop_ms >= 1000,
              "kStepperReleaseAfterStop_ms: 0 (never) or at least 1 s (a person's re-arm comes first)");
// the stop's deceleration at least the ramp's acceleration: a slower one would make a stop longer
// than braking on the ramp, and means the ramp asks for more torque than the motor has
static_assert(kStopDecel_steps_s2[0] >= kStepperAccel_crad_s2[0] / 100.0 * kStepsPerJointTurn[0] / (2 * kStopPi) * 0.9 &&
                  kStopDecel_steps_s2[1] >= kStepperAccel_crad_s2[1] / 100.0 * kStepsPerJointTurn[1] / (2 * kStopPi) &&
                  kStopDecel_steps_s2[2] >= kStepperAccel_crad_s2[2] / 100.0 * kStepsPerJointTurn[2] / (2 * kStopPi),
              "kStepperAccel_crad_s2: within the stop's deceleration (the motor's torque share over the worst "
              "inertia); J1's within 10 % of it");

}  // namespace config
}  // namespace wmra
