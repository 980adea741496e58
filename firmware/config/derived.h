// What the firmware derives from the configuration headers at compile time: the joints' maps
// (steps and pot units to angles), the steppers' ramps and stops, the DC servos' gains and
// feedforward, the homing and the joint moves' limits; and the checks that span more than one
// configuration header. Nothing here is set by hand: change the figures in the other config
// headers. Every table is a constexpr, so a value out of range stops the build here.
#pragma once

#include <stdint.h>

#include "config/control_config.h"
#include "config/joints_config.h"
#include "config/motion_config.h"
#include "config/stop_config.h"
#include "control/joystick.h"
#include "control/step_rate.h"
#include "core/dc_servo.h"
#include "core/homing.h"
#include "core/joint_map.h"
#include "core/joint_move.h"
#include "core/resolved_rate.h"
#include "core/stepper_tracking.h"
#include "core/wrist_homing.h"
#include "drivers/steppers.h"
#include "drivers/uart.h"
#include "kinematics/arm_model.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace config {

constexpr double kTwoPi = 2 * core::kPi;

// --- the stepper joints' steps
constexpr core::StepperMap kStepperMap[3] = {core::StepperMap::make(kStepsPerJointTurn[0]),
                                              core::StepperMap::make(kStepsPerJointTurn[1]),
                                              core::StepperMap::make(kStepsPerJointTurn[2])};
constexpr int32_t steps_of(uint8_t i, double turns) { return (int32_t)(turns * kStepsPerJointTurn[i] + (turns < 0 ? -0.5 : 0.5)); }
constexpr int32_t steps_per_s(uint8_t i, int16_t crad_s) { return steps_of(i, crad_s / 100.0 / kTwoPi); }
constexpr int32_t steps_of_deg(uint8_t i, int16_t deg) { return steps_of(i, deg / 360.0); }
constexpr int32_t steps_of_mdeg(uint8_t i, int32_t mdeg) { return steps_of(i, mdeg / 360000.0); }

constexpr core::MotionLimits kLimits = core::motion_limits();
// The one copy read at run time, defined in app/motion.cpp: every file that indexed the constexpr
// at run time would hold a copy of its own in RAM (156 B each).
extern const core::MotionLimits kMotionLimits;

// --- the steppers' ramps, tracking and stops
constexpr control::StepRateConfig kRampConfig[3] = {
    {steps_per_s(0, kStepperAccel_crad_s2[0]), kStepMinInterval_ticks, kStepMaxInterval_ticks},
    {steps_per_s(1, kStepperAccel_crad_s2[1]), kStepMinInterval_ticks, kStepMaxInterval_ticks},
    {steps_per_s(2, kStepperAccel_crad_s2[2]), kStepMinInterval_ticks, kStepMaxInterval_ticks}};
// the ramps' slowest speed (steps/s): a step per kStepMaxInterval_ticks
constexpr int32_t kSlowestStep_steps_s = (int32_t)(steppers::kTickHz / kStepMaxInterval_ticks);
constexpr core::StepperTracking kTracking[3] = {{kStepperPositionGain_per_s, kRampConfig[0].accel_steps_s2, kSlowestStep_steps_s},
                                                {kStepperPositionGain_per_s, kRampConfig[1].accel_steps_s2, kSlowestStep_steps_s},
                                                {kStepperPositionGain_per_s, kRampConfig[2].accel_steps_s2, kSlowestStep_steps_s}};
constexpr control::StepRateConstants ramp_constants(uint8_t i) {
  return control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, kRampConfig[i]);
}
constexpr control::StepRateConstants kRampConstants[3] = {ramp_constants(0), ramp_constants(1), ramp_constants(2)};
static_assert(kRampConstants[0].status == control::RateStatus::ok && kRampConstants[1].status == control::RateStatus::ok &&
                  kRampConstants[2].status == control::RateStatus::ok,
              "a stepper's acceleration or top speed does not fit its ramp (lib/control/step_rate.h)");
// J1's ramp and tracking at each of kJ1AccelMultiples (stop_config.h)
constexpr control::StepRateConfig j1_ramp_config(uint8_t level) {
  return {kRampConfig[0].accel_steps_s2 * kJ1AccelMultiples[level], kStepMinInterval_ticks, kStepMaxInterval_ticks};
}
constexpr control::StepRateConstants kJ1RampConstants[4] = {
    control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, j1_ramp_config(0)),
    control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, j1_ramp_config(1)),
    control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, j1_ramp_config(2)),
    control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, j1_ramp_config(3))};
