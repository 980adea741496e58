// The joints' drives: stepper resolutions and ramps, homing, the ready pose, the DC joints'
// potentiometers, servo gains and plausibility limits. Units are in the names; each value has
// a static_assert on its range. Changing one is an edit here and a rebuild.
#pragma once

#include <stdint.h>

#include "kinematics/arm_model.h"
#include "kinematics/ratio.h"

namespace wmra {
namespace config {

// --- stepper joints J1, J5, J6 (index 0, 1, 2 here)
// 200 full steps x 1/32 microstep (DRV8825 mode pins high) x the joint's reduction
constexpr uint32_t kStepsPerJointTurn[3] = {200ul * 32 * 2, 200ul * 32 * 10, 200ul * 32 * 1};
// acceleration limits, rad/s^2 x 100: J1 carries the whole arm (about 0.8 rad/s^2 stretched with
// the payload before the NEMA23 slips)
constexpr int16_t kStepperAccel_crad_s2[3] = {60, 400, 400};
// the shortest step interval, Timer5 ticks of 4 us: 12.5 ticks, 20 kHz (the ramp carries the
// fraction)
constexpr uint16_t kStepMinInterval_ticks = 12;
// the longest: slower commands are a stop (20 steps/s), so a stop never waits more than 50 ms
// behind a creeping step (lib/control/step_rate.h)
constexpr uint16_t kStepMaxInterval_ticks = 12500;
// position loop of a stepper around its reference: speed += gain x (reference - position), at
// most sqrt(accel x |error|) (firmware/core/stepper_tracking.h)
constexpr int16_t kStepperPositionGain_per_s = 20;

// Homing (docs/arm-guide.md, using the arm): J1 to its +90 deg switch, J5 to its -90 deg switch, J6 to its zero switch.
// J6's closes kHomeSwitch_deg[2] before each whole turn (0, +-360 deg) from either side (its cam
// is +-2 deg wide, symmetric about zero); kHomingDir[2] is the direction J6 approaches 0 in when
// it starts on the cam (-1: from above).
constexpr int8_t kHomingDir[3] = {+1, -1, -1};
constexpr int16_t kHomeSwitch_deg[3] = {90, -90, 2};
// Fast approach: the ramp must brake within the 3 deg between a switch and its hard stop, and a
// stop during homing keeps the hand within the stop's 10 mm (docs/arm-guide.md, safety) (J1: stop_config.h's check, with the
// largest inertia at the farthest reach: the pose is not known before homing). J6 brakes on the
// cam of the first switch it meets, so that it never turns past a switch, +-360 deg's included.
constexpr int16_t kHomingFast_crad_s[3] = {10, 30, 25};
constexpr int16_t kHomingSlow_crad_s[3] = {3, 3, 5};
// J1, J5: how far they back off their switch before the slow approach; J6: how far before the
// cam's edge its slow approach starts
constexpr int16_t kHomingBackOff_deg[3] = {3, 3, 4};
constexpr int16_t kHomingMaxTravel_deg[2] = {200, 200};  // J1, J5 (J6: below)
// The limit switches' RC filter (47 kOhm x 1 uF, seed 2) and optocoupler see a closing about
// two time constants late; homing corrects its slow approach by that delay. Measured in the
// simulator's model of the board; measure it on a real board.
constexpr int16_t kSwitchDelay_ms = 94;

// J6's turn (firmware/core/wrist_homing.h). Its angle at rest is recorded in EEPROM once
// it has stayed within kJ6RestBand_mdeg (its tracking may dither a step or two) for
// kJ6RestBeforeRecord_ms outside a move to a pose (whose line may creep J6 slower than that), at least kJ6RecordChange_mdeg from the angle last recorded, and homing
// goes to the switch of the turn nearest it: at most half a turn and the cam away. The recorded angle must be where the switch says within kJ6AngleTolerance_mdeg, or
// the homing stops J6 (docs/arm-guide.md: a wrist turned by hand while switched off).
constexpr int16_t kJ6RestBeforeRecord_ms = 1000;
constexpr int16_t kJ6RestBand_mdeg = 500;
constexpr int16_t kJ6RecordChange_mdeg = 1000;
constexpr int16_t kJ6AngleTolerance_mdeg = 1500;
// With no recorded angle (a new board, a lost EEPROM) J6 is taken to be within half a turn of
// 0: sweeps from where it starts, to these angles from there in turn, find the nearest switch.
// The first legs are short, so that a J6 near 0 homes with a short roll; the last two reach
// 180 deg less the cam's half width either way, where the next turn's switch is still out of
// reach.
constexpr int16_t kJ6Sweep_deg[4] = {-30, 90, -178, 178};

// The ready pose after homing (off the singular J5 = -90 deg), J1..J6, deg
constexpr int16_t kReadyPose_deg[6] = {70, 20, -70, 50, -30, 0};
constexpr bool ready_pose_inside_limits(int j) {
  return j == 6 || (kReadyPose_deg[j] >= arm::q_min_deg[j] + 5 && kReadyPose_deg[j] <= arm::q_max_deg[j] - 5 &&
                    ready_pose_inside_limits(j + 1));
}
static_assert(ready_pose_inside_limits(0), "kReadyPose_deg: every joint at least 5 deg inside its limits");
static_assert(kReadyPose_deg[4] > -85 && kReadyPose_deg[4] < 85, "kReadyPose_deg: off the singular J5 = +-90 deg");
static_assert(kReadyPose_deg[2] < -5 || kReadyPose_deg[2] > 5, "kReadyPose_deg: off the singular sin q3 = 0");
// joint-space moves (to the ready pose, to a stored pose): this fraction of each joint's limit
constexpr Ratio kJointMoveSpeed{1, 2};
constexpr int16_t kArrivedTolerance_mdeg = 1000;  // DC joints; steppers arrive exactly

// --- DC joints J2, J3, J4 (index 0, 1, 2 here)
// Potentiometers: the joint range spans 250..4750 mV of the 5 V ADC range, so an open
// or shorted wiper (a rail) is told from any angle. Per-joint calibration in EEPROM overrides.
constexpr int16_t kPotAtMin_mV = 250;
constexpr int16_t kPotAtMax_mV = 4750;
constexpr int16_t kAdcRef_mV = 5000;
constexpr int16_t kPositionUnitsPerCount = 16;

// PID by seed 1's pole placement on each joint (tools/jointsim dc --show-design; README):
// Kp in duty per count, Ki per count-second, Kd in duty-seconds per count, at the loop rate
constexpr Ratio kDcKp[3] = {{5527, 100000}, {8799, 100000}, {7020, 100000}};
constexpr Ratio kDcKi_per_s[3] = {{12754, 100000}, {24367, 100000}, {25922, 100000}};
constexpr Ratio kDcKd_s[3] = {{5894, 1000000}, {8551, 1000000}, {4686, 1000000}};
// Velocity feedforward: each joint's speed at full duty without load, hundredths of a rad/s
// (the Mabuchi 578VA's 85 rpm at its worm's output over the joint's gear, 4.5, 2.5 and 2:1;
// measure on the arm). The PID adds speed / this as effort, and its integral the rest (load,
// friction).
constexpr int16_t kDcFullDutySpeed_crad_s[3] = {198, 356, 445};
// Inertia each DC drive moves, at its worm's output (for the acceleration's feedforward):
// the motor's rotor through the worm and the wheel, about 50 g m^2 (estimate: measure the
// coast-down time constant, tau = J w0 / T_stall), plus the links and payload beyond the joint
// (gravity_config's point masses at the ready pose, about 1.5, 0.5 and 0.15 kg m^2 at J2..J4)
// over the joint's gear squared. Too small only leaves some lag for the PID; too large leads.
constexpr int16_t kDcInertiaAtWorm_gm2[3] = {120, 130, 90};
// of which the rotor's, through the worm: a worm that does not back-drive (gravity_config's
// kDcSelfLocking) stops the links itself when the motor slows, so slowing a reference down
// brakes only the rotor (estimate, as above)
constexpr int16_t kDcRotorInertiaAtWorm_gm2 = 50;
// A DC reference slower than this stands (no feedforward; the servo may park): the drift
// correction's trickle after the stick is let go, a pot count (3.4-6 mrad) in most of a second or slower.
constexpr int16_t kDcStandingSpeed_mrad_s = 5;
// Duty kept back for the PID's corrections: a DC joint that lifts its load may go only as fast
// as the rest of full duty beyond its holding effort takes it (firmware/core/gravity.h); the
// whole arm slows with it, so that the hand stays on its line.
constexpr int16_t kDcDutyReserve_permille = 100;
// effort ramps from 0 to full in 50 ms; the worm's stiction needs 11 % duty to break away;
// below 1 % effort the duty is 0
constexpr int16_t kDcRampTime_ms = 50;
constexpr int16_t kDcMinDuty_permille = 110;
// once moving, the worm's Coulomb friction takes less (0.8 of 9.12 N m: 9 %); a moving
// reference's effort is mapped through it in the motion's direction (pid.h's duty_moving).
// Measure on the arm: the duty at which a joint, moving slowly, coasts to a stop.
constexpr int16_t kDcMovingFrictionDuty_permille = 88;
constexpr int16_t kDcZeroBand_permille = 10;
// park (duty 0: the worm holds) once within this many ADC counts for this long
constexpr int16_t kDcParkBand_counts = 1;
constexpr int16_t kDcParkTime_ms = 50;
// and leave it when the error stays beyond twice the band this long (a noisy reading is one tick)
constexpr int16_t kDcUnparkTime_ms = 10;
// seed 1's relay with dead zone instead of the PID
constexpr bool kDcUseRelay = false;
constexpr int16_t kRelayDeadZone_counts = 2;
constexpr int16_t kRelayDuty_permille = 600;

// Plausibility: saturated drive without progress = stall; against the drive = sign
// error; a reading jumping more than a joint can move = jump; near a rail = broken wiring
constexpr int16_t kStallDuty_permille = 950;
constexpr int16_t kStallTime_ms = 300;
constexpr int16_t kStallProgress_counts = 2;
constexpr int16_t kSignGrace_ms = 200;
constexpr int16_t kSignDistance_counts = 8;
constexpr int16_t kMaxStep_counts_per_ms = 12;
constexpr int16_t kRailMargin_counts = 20;
constexpr int16_t kRailTime_ms = 5;
// Tracking: a DC joint behind its reference slows the hand (from the first to the second
// lag) rather than letting the reference run away; beyond the third it is a fault. What lag is
// left when the stick is let go, the joint still catches up: 50 mrad is 20 to 40 mm at the hand.
constexpr int16_t kTrackingSlowFrom_mrad = 15;
constexpr int16_t kTrackingStopAt_mrad = 50;
constexpr int16_t kTrackingFault_mrad = 250;

// --- checks
static_assert(kStepMinInterval_ticks >= 12, "kStepMinInterval_ticks >= 12: at most 20.8 kHz per stepper");
static_assert(kStepMaxInterval_ticks > kStepMinInterval_ticks && kStepMaxInterval_ticks <= 25000,
              "kStepMaxInterval_ticks: the slowest step between the fastest and 10 steps/s (a command waits at most 100 ms)");
static_assert(kStepperPositionGain_per_s * (uint32_t)kStepMaxInterval_ticks >= 250000ul,
              "kStepperPositionGain_per_s x kStepMaxInterval_ticks: one step of error must ask for at least the slowest step, or the loop stops short of it");
constexpr bool stepper_config_ok() {
  for (int i = 0; i < 3; ++i) {
    if (kStepperAccel_crad_s2[i] <= 0 || kStepperAccel_crad_s2[i] > 2000) return false;
    if (kHomingFast_crad_s[i] <= 0 || kHomingFast_crad_s[i] > 50 || kHomingSlow_crad_s[i] <= 0 ||
        kHomingSlow_crad_s[i] > kHomingFast_crad_s[i])
      return false;
    // the slow approach is not below the slowest step (it would be a stop)
    if (kHomingSlow_crad_s[i] * (double)kStepsPerJointTurn[i] * kStepMaxInterval_ticks < 100 * 6.2832 * 250000) return false;
    if (kHomingBackOff_deg[i] < 1 || kHomingBackOff_deg[i] > 20 || (i < 2 && kHomingMaxTravel_deg[i] < 90)) return false;
    if (kHomingDir[i] != 1 && kHomingDir[i] != -1) return false;
  }
  return true;
}
static_assert(stepper_config_ok(), "kStepperAccel_crad_s2 in (0, 2000], kHomingFast_crad_s in (0, 50], kHomingSlow_crad_s in (0, fast] and not below the slowest step, kHomingBackOff_deg in [1, 20], kHomingMaxTravel_deg >= 90, kHomingDir +-1");
// The joint map: which of J1..J6 (0..5) each driver turns. Steppers 0, 1, 2 (steppers::rate(i),
// the DRV8825s) are J1, J5, J6; DC drives 0, 1, 2 (bridges::set(d), the BTS7960s) are J2, J3, J4.
constexpr uint8_t kStepperJoint[3] = {0, 4, 5};
constexpr uint8_t kDcJoint[3] = {1, 2, 3};
constexpr int16_t largest_angle_deg(int j) { return -arm::q_min_deg[j] > arm::q_max_deg[j] ? -arm::q_min_deg[j] : arm::q_max_deg[j]; }
constexpr bool stepper_steps_ok() {
  for (int i = 0; i < 3; ++i)
    if (kStepsPerJointTurn[i] < 200 || kStepsPerJointTurn[i] * largest_angle_deg(kStepperJoint[i]) / 360 >= 65536ul)
      return false;
  return true;
}
static_assert(stepper_steps_ok(),
              "kStepsPerJointTurn: at least a full-step motor's 200, and every angle of the joint's range within "
              "2^16 steps of zero (core/joint_map.h's StepperMap)");
constexpr bool home_switches_ok() {
  for (int i = 0; i < 3; ++i)
    if (kHomeSwitch_deg[i] < arm::q_min_deg[kStepperJoint[i]] || kHomeSwitch_deg[i] > arm::q_max_deg[kStepperJoint[i]])
      return false;
  return true;
}
static_assert(home_switches_ok(), "kHomeSwitch_deg: each switch within its joint's range (arm_model.h)");
// J1 and J5 home to a switch 3 deg before their hard stop: the fast approach runs on for the
// switch's delay before it is seen, then brakes at the ramp's acceleration. J6's zero switch has
// no stop behind it, but its fast approach brakes within the cam's half width (its edge 2 deg
// before a whole turn): a switch met at +-358 deg stops J6 within its +-360 deg range.
constexpr double homing_overrun_deg(int i) {
  return (kHomingFast_crad_s[i] / 100.0 * kSwitchDelay_ms / 1000.0 +
          (kHomingFast_crad_s[i] / 100.0) * (kHomingFast_crad_s[i] / 100.0) / (2 * kStepperAccel_crad_s2[i] / 100.0)) *
         180 / 3.14159265;
}
static_assert(homing_overrun_deg(0) < 3 && homing_overrun_deg(1) < 3,
              "kHomingFast_crad_s: J1's and J5's fast approach (the switch's delay, then braking at "
              "kStepperAccel_crad_s2) must stop within the 3 deg between the switch and the hard stop");
static_assert(homing_overrun_deg(2) < kHomeSwitch_deg[2],
              "kHomingFast_crad_s[2]: J6's fast approach (the switch's delay, then braking at kStepperAccel_crad_s2[2]) "
              "must stop within kHomeSwitch_deg[2], the zero cam's half width, of the cam's edge");
static_assert(kHomeSwitch_deg[2] >= 1 && kHomeSwitch_deg[2] <= 10 && kJ6AngleTolerance_mdeg > 0 &&
                  kJ6AngleTolerance_mdeg < kHomeSwitch_deg[2] * 1000 && kJ6AngleTolerance_mdeg < kHomingBackOff_deg[2] * 1000,
              "kHomeSwitch_deg[2] (J6's cam half width) in [1, 10] deg; kJ6AngleTolerance_mdeg above 0 and within the "
              "half width and J6's slow run-up (kHomingBackOff_deg[2]): the switch must tell a recorded angle that is off");
static_assert(kHomingBackOff_deg[2] > kHomeSwitch_deg[2],
              "kHomingBackOff_deg[2] (J6's slow run-up) more than kHomeSwitch_deg[2] (its cam's half width): J6 started on "
              "its cam backs off both and must leave the cam");
static_assert(kJ6RestBand_mdeg > 0 && kJ6RestBand_mdeg < kJ6RecordChange_mdeg && kJ6RecordChange_mdeg <= kJ6AngleTolerance_mdeg &&
                  kJ6RestBeforeRecord_ms >= 100 && kJ6RestBeforeRecord_ms <= 10000,
              "0 < kJ6RestBand_mdeg < kJ6RecordChange_mdeg <= kJ6AngleTolerance_mdeg: a recorded angle stays within the "
              "tolerance of where J6 rests; kJ6RestBeforeRecord_ms in [100, 10000]");
constexpr bool j6_sweep_ok() {
  // each leg the other way and wider, the last two the widest either way, short of the next turn's switch
  for (int k = 1; k < 4; ++k)
    if ((kJ6Sweep_deg[k] > 0) == (kJ6Sweep_deg[k - 1] > 0) ||
        (kJ6Sweep_deg[k] < 0 ? -kJ6Sweep_deg[k] : kJ6Sweep_deg[k]) < (kJ6Sweep_deg[k - 1] < 0 ? -kJ6Sweep_deg[k - 1] : kJ6Sweep_deg[k - 1]))
      return false;
  const int last = kJ6Sweep_deg[3] < 0 ? -kJ6Sweep_deg[3] : kJ6Sweep_deg[3];
  const int before = kJ6Sweep_deg[2] < 0 ? -kJ6Sweep_deg[2] : kJ6Sweep_deg[2];
  return kJ6Sweep_deg[0] != 0 && last == before && last <= 180 - kHomeSwitch_deg[2] && last >= 180 - 2 * kHomeSwitch_deg[2];
}
static_assert(j6_sweep_ok(), "kJ6Sweep_deg: alternating signs, each leg at least as wide as the one before, the last two "
                             "the same width either way, 180 deg less one to two of J6's cam half widths");
constexpr bool switch_delay_ok() {
  for (int i = 0; i < 3; ++i)
    if (kHomingSlow_crad_s[i] / 100.0 * kSwitchDelay_ms / 1000.0 >= kHomingBackOff_deg[i] * 3.14159265 / 180) return false;
  return true;
}
static_assert(kSwitchDelay_ms >= 0 && kSwitchDelay_ms <= 500 && switch_delay_ok(),
              "kSwitchDelay_ms in [0, 500], and the slow approach's travel in it shorter than the back-off (the "
              "switch closes again within the back-off)");
static_assert(kJointMoveSpeed.num > 0 && kJointMoveSpeed.num <= kJointMoveSpeed.den,
              "kJointMoveSpeed in (0, 1] of each joint's speed limit");
// a DC servo parks within kDcParkBand_counts: a move's tolerance below that (the nominal pot span
// over the widest DC joint, J4's 320 deg) might never count as arrived
constexpr double kWidestDcJointDegPerCount =
    (arm::q_max_deg[3] - arm::q_min_deg[3]) / ((kPotAtMax_mV - kPotAtMin_mV) * 1023.0 / kAdcRef_mV);
static_assert(kArrivedTolerance_mdeg >= kDcParkBand_counts * kWidestDcJointDegPerCount * 1000 && kArrivedTolerance_mdeg <= 5000,
              "kArrivedTolerance_mdeg: at least the DC servos' parking band in the coarsest joint's degrees, at most "
              "5 deg (a move that ends further off has not arrived)");
static_assert(kPositionUnitsPerCount >= 1, "kPositionUnitsPerCount >= 1 (its upper bound, 16 bits, is in config/derived.h)");
constexpr bool dc_gains_ok() {
  for (int d = 0; d < 3; ++d)
    if (kDcKp[d].num < 0 || kDcKp[d].den <= 0 || kDcKi_per_s[d].num < 0 || kDcKi_per_s[d].den <= 0 || kDcKd_s[d].num < 0 ||
        kDcKd_s[d].den <= 0)
      return false;
  return true;
}
static_assert(dc_gains_ok(),
              "kDcKp, kDcKi_per_s, kDcKd_s: non-negative, positive denominators (their fit in the PID's formats is "
              "checked in config/derived.h)");
static_assert(kRelayDeadZone_counts >= 1 && kRelayDeadZone_counts <= 20,
              "kRelayDeadZone_counts in [1, 20]: without a dead zone the relay chatters around its target");
static_assert(kRelayDuty_permille > kDcMinDuty_permille && kRelayDuty_permille <= 1000,
              "kRelayDuty_permille: above the stiction's kDcMinDuty_permille (or the relay never moves the joint), at "
              "most full duty");
static_assert(kStallDuty_permille > kDcMinDuty_permille && kStallDuty_permille <= 1000,
              "kStallDuty_permille: above the stiction's duty (a slow joint is no stall), at most full duty");
static_assert(kStallTime_ms <= 1000 && kSignGrace_ms > 0 && kSignGrace_ms <= 1000,
              "kStallTime_ms at most 1 s (a jammed motor draws its stall current meanwhile), kSignGrace_ms in (0, 1] s "
              "(a drive wired backwards runs away meanwhile)");
static_assert(kRailMargin_counts < (int32_t)kPotAtMin_mV * 1023 / kAdcRef_mV &&
                  kRailMargin_counts < (int32_t)(kAdcRef_mV - kPotAtMax_mV) * 1023 / kAdcRef_mV,
              "kRailMargin_counts: a pot at either end of its joint's range reads outside the rail margin (or the "
              "joint's end is a wiring fault)");
static_assert(kDcParkBand_counts <= 64 && kRailTime_ms <= 255,
              "kDcParkBand_counts at most 64 counts, kRailTime_ms fits its 8-bit counter");
static_assert(kStepperPositionGain_per_s > 0 && kStepperPositionGain_per_s <= 100, "kStepperPositionGain_per_s in (0, 100] /s");
static_assert(kPotAtMin_mV > 100 && kPotAtMax_mV < kAdcRef_mV - 100 && kPotAtMin_mV < kPotAtMax_mV,
              "kPotAtMin_mV, kPotAtMax_mV: the pot range must leave both rails (100 mV) for fault detection");
static_assert(kDcDutyReserve_permille >= 0 && kDcDutyReserve_permille <= 500, "kDcDutyReserve_permille in [0, 500]: the duty reserve for the PID");
static_assert(kDcRampTime_ms > 0 && kDcMinDuty_permille >= 0 && kDcMinDuty_permille < 500 && kDcZeroBand_permille >= 0,
              "kDcRampTime_ms > 0, kDcMinDuty_permille in [0, 500), kDcZeroBand_permille >= 0");
static_assert(kDcMovingFrictionDuty_permille >= 0 && kDcMovingFrictionDuty_permille <= kDcMinDuty_permille,
              "kDcMovingFrictionDuty_permille in [0, kDcMinDuty_permille]: the moving friction's duty at most the breakaway's");
static_assert(kDcParkBand_counts >= 1 && kDcParkTime_ms > 0 && kDcUnparkTime_ms > 0 && kDcUnparkTime_ms <= 100,
              "kDcParkBand_counts >= 1, kDcParkTime_ms > 0, kDcUnparkTime_ms in (0, 100]");
static_assert(kDcFullDutySpeed_crad_s[0] >= 100 && kDcFullDutySpeed_crad_s[1] >= 100 && kDcFullDutySpeed_crad_s[2] >= 100 &&
                  kDcFullDutySpeed_crad_s[0] <= 2000 && kDcFullDutySpeed_crad_s[1] <= 2000 &&
                  kDcFullDutySpeed_crad_s[2] <= 2000,
              "kDcFullDutySpeed_crad_s in [100, 2000]: [1, 20] rad/s");
static_assert(kDcInertiaAtWorm_gm2[0] > 0 && kDcInertiaAtWorm_gm2[1] > 0 && kDcInertiaAtWorm_gm2[2] > 0 &&
                  kDcInertiaAtWorm_gm2[0] <= 1000 && kDcInertiaAtWorm_gm2[1] <= 1000 && kDcInertiaAtWorm_gm2[2] <= 1000,
              "kDcInertiaAtWorm_gm2 in (0, 1000]: (0, 1] kg m^2");
static_assert(kDcRotorInertiaAtWorm_gm2 > 0 && kDcRotorInertiaAtWorm_gm2 <= kDcInertiaAtWorm_gm2[0] &&
                  kDcRotorInertiaAtWorm_gm2 <= kDcInertiaAtWorm_gm2[1] && kDcRotorInertiaAtWorm_gm2 <= kDcInertiaAtWorm_gm2[2],
              "kDcRotorInertiaAtWorm_gm2 in (0, kDcInertiaAtWorm_gm2]: the rotor's inertia is part of each drive's");
static_assert(kDcStandingSpeed_mrad_s > 0 && kDcStandingSpeed_mrad_s <= 50, "kDcStandingSpeed_mrad_s in (0, 50]");
static_assert(kTrackingSlowFrom_mrad > 0 && kTrackingSlowFrom_mrad < kTrackingStopAt_mrad &&
                  kTrackingStopAt_mrad < kTrackingFault_mrad,
              "kTrackingSlowFrom_mrad < kTrackingStopAt_mrad < kTrackingFault_mrad, all positive");
static_assert(kStallTime_ms > 0 && kStallProgress_counts > 0 && kSignDistance_counts > 0 && kMaxStep_counts_per_ms > 0 &&
                  kRailMargin_counts > 0 && kRailTime_ms > 0,
              "kStallTime_ms, kStallProgress_counts, kSignDistance_counts, kMaxStep_counts_per_ms, kRailMargin_counts, kRailTime_ms: positive");

}  // namespace config
}  // namespace wmra
