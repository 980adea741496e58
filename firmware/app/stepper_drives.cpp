// The stepper joints J1, J5, J6: ramps tracking references, J1's stop (stepper_drives.h).
#include "app/stepper_drives.h"

#include <util/atomic.h>

#include "app/arm.h"
#include "app/flash_config.h"
#include "config/derived.h"
#include "core/base_inertia.h"
#include "core/gravity.h"
#include "drivers/inputs.h"
#include "drivers/steppers.h"

namespace wmra {
namespace app {
namespace stepper_drives {

namespace {

using namespace config;

const control::StepRateConstants kRampConstantsInFlash[3] PROGMEM = {kRampConstants[0], kRampConstants[1], kRampConstants[2]};
fx::Real g_j1_stop_speed{0x7FFFFFFF};  // J1's speed from which the hand stops within kStopTravel_mm
const control::StepRateConstants kJ1RampInFlash[4] PROGMEM = {kJ1RampConstants[0], kJ1RampConstants[1], kJ1RampConstants[2],
                                                              kJ1RampConstants[3]};
uint8_t g_j1_level = 0;  // the index of J1's acceleration in kJ1AccelMultiples (its ramp's and its tracking's)
// the way J5 may not turn (it would lift the wrist with more than its motor's planned torque):
// 0 none, +1 or -1
int8_t g_j5_no_lift = 0;

void set_j1_level(uint8_t level) {
  if (level == g_j1_level) return;
  g_j1_level = level;
  steppers::rate(0).set_acceleration(from_flash(kJ1RampInFlash[level]));
}

// With interrupts off: the stop hook (the safety button's interrupt) reads the interval.
void set_j1_stop(const control::StopConstants& k) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { steppers::rate(0).configure_stop(k); }
}

// One stepper's ramp follows its joint's reference. A template per stepper: with the stepper a
// constant, its map's scales are constants and their shifts fixed (a shift by a run-time count
// is a loop).
template <uint8_t kStepper>
void track_one() {
  constexpr uint8_t j = kStepperJoint[kStepper];
  steppers::Rate& rate = steppers::rate(kStepper);
  const int32_t error = kStepperMap[kStepper].steps(g_arm.q.q.q[j]) - rate.position_steps();
  const core::StepperTracking& tracking = kStepper == 0 ? kJ1Tracking[g_j1_level] : kTracking[kStepper];
  rate.set_speed(core::tracking_speed_steps_s(tracking, kStepperMap[kStepper].speed_steps_s(g_arm.q.qd_rad_s[j]), error));
}

}  // namespace

void configure() {
  for (uint8_t i = 0; i < 3; ++i) {
    steppers::rate(i).configure(from_flash(kRampConstantsInFlash[i]));
    steppers::rate(i).configure_stop(kStopConstants[i]);
  }
}

void track() {
  track_one<0>();
  track_one<1>();
  track_one<2>();
}

void references_from_counts() {
  for (uint8_t i = 0; i < 3; ++i) g_arm.q.set(kStepperJoint[i], angle(i));
}

fx::Angle angle(uint8_t i) { return angle_of(i, steppers::rate(i).position_steps()); }
int32_t steps_of(uint8_t i, fx::Angle a) { return kStepperMap[i].steps(a); }
fx::Angle angle_of(uint8_t i, int32_t steps) { return kStepperMap[i].angle(steps); }

void use_largest_j1_stop() {
  set_j1_stop(kStopConstants[0]);
  set_j1_level(0);
  g_arm.j1_max_change_per_tick = kJ1MaxChangeAtWorst;
  g_arm.j1_max_brake_per_tick = kJ1MaxChangePerTick[0];
}

// The deceleration above the start/stop rate stays the largest inertia's: with the speed bound
// J1 runs faster than the start/stop rate only within 0.13 m of the base axis (the two speeds'
// ratio squared is 2 kStopTravel_mm N_r / (3 gear r)), and a division for it costs ~650 cycles.
void update_j1_stop(const kin::JacobianTrig<kin::Fixed>& trig) {
  const core::BaseLoad load = core::base_load(trig);
  const uint16_t inertia_gm2 = (uint16_t)(load.inertia_gm2 + kJ1RotorAtJoint_gm2);
  const uint16_t interval = fx::isqrt32((uint32_t)inertia_gm2 * kJ1StartStopInterval2_per_gm2_q8 >> 8);
  set_j1_stop(control::StopConstants{kStopConstants[0].dv_q8_per_tick, interval});
  const uint16_t reach_mm = load.hand_reach_mm > 50 ? load.hand_reach_mm : 50;
  uint32_t speed2_q4 = kJ1StopSpeed2_q4 / fx::mul_uu(inertia_gm2, reach_mm);
  if (speed2_q4 > (1ul << 27)) speed2_q4 = 1ul << 27;
  const uint16_t speed_mrad_s = fx::isqrt32(speed2_q4 << 4);
  g_j1_stop_speed = fx::Real{(int32_t)fx::mul_uu(speed_mrad_s, 8388)};  // Q23 rad/s: 8,388.6 a mrad/s
  uint8_t level = 0;
  while (level + 1 < sizeof(kJ1AccelMultiples) && fx::mul_uu(inertia_gm2, kJ1AccelMultiples[level + 1]) <= kJ1WorstInertia_gm2) ++level;
  set_j1_level(level);
  const fx::Real limit = kJ1MaxChangePerTick[level];
  g_arm.j1_max_brake_per_tick = limit;
  const uint32_t change = kJ1LagAccelPerTick_q23_x16 / fx::mul_uu(inertia_gm2, reach_mm) * 16;
  g_arm.j1_max_change_per_tick = fx::Real{(int32_t)(change < (uint32_t)limit.raw ? change : limit.raw)};
}

// The torque left beyond gravity's, over the wrist's largest inertia (with J5's rotor through
// its gear), is J5's acceleration: a change per tick (Q23 rad/s) per Q14 of the planned torque,
// x 2^10. At least kJ5FloorAccel_crad_s2 (where it cannot lift, its drive stops the lift).
constexpr double kJ5Inertia_kgm2 = kStepperLoadInertia_gm2[1] * 1e-3 + kStepperRotorInertia_gcm2[1] * 1e-7 * stepper_gear(1) * stepper_gear(1);
constexpr uint16_t kJ5ChangePerQ14_x1024 =
    (uint16_t)(core::gravity_detail::kJ5PlannedTorque_Nm / kJ5Inertia_kgm2 / kLoopHz * 8388608.0 / 16384.0 * 1024.0);
static_assert(core::gravity_detail::kJ5PlannedTorque_Nm / kJ5Inertia_kgm2 / kLoopHz * 8388608.0 / 16384.0 * 1024.0 < 65536.0,
              "J5's acceleration per Q14 of its torque fits 16 bits");
constexpr int16_t kJ5FloorAccel_crad_s2 = 35;
constexpr fx::Real kJ5FloorChange = accel_per_tick(kJ5FloorAccel_crad_s2);

void update_wrist_load(const kin::JacobianTrig<kin::Fixed>& trig) {
  const int16_t gravity = core::wrist_gravity_q14(trig);
  const int16_t left = (int16_t)(16384 - (gravity < 0 ? -gravity : gravity));
  // lifting turns J5 against gravity
  g_arm.j5_lift_way = gravity > 0 ? -1 : gravity < 0 ? 1 : 0;
  g_j5_no_lift = left > 0 ? 0 : g_arm.j5_lift_way;
  const uint32_t change = left > 0 ? fx::mul_uu((uint16_t)left, kJ5ChangePerQ14_x1024) >> 10 : 0;
  g_arm.j5_max_change_per_tick = fx::Real{(int32_t)(change > (uint32_t)kMaxSpeedChangePerTick[4].raw ? kMaxSpeedChangePerTick[4].raw
                                                    : change < (uint32_t)kJ5FloorChange.raw ? kJ5FloorChange.raw : change)};
}

// (the DC joints' speeds are the governor's, set just before or at its last run)
void limit_speeds(bool resolved_rate) {
  core::DriveSpeeds& drives = g_arm.drives;
  for (uint8_t i = 0; i < 3; ++i) {
    const uint8_t j = kStepperJoint[i];
    drives.positive_rad_s[j] = drives.negative_rad_s[j] = kMotionLimits.joint[j].speed_rad_s;
  }
  if (g_j1_stop_speed.raw < kMotionLimits.joint[0].speed_rad_s.raw) drives.positive_rad_s[0] = drives.negative_rad_s[0] = g_j1_stop_speed;
  // (the creep of a closed switch's stop: J^-1's rounding turns J5 a little in many motions)
  if (resolved_rate && g_j5_no_lift > 0) drives.positive_rad_s[4] = core::kCreepTowardsClosedSwitch_rad_s;
  if (resolved_rate && g_j5_no_lift < 0) drives.negative_rad_s[4] = core::kCreepTowardsClosedSwitch_rad_s;
  core::stop_towards_switches(drives, inputs::closed_switches() & kSwitchesArmed);
}

}  // namespace stepper_drives
}  // namespace app
}  // namespace wmra