static_assert(kJ1RampConstants[1].status == control::RateStatus::ok && kJ1RampConstants[2].status == control::RateStatus::ok &&
                  kJ1RampConstants[3].status == control::RateStatus::ok,
              "kJ1AccelMultiples: J1's fastest acceleration does not fit its ramp (lib/control/step_rate.h)");
constexpr core::StepperTracking kJ1Tracking[4] = {{kStepperPositionGain_per_s, j1_ramp_config(0).accel_steps_s2, kSlowestStep_steps_s},
                                                  {kStepperPositionGain_per_s, j1_ramp_config(1).accel_steps_s2, kSlowestStep_steps_s},
                                                  {kStepperPositionGain_per_s, j1_ramp_config(2).accel_steps_s2, kSlowestStep_steps_s},
                                                  {kStepperPositionGain_per_s, j1_ramp_config(3).accel_steps_s2, kSlowestStep_steps_s}};
constexpr control::StopConstants stop_constants(uint8_t i) {
  return control::stop_constants(steppers::kTickHz, steppers::kServiceHz, kStopDecel_steps_s2[i], (uint32_t)kStartStop_steps_s[i]);
}
constexpr control::StopConstants kStopConstants[3] = {stop_constants(0), stop_constants(1), stop_constants(2)};
constexpr bool stepper_speeds_ok(uint8_t i) {
  return kHomingFast_crad_s[i] <= kJointSpeedLimit_crad_s[kStepperJoint[i]] &&
         steps_per_s(i, kJointSpeedLimit_crad_s[kStepperJoint[i]]) * kStepMinInterval_ticks < 250000;
}
static_assert(stepper_speeds_ok(0) && stepper_speeds_ok(1) && stepper_speeds_ok(2),
              "kHomingFast_crad_s at most the joint's kJointSpeedLimit_crad_s, and that limit within the fastest "
              "step (kStepMinInterval_ticks of 4 us) at kStepsPerJointTurn");

// --- every joint reference's largest change of speed per tick
constexpr fx::Real accel_per_tick(int16_t crad_s2) { return fx::real(Ratio{crad_s2, 100 * (int32_t)kLoopHz}); }
constexpr fx::Real kMaxSpeedChangePerTick[6] = {accel_per_tick(kJointAccelLimit_crad_s2[0]), accel_per_tick(kJointAccelLimit_crad_s2[1]),
                                               accel_per_tick(kJointAccelLimit_crad_s2[2]), accel_per_tick(kJointAccelLimit_crad_s2[3]),
                                               accel_per_tick(kJointAccelLimit_crad_s2[4]), accel_per_tick(kJointAccelLimit_crad_s2[5])};
static_assert(kJointAccelLimit_crad_s2[0] * 10 <= kStepperAccel_crad_s2[0] * 9 &&
                  kJointAccelLimit_crad_s2[4] * 10 <= kStepperAccel_crad_s2[1] * 9 &&
                  kJointAccelLimit_crad_s2[5] * 10 <= kStepperAccel_crad_s2[2] * 9,
              "a stepper's reference accelerates at most 90 % of its ramp's limit, or the ramp cannot catch up");
// J1's reference's at each of kJ1AccelMultiples
constexpr fx::Real kJ1MaxChangePerTick[4] = {
    accel_per_tick(kJointAccelLimit_crad_s2[0] * kJ1AccelMultiples[0]), accel_per_tick(kJointAccelLimit_crad_s2[0] * kJ1AccelMultiples[1]),
    accel_per_tick(kJointAccelLimit_crad_s2[0] * kJ1AccelMultiples[2]), accel_per_tick(kJointAccelLimit_crad_s2[0] * kJ1AccelMultiples[3])};
// a DC reference's largest change of speed in one tick
constexpr int32_t max_of(int32_t a, int32_t b) { return a > b ? a : b; }
// J1's at the largest inertia and the farthest reach (1.1 m), until the pose is known
constexpr fx::Real kJ1MaxChangeAtWorst{(int32_t)(kJ1LagAccelPerTick_q23_x16 * 16.0 / (kStepperLoadInertia_gm2[0] * 1100.0))};
static_assert(kJ1MaxChangeAtWorst.raw > 0 && kJ1MaxChangeAtWorst.raw <= kMaxSpeedChangePerTick[0].raw,
              "kJ1LagTravel_um: J1's acceleration at the worst pose above 0 and within kJointAccelLimit_crad_s2[0]");
constexpr int32_t kMaxDcChange =
    max_of(max_of(kMaxSpeedChangePerTick[kDcJoint[0]].raw, kMaxSpeedChangePerTick[kDcJoint[1]].raw), kMaxSpeedChangePerTick[kDcJoint[2]].raw);
static_assert(kMaxDcChange < 32768, "a DC reference's change of speed in one tick fits 16 bits");

constexpr int16_t permille_q15(int16_t permille) { return (int16_t)((int32_t)permille * 32767 / 1000); }

// --- the joystick
constexpr control::JoystickConfig kStickConfig{1023,
                                               kStickRailMargin_counts,
                                               kStickRailTicks,
                                               kStickCalibrationSamples,
                                               kStickCalibrationSpread_counts,
                                               kStickCentreTolerance_counts,
                                               permille_q15(kStickDeadZone_permille),
                                               permille_q15(kStickExpo_permille),
                                               (int16_t)(32767 / kStickRise_ms),
                                               (int16_t)(32767 / kStickFall_ms),
                                               kStickNeutral_ms,
                                               kStickFullDeflection_counts,
                                               kStickStoredCentreTolerance_counts};
static_assert(control::joystick_check(kStickConfig), "joystick configuration");

// --- the DC drives' feedforward
// The duty beyond the stiction's a motion needs as the PID's effort: the dead-zone inverse maps
// effort e to min + e (1 - min) (lib/control/pid.h), and the stiction's min duty is what the
// worm's friction takes while the joint runs, so the model's duty is divided by that slope:
// 1 / slope = 1 + (1 / slope - 1), a 16x16 product.
constexpr int32_t kDutySlope_permille = 1000 - kDcMinDuty_permille;
constexpr int16_t kInverseSlopeLess1_q16 = (int16_t)(65536.0 * kDcMinDuty_permille / kDutySlope_permille + 0.5);
static_assert(kDcMinDuty_permille * 3 < 1000, "1 / slope - 1 below a half: a Q16 fraction in 16 bits");
// the inertia's feedforward: duty per change of the reference speed in one tick, Q8 of
// (Q15 duty per Q23 rad/s) x 2^16: J_worm x gear x loop rate / stall torque at the worm
constexpr int32_t accel_feedforward_q8(int16_t inertia_gm2, uint8_t d) {
  return (int32_t)(inertia_gm2 / 1000.0 * kDcGear_tenths[d] / 10.0 * kLoopHz / (kDcStallTorque_cNm / 100.0) *
                       32768.0 / 8388608.0 * 65536.0 +
                   0.5);
}
static_assert(accel_feedforward_q8(kDcInertiaAtWorm_gm2[0], 0) < 32768 && accel_feedforward_q8(kDcInertiaAtWorm_gm2[1], 1) < 32768 &&
                  accel_feedforward_q8(kDcInertiaAtWorm_gm2[2], 2) < 32768,
              "the inertia's feedforward fits 16 bits");
// Slowing down, a self-locking worm stops the links itself: the drive brakes its rotor only.
// With the whole inertia the braking feedforward takes J2's effort away early enough that it
// stops short of its slowing reference (16 mrad, the hand 12 mm high after S1's release).
constexpr int16_t brake_feedforward_q8(uint8_t d) {
  return (int16_t)accel_feedforward_q8(kDcSelfLocking ? kDcRotorInertiaAtWorm_gm2 : kDcInertiaAtWorm_gm2[d], d);
}
struct DcFeedforward {
  fx::Unit per_speed;  // effort (Q15 through a Unit) per rad/s of reference speed
  int16_t accel_q8;    // per change of the reference speed in a tick, speeding up
  int16_t brake_q8;    // and slowing down
};
constexpr DcFeedforward kDcFeedforward[3] = {
    {fx::unit(Ratio{100, kDcFullDutySpeed_crad_s[0]}), (int16_t)accel_feedforward_q8(kDcInertiaAtWorm_gm2[0], 0), brake_feedforward_q8(0)},
    {fx::unit(Ratio{100, kDcFullDutySpeed_crad_s[1]}), (int16_t)accel_feedforward_q8(kDcInertiaAtWorm_gm2[1], 1), brake_feedforward_q8(1)},
    {fx::unit(Ratio{100, kDcFullDutySpeed_crad_s[2]}), (int16_t)accel_feedforward_q8(kDcInertiaAtWorm_gm2[2], 2), brake_feedforward_q8(2)}};
constexpr int32_t kDcStandingSpeed = fx::real(Ratio{kDcStandingSpeed_mrad_s, 1000}).raw;

// --- the speed governor: the duty that moves a DC joint at its speed limit without load (Q15),
// and the planned share of each drive's full-duty speed
constexpr int16_t kUsableDuty_q15 = permille_q15(kDutySlope_permille);
constexpr int16_t kPlannedDuty_q15 = permille_q15(1000 - kDcDutyReserve_permille);
constexpr int16_t limit_duty_q15(uint8_t d) { return (int16_t)(32767L * kJointSpeedLimit_crad_s[kDcJoint[d]] / kDcFullDutySpeed_crad_s[d]); }
constexpr int16_t kLimitDuty_q15[3] = {limit_duty_q15(0), limit_duty_q15(1), limit_duty_q15(2)};
constexpr fx::Real planned_speed(uint8_t d) {
  return fx::Real{fx::mul_q15_const(fx::real(Ratio{kDcFullDutySpeed_crad_s[d], 100}).raw, kPlannedDuty_q15)};
}
constexpr fx::Real kPlannedSpeed[3] = {planned_speed(0), planned_speed(1), planned_speed(2)};
static_assert(kJointSpeedLimit_crad_s[kDcJoint[0]] <= kDcFullDutySpeed_crad_s[0] &&
                  kJointSpeedLimit_crad_s[kDcJoint[1]] <= kDcFullDutySpeed_crad_s[1] &&
                  kJointSpeedLimit_crad_s[kDcJoint[2]] <= kDcFullDutySpeed_crad_s[2],
              "a DC joint's speed limit within what its drive reaches at full duty");
// the relay's fixed duty is not governed: it must not drive a joint past its speed limit (at
// 600 permille J3 would turn at about 2 rad/s against 1.0)
constexpr bool relay_within_limit(uint8_t d) {
  return kRelayDuty_permille <= kDcMinDuty_permille + (int32_t)kDutySlope_permille * kLimitDuty_q15[d] / 32767;
}
static_assert(!kDcUseRelay || (relay_within_limit(0) && relay_within_limit(1) && relay_within_limit(2)),
              "the relay's duty within every DC joint's speed limit");

// --- the DC servos
// a pot's reading at a rail (open, shorted wiper), in pot units: below the low one or above the high
constexpr int16_t kPotRailLow_units = kRailMargin_counts * kPositionUnitsPerCount;
constexpr int16_t kPotRailHigh_units = (1023 - kRailMargin_counts) * kPositionUnitsPerCount;
constexpr core::DcServoConfig dc_servo_config(uint8_t d) {
  return core::DcServoConfig{
      kDcUseRelay,
      control::PidConfig{control::pid_gains(kDcKp[d], kDcKi_per_s[d], kDcKd_s[d], kLoopHz, kPositionUnitsPerCount).gains, 32767,
                         (int16_t)(32767 / kDcRampTime_ms), permille_q15(kDcMinDuty_permille), permille_q15(kDcZeroBand_permille)},
      control::RelayConfig{kRelayDeadZone_counts * kPositionUnitsPerCount, 0, permille_q15(kRelayDuty_permille)},
      control::PlausibilityConfig{permille_q15(kStallDuty_permille), (uint16_t)kStallTime_ms,
                                  (int16_t)(kStallProgress_counts * kPositionUnitsPerCount), (uint16_t)kSignGrace_ms,
                                  (int16_t)(kSignDistance_counts * kPositionUnitsPerCount),
                                  (int16_t)(kMaxStep_counts_per_ms * kPositionUnitsPerCount),
                                  kPotRailLow_units, kPotRailHigh_units, (uint8_t)kRailTime_ms},
      (int16_t)(kDcParkBand_counts * kPositionUnitsPerCount), (uint16_t)kDcParkTime_ms, (uint16_t)kDcUnparkTime_ms,
      permille_q15(kDcMovingFrictionDuty_permille)};
}
constexpr core::DcServoConfig kDcServoConfig[3] = {dc_servo_config(0), dc_servo_config(1), dc_servo_config(2)};
// configure() refuses what these refuse, at boot, and leaves that joint without its servo
constexpr bool dc_servo_ok(uint8_t d) {
  return control::pid_gains(kDcKp[d], kDcKi_per_s[d], kDcKd_s[d], kLoopHz, kPositionUnitsPerCount).ok &&
         control::pid_check(kDcServoConfig[d].pid) == control::PidStatus::ok &&
         control::relay_check(kDcServoConfig[d].relay) == control::RelayStatus::ok &&
         control::plausibility_check(kDcServoConfig[d].checks) == control::PlausibilityStatus::ok &&
         core::dc_servo_limits_ok(kDcServoConfig[d]);
}
static_assert(dc_servo_ok(0) && dc_servo_ok(1) && dc_servo_ok(2),
              "kDcKp, kDcKi_per_s, kDcKd_s: each gain fits its 16-bit format at kPositionUnitsPerCount (Kp Q4, Ki Q8 "
              "per tick, Kd per tick: pid.h's pid_gains), and the DC servos' limits pass pid_check, relay_check, "
              "plausibility_check");
// a DC joint's lag thresholds (kTracking*_mrad) in pot units come from its calibration at run
// time (dc_drives.cpp's lag_units): the Angle counts per mrad, Q24
constexpr uint32_t kAngleCountsPerMrad_q24 = (uint32_t)(core::kAngleCountsPerRad / 1000.0 * 16777216.0 + 0.5);
static_assert(kAngleCountsPerMrad_q24 < (1ul << 30), "ah kl + al kh fits 31 bits");
static_assert(kTrackingSlowFrom_mrad > 0 && kTrackingStopAt_mrad < 1024 && kTrackingFault_mrad < 1024 &&
                  1023 * 16 * 1023L < (1L << 24),
              "a calibration's span of pot units (< 2^14) times a lag in mrad fits 24 bits");
static_assert(1023 * kPositionUnitsPerCount < 32768, "pot units of a 10-bit reading fit 16 bits");

// --- homing: J1 to its high switch, J5 to its low one, J6 to its zero switch's turn
constexpr uint16_t kHomingSwitch[2] = {1u << 1, 1u << 8};  // J1 high, J5 low (inputs.h's bits)
static_assert(kHomingDir[0] > 0 && kHomingDir[1] < 0, "J1 homes to its high switch, J5 to its low one");
constexpr core::HomingConfig homing_config(uint8_t i) {
  return core::HomingConfig{kHomingDir[i],
                            steps_per_s(i, kHomingFast_crad_s[i]),
                            steps_per_s(i, kHomingSlow_crad_s[i]),
                            steps_of_deg(i, kHomingBackOff_deg[i]),
                            steps_of_deg(i, kHomeSwitch_deg[i]),
                            steps_of_deg(i, kHomingMaxTravel_deg[i]),
                            steps_per_s(i, kHomingSlow_crad_s[i]) * kSwitchDelay_ms / 1000};
}
constexpr core::HomingConfig kHomingConfig[2] = {homing_config(0), homing_config(1)};
constexpr core::WristHomingConfig kWristHomingConfig{
    (int32_t)kStepsPerJointTurn[2],
    steps_of_deg(2, arm::q_max_deg[5]),
    steps_of_deg(2, kHomeSwitch_deg[2]),
    steps_of_deg(2, kHomingBackOff_deg[2]),
    steps_of_mdeg(2, kJ6AngleTolerance_mdeg),
    steps_per_s(2, kHomingFast_crad_s[2]),
    steps_per_s(2, kHomingSlow_crad_s[2]),
    steps_per_s(2, kHomingFast_crad_s[2]) * kSwitchDelay_ms / 1000,
    steps_per_s(2, kHomingSlow_crad_s[2]) * kSwitchDelay_ms / 1000,
    2 * kSwitchDelay_ms,
    kHomingDir[2],
    {steps_of_deg(2, kJ6Sweep_deg[0]), steps_of_deg(2, kJ6Sweep_deg[1]), steps_of_deg(2, kJ6Sweep_deg[2]),
     steps_of_deg(2, kJ6Sweep_deg[3])}};
static_assert(-arm::q_min_deg[5] == arm::q_max_deg[5] && arm::q_max_deg[5] % 360 == 0,
              "J6's range whole turns either way: its ends are switches (core/wrist_homing.h)");
// Once J6 is homed its zero switch closes only within this of a whole turn: the cam's half width,
// what J6 turns at its speed limit while the switch's filter lets the closing (and the opening)
// through late, the count's age (the stick's loop counts J6's steps every fourth tick) and 1 deg.
constexpr int32_t kJ6ZeroWatch_steps =
    steps_of_deg(2, kHomeSwitch_deg[2]) + steps_per_s(2, kJointSpeedLimit_crad_s[5]) * (kSwitchDelay_ms + 4) / 1000 + steps_of_deg(2, 1);
static_assert(kJ6ZeroWatch_steps < (int32_t)kStepsPerJointTurn[2] / 4, "J6's zero switch watch tells a turn's switch from another's");

// --- joint-space moves (to the ready pose, to a stored pose: core/joint_move.h)
constexpr fx::Real move_speed(uint8_t j) {
  return fx::real(Ratio{(int32_t)kJointSpeedLimit_crad_s[j] * kJointMoveSpeed.num, 100 * (int32_t)kJointMoveSpeed.den});
}
constexpr fx::Real joint_accel(uint8_t j) { return fx::real(Ratio{kJointAccelLimit_crad_s2[j], 100}); }
// the farthest the frame-6 origin can be from each joint's axis, over core::kReachScale_m: J1
// the arm's reach from the base axis; J2 a2 + a3 + a4 + d6; J3 a3 + a4 + d6; J4 a4 + d6; J5 d6;
// J6 none (the origin is on its axis)
constexpr fx::Unit reach(double m) { return fx::Unit{(int16_t)(m / core::kReachScale_m * 32768.0)}; }
constexpr core::JointMoveLimits kMoveLimits{
    {move_speed(0), move_speed(1), move_speed(2), move_speed(3), move_speed(4), move_speed(5)},
    {joint_accel(0), joint_accel(1), joint_accel(2), joint_accel(3), joint_accel(4), joint_accel(5)},
    {reach(arm::a1_m + arm::a2_m + arm::a3_m + arm::a4_m + arm::d6_m), reach(arm::a2_m + arm::a3_m + arm::a4_m + arm::d6_m),
     reach(arm::a3_m + arm::a4_m + arm::d6_m), reach(arm::a4_m + arm::d6_m), reach(arm::d6_m), fx::Unit{0}},
    fx::real(Ratio{kMaxHandSpeed_m_s.num * 1000, (int32_t)(kMaxHandSpeed_m_s.den * 1000 * core::kReachScale_m)}),
    fx::real(kMaxWristSpeed_rad_s)};
static_assert(arm::a1_m + arm::a2_m + arm::a3_m + arm::a4_m + arm::d6_m < core::kReachScale_m, "the reaches as Units below 1");
// At the line's end each stepper settles onto its target step by a position move (tracking
// the reference there, a step's error asks for the slowest speed, whose scheduled edge then
// overshoots by a step: it hunts), at most at a tenth of its joint's speed limit.
constexpr control::MoveSpeed settle_speed(uint8_t i) {
  return control::move_speed(kRampConstants[i], (uint32_t)steps_per_s(i, (int16_t)(kJointSpeedLimit_crad_s[kStepperJoint[i]] / 10)));
}
constexpr control::MoveSpeed kSettleSpeed[3] = {settle_speed(0), settle_speed(1), settle_speed(2)};

// --- the drift correction's velocity for a position error (Q23 m): beyond the largest / gain
// the product is clamped anyway, and within it the error fits 16 bits
constexpr int32_t kMaxCorrection = (int32_t)(kDriftMaxCorrection_mm_s / 1000.0 * core::kRealPerRad);
constexpr int32_t kMaxCorrectedError = kDriftGain_per_s > 0 ? kMaxCorrection / kDriftGain_per_s : 0;
static_assert(kMaxCorrectedError < 65536, "the drift correction's error within its clamp fits 16 bits");
static_assert(kDriftMaxCorrection_mm_s * 3 * kMaxHandSpeed_m_s.den <= kMaxHandSpeed_m_s.num * 1000,
              "kDriftMaxCorrection_mm_s at most a third of kMaxHandSpeed_m_s: a larger correction bends the hand's line");

// --- the serial link reads at most kMaxRxBytesPerTick a tick: at least what the line brings (10
// bits a byte), or the receive ring overflows under a steady stream; more than the ring holds is
// moot
static_assert(kMaxRxBytesPerTick * 10ul * kLoopHz > board::kSerialBaud && kMaxRxBytesPerTick <= uart::kRxBytes,
              "kMaxRxBytesPerTick: above the serial line's bytes per tick, at most the receive ring's size");

}  // namespace config
}  // namespace wmra
