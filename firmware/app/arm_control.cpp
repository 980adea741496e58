#include "app/arm_control.h"

#include <avr/pgmspace.h>
#include <util/atomic.h>

#include "app/settings.h"
#include "app/velocity_request.h"
#include "app/wrist_angle.h"
#include "config/control_config.h"
#include "config/joints_config.h"
#include "config/stop_config.h"
#include "control/button.h"
#include "control/joystick.h"
#include "core/base_inertia.h"
#include "core/dc_servo.h"
#include "core/faults.h"
#include "core/gravity.h"
#include "core/homing.h"
#include "core/joint_move.h"
#include "core/joint_acceleration.h"
#include "core/joint_map.h"
#include "core/ready_roll.h"
#include "core/resolved_rate.h"
#include "core/rest_watch.h"
#include "core/stepper_tracking.h"
#include "core/stick_twist.h"
#include "core/wrist_homing.h"
#include "drivers/adc_scan.h"
#include "drivers/bridges.h"
#include "drivers/inputs.h"
#include "drivers/steppers.h"
#include "drivers/system_tick.h"
#include "drivers/uart.h"
#include "kinematics/forward_kinematics.h"
#include "wmra_mega/board.h"

// Start-up, state changes, the status report and the joint-space moves (homing, to the ready
// pose: no kinematics) are optimised for size, so that the stick's iteration can stay at -O3
// within the 64 KB flash budget (3 KB less).
#define WMRA_COLD __attribute__((cold, optimize("Os")))
// Small per-tick work whose cycles matter less than its flash (the load model, the drives' speeds)
#define WMRA_SMALL __attribute__((noinline, optimize("Os")))

namespace wmra {
namespace app {

namespace {

using kin::Fixed;
using namespace config;

// --- joints and their drives
constexpr uint8_t kStepperJoint[3] = {0, 4, 5};  // J1, J5, J6: steppers::rate(i)
constexpr uint8_t kDcJoint[3] = {1, 2, 3};       // J2, J3, J4: bridges::set(d)
// One sweep per tick (adc_scan.h) from kAdcSweepPhase_us on: the pots are converted 0.52 to
// 0.83 ms into the tick and read at the next, 0.2 to 0.5 ms old. Older readings made the DC
// joints catch up their lag harder (S7: J3 1.06 rad/s against its 1.0 limit when the pots were
// converted first in a sweep from the loop's start).
constexpr uint8_t kAdcOrder[5] = {board::kAdcJoystickX, board::kAdcJoystickY, board::kAdcPotJ2, board::kAdcPotJ3,
                                  board::kAdcPotJ4};
constexpr uint8_t kAdcStickX = 0, kAdcStickY = 1, kAdcPot = 2;  // indices of the results
constexpr uint16_t kAdcSweepPhase_us = 310;
static_assert(kAdcSweepPhase_us + sizeof kAdcOrder * 104 + 30 < 1000, "the sweep done before the next tick reads it");
constexpr double kTwoPi = 2 * core::kPi;

constexpr core::StepperMap kStepperMap[3] = {core::StepperMap::make(kStepsPerJointTurn[0]),
                                              core::StepperMap::make(kStepsPerJointTurn[1]),
                                              core::StepperMap::make(kStepsPerJointTurn[2])};
constexpr int32_t steps_of(uint8_t i, double turns) { return (int32_t)(turns * kStepsPerJointTurn[i] + (turns < 0 ? -0.5 : 0.5)); }
constexpr int32_t steps_per_s(uint8_t i, int16_t crad_s) { return steps_of(i, crad_s / 100.0 / kTwoPi); }
constexpr int32_t steps_of_deg(uint8_t i, int16_t deg) { return steps_of(i, deg / 360.0); }

constexpr core::MotionLimits kLimits = core::motion_limits();

constexpr control::StepRateConfig kRampConfig[3] = {
    {steps_per_s(0, kStepperAccel_crad_s2[0]), kStepMinInterval_ticks, kStepMaxInterval_ticks},
    {steps_per_s(1, kStepperAccel_crad_s2[1]), kStepMinInterval_ticks, kStepMaxInterval_ticks},
    {steps_per_s(2, kStepperAccel_crad_s2[2]), kStepMinInterval_ticks, kStepMaxInterval_ticks}};
constexpr core::StepperTracking kTracking[3] = {{kStepperPositionGain_per_s, kRampConfig[0].accel_steps_s2},
                                                {kStepperPositionGain_per_s, kRampConfig[1].accel_steps_s2},
                                                {kStepperPositionGain_per_s, kRampConfig[2].accel_steps_s2}};
// each joint reference's largest change of speed per tick
constexpr fx::Real accel_per_tick(int16_t crad_s2) { return fx::real(Ratio{crad_s2, 100 * (int32_t)kLoopHz}); }
constexpr fx::Real kMaxSpeedChangePerTick[6] = {accel_per_tick(kJointAccelLimit_crad_s2[0]), accel_per_tick(kJointAccelLimit_crad_s2[1]),
                                               accel_per_tick(kJointAccelLimit_crad_s2[2]), accel_per_tick(kJointAccelLimit_crad_s2[3]),
                                               accel_per_tick(kJointAccelLimit_crad_s2[4]), accel_per_tick(kJointAccelLimit_crad_s2[5])};
// and per motion pass, which runs every kMotionPeriod_ticks
constexpr uint8_t kMotionPeriod_ticks = kDrivePeriod_ticks;
constexpr fx::Real kMaxSpeedChangePerPass[6] = {
    fx::Real{kMaxSpeedChangePerTick[0].raw * kMotionPeriod_ticks}, fx::Real{kMaxSpeedChangePerTick[1].raw * kMotionPeriod_ticks},
    fx::Real{kMaxSpeedChangePerTick[2].raw * kMotionPeriod_ticks}, fx::Real{kMaxSpeedChangePerTick[3].raw * kMotionPeriod_ticks},
    fx::Real{kMaxSpeedChangePerTick[4].raw * kMotionPeriod_ticks}, fx::Real{kMaxSpeedChangePerTick[5].raw * kMotionPeriod_ticks}};
static_assert(kJointAccelLimit_crad_s2[0] * 10 <= kStepperAccel_crad_s2[0] * 9 &&
                  kJointAccelLimit_crad_s2[4] * 10 <= kStepperAccel_crad_s2[1] * 9 &&
                  kJointAccelLimit_crad_s2[5] * 10 <= kStepperAccel_crad_s2[2] * 9,
              "a stepper's reference accelerates at most 90 % of its ramp's limit, or the ramp cannot catch up");
constexpr control::StepRateConstants ramp_constants(uint8_t i) {
  return control::step_rate_constants(steppers::kTickHz, steppers::kServiceHz, kRampConfig[i]);
}
constexpr control::StepRateConstants kRampConstants[3] = {ramp_constants(0), ramp_constants(1), ramp_constants(2)};
constexpr control::StopConstants stop_constants(uint8_t i) {
  return control::stop_constants(steppers::kTickHz, steppers::kServiceHz, kStopDecel_steps_s2[i], (uint32_t)kStartStop_steps_s[i]);
}
constexpr control::StopConstants kStopConstants[3] = {stop_constants(0), stop_constants(1), stop_constants(2)};
static_assert(kRampConstants[0].status == control::RateStatus::ok && kRampConstants[1].status == control::RateStatus::ok &&
                  kRampConstants[2].status == control::RateStatus::ok,
              "a stepper's acceleration or top speed does not fit its ramp (lib/control/step_rate.h)");

// a joint-space move's step per tick (Angle counts) as a speed
constexpr int32_t kRealPerAngleCountPerTick = (int32_t)(core::kRealPerRad * kLoopHz / core::kAngleCountsPerRad + 0.5);

constexpr int16_t permille_q15(int16_t permille) { return (int16_t)((int32_t)permille * 32767 / 1000); }

// The duty beyond the stiction's a motion needs as the PID's effort: the dead-zone inverse maps
// effort e to min + e (1 - min) (lib/control/pid.h), and the stiction's min duty is what the
// worm's friction takes while the joint runs, so the model's duty is divided by that slope.
constexpr int32_t kDutySlope_permille = 1000 - kDcMinDuty_permille;
// 1 / slope = 1 + (1 / slope - 1): one 16x16 product and a shift by whole bytes (a 32-bit
// division is ~600 cycles, a shift by 15 a loop)
constexpr int16_t kInverseSlopeLess1_q16 = (int16_t)(65536.0 * kDcMinDuty_permille / kDutySlope_permille + 0.5);
static_assert(kDcMinDuty_permille * 3 < 1000, "1 / slope - 1 below a half: a Q16 fraction in 16 bits");
// |duty| <= 32767 in, the effort saturated to +-32767 out: all in 16 bits (the rounded high
// half of the product is a byte move; the sum's overflow flag saturates it)
// (inlined into run_dc_servo, the every-run caller: its call saved and restored registers on
// both sides; update_holding calls it out of line, seven times)
inline __attribute__((always_inline)) int16_t effort_for_duty_inline(int16_t duty_q15) {
  const int16_t extra = (int16_t)fx::hi16((uint32_t)(fx::mul_ss(duty_q15, kInverseSlopeLess1_q16) + 32768));
  int16_t effort;
  if (__builtin_add_overflow(duty_q15, extra, &effort)) return duty_q15 < 0 ? (int16_t)-32767 : (int16_t)32767;
  return effort == -32768 ? (int16_t)-32767 : effort;
}
__attribute__((noinline)) int16_t effort_for_duty(int16_t duty_q15) { return effort_for_duty_inline(duty_q15); }
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
// With the whole inertia the braking feedforward took J2's effort away early enough that it
// stopped 16 mrad short of its slowing reference (the hand 12 mm high after S1's release).
constexpr int16_t brake_feedforward_q8(uint8_t d) {
  return (int16_t)accel_feedforward_q8(kDcSelfLocking ? kDcRotorInertiaAtWorm_gm2 : kDcInertiaAtWorm_gm2[d], d);
}
// a DC joint's feedforward constants together (one address for run_dc_servo)
struct DcFeedforward {
  fx::Unit per_speed;  // effort (Q15 through a Unit) per rad/s of reference speed
  int16_t accel_q8;    // per change of the reference speed in a tick, speeding up
  int16_t brake_q8;    // and slowing down
};
constexpr DcFeedforward kDcFeedforward[3] = {
    {fx::unit(Ratio{100, kDcFullDutySpeed_crad_s[0]}), (int16_t)accel_feedforward_q8(kDcInertiaAtWorm_gm2[0], 0), brake_feedforward_q8(0)},
    {fx::unit(Ratio{100, kDcFullDutySpeed_crad_s[1]}), (int16_t)accel_feedforward_q8(kDcInertiaAtWorm_gm2[1], 1), brake_feedforward_q8(1)},
    {fx::unit(Ratio{100, kDcFullDutySpeed_crad_s[2]}), (int16_t)accel_feedforward_q8(kDcInertiaAtWorm_gm2[2], 2), brake_feedforward_q8(2)}};

constexpr uint16_t kHomingSwitch[2] = {1u << 1, 1u << 8};  // J1 high, J5 low (J6: its zero switch, g_wrist)
constexpr uint16_t kSwitchesArmedHoming = kSwitchesArmed & ~(1u << 1) & ~(1u << 8);
static_assert(kHomingDir[0] > 0 && kHomingDir[1] < 0, "J1 homes to its high switch, J5 to its low one");
constexpr bool stepper_speeds_ok(uint8_t i) {
  return kHomingFast_crad_s[i] <= kJointSpeedLimit_crad_s[kStepperJoint[i]] &&
         steps_per_s(i, kJointSpeedLimit_crad_s[kStepperJoint[i]]) * kStepMinInterval_ticks < 250000;
}
static_assert(stepper_speeds_ok(0) && stepper_speeds_ok(1) && stepper_speeds_ok(2),
              "kHomingFast_crad_s at most the joint's kJointSpeedLimit_crad_s, and that limit within the fastest "
              "step (kStepMinInterval_ticks of 4 us) at kStepsPerJointTurn");

// --- the periodic jobs' schedule
// Every periodic job of the running loop has a fixed phase of one counter, g_phase, which
// advances by one each iteration (as the slots do: after an overrun no job is skipped and none
// runs twice), so that no tick carries two of the heavy ones. The motion pass and the drives'
// loops alternate (joints_config.h); the holding effort and the speed governor, the drives'
// plan, go to the drives' ticks, each on its own, the governor half a period after the holding
// update it follows (it read the holding duties of the same tick; 4 ticks later it reads the
// same ones); the drift correction's hand position goes with the holding effort (the same trig):
//   phase      0         1         2         3         4          5         6         7
//   slot       drives    motion    drives    motion    drives     motion    drives    motion
//   jobs       holding,            steppers            governor or          steppers
//              drift FK                                J1's stop, in turn
// Without the motion pass (homing, a move to a pose, its brake) the holding update and the
// governor run a tick earlier, in the idle motion slot (dc_tick).
// The state frame (link::poll, every 20 ms after the iteration, about 6,500 cycles) keeps its
// phase of the clock, not of this counter.
// The holding effort: the load and with it the drives' speeds change with the pose, slowly: at
// a joint's top speed the pose moves 16 mrad between updates. The speed governor's bounds and
// the drives' speeds every second update: between those the angle sums the load depends on (q2,
// q2 + q3, q2 + q3 + q4) move at most 16, 32 and 58 mrad at the DC joints' speed limits, which
// changes a holding duty of at most 70 % (J3 stretched) by at most 4 % of full duty, within the
// 10 % reserve the plan keeps for the PID (kDcDutyReserve_permille). (All of it every 16 ticks,
// the holding effort itself too, turned the hand in S2 by 0.91 deg where it was 0.78.)
constexpr uint8_t kHoldingPeriod_ticks = 8;
// The drift correction's hand position (FK, ~1,100 cycles, of which the trig is the holding
// effort's): its time constant is 1 / kDriftGain_per_s (200 ms), and the error it corrects
// (fixed-point rounding of the integrated references) grows over seconds. (In the motion pass,
// every fourth tick, it made that pass the loop's longest tick: 12,260 cycles in R1.)
constexpr uint8_t kDriftEvery_ticks = kHoldingPeriod_ticks;
static_assert(kDriftEvery_ticks * kDriftGain_per_s <= 1000 / 20, "the correction updated 20 times per time constant");
static_assert(kHandPositionAge_ms >= 2 * kDriftEvery_ticks, "the report takes the drift correction's position after an overrun too");
constexpr uint8_t kSchedulePeriod_ticks = kHoldingPeriod_ticks;
constexpr uint8_t kHoldingPhase = kDriveSlot;
static_assert(kSchedulePeriod_ticks % kDrivePeriod_ticks == 0 && kSchedulePeriod_ticks % kStepperPeriod_ticks == 0 &&
                  kHoldingPeriod_ticks == kSchedulePeriod_ticks,
              "every job's period divides the schedule's");
constexpr uint8_t kGovernorPhase = (uint8_t)((kHoldingPhase + kSchedulePeriod_ticks / 2) % kSchedulePeriod_ticks);
static_assert(kGovernorPhase != kHoldingPhase, "the holding update and the speed governor on different ticks");
// the tick before each: the motion pass's (it keeps its trig for the holding update), and the
// holding update's and the governor's without the stick's motion pass (dc_tick)
constexpr uint8_t kEarlyHoldingPhase = (kHoldingPhase + kSchedulePeriod_ticks - 1) % kSchedulePeriod_ticks;
constexpr uint8_t kEarlyGovernorPhase = (kGovernorPhase + kSchedulePeriod_ticks - 1) % kSchedulePeriod_ticks;
static_assert(kHoldingPhase % kStepperPeriod_ticks != kStepperSlot && kGovernorPhase % kStepperPeriod_ticks != kStepperSlot,
              "the steppers' ramps on ticks without the holding update and the speed governor");
static_assert(kHoldingPhase % kDrivePeriod_ticks == kDriveSlot && kGovernorPhase % kDrivePeriod_ticks == kDriveSlot,
              "the drives' plan in the drives' slot");

// --- state
core::Supervisor g_supervisor;
core::ArmState g_prev_state = core::ArmState::boot;
control::Joystick g_stick;
control::Button g_button;
// The DC servos are built at boot from one copy of their start state in flash rather than copied
// from .data, which holds an initialised object whole, zeros too (3 x 125 bytes)
const core::DcServo kServoAtBoot PROGMEM{};
union DcServos {
  DcServos() {
    for (uint8_t d = 0; d < 3; ++d) memcpy_P(&servo[d], &kServoAtBoot, sizeof servo[d]);
  }
  core::DcServo servo[3];
} g_servos;
static_assert(__is_trivially_copyable(core::DcServo), "a servo's bytes are its state");
core::DcServo (&g_servo)[3] = g_servos.servo;
// A DC joint's state that its servo's run reads, together: run_dc_servo reaches every field
// from one address (a table per field cost an address sum each, ~100 cycles a run)
struct DcJoint {
  int16_t units;            // measured, ADC counts x 16 (< 16,368)
  int16_t reference_units;  // the reference in pot units, as the last dc_tick drove it (PotMap::units)
  int16_t lag_fault_units;  // capped at 32767: a reference less a reading is at most 32,752
  int16_t holding_q15;      // the holding effort's duty at the reference pose (core::HoldingEffort)
  int16_t holding_effort_q15;  // the same as the servo's effort (through the dead-zone inverse)
  int16_t still_units;      // where it came to rest after a stop (watch_standstill)
  int16_t standstill_units;  // kStandstillMove_mdeg in pot units (configure_pot)
  fx::Real qd_prev;         // the reference's speed of the last dc_tick (its acceleration)
  core::PotMap pot;
};
DcJoint g_dc[3];
uint8_t g_phase;           // this iteration's phase of the schedule (kSchedulePeriod_ticks, below)
uint8_t g_servo_elapsed;   // control ticks since the DC servos last ran (in one slot, all three)
uint8_t g_ramp_elapsed;    // and since the stepper ramps last ran
uint8_t g_motion_elapsed;  // and since the motion pass last ran (or the stick took over)
uint8_t g_stick_elapsed;   // and since the stick was last sampled
uint8_t g_wrist_elapsed;   // and since J6's zero switch and rest were last watched (watch_wrist)
int32_t g_lag_slow_units[3], g_lag_stop_units[3];
int16_t g_lag_inverse[3];  // 32767 / (stop - slow)
core::StepperHoming g_homing[2];  // J1, J5
core::WristHoming g_wrist;         // J6
core::RestWatch g_wrist_rest;      // when J6's angle is recorded
core::JointReferences g_q;  // joint references
fx::Real (&g_qd)[6] = g_q.qd_rad_s;  // joint reference velocities
bool g_holding_governs;         // the last update is one the speed governor follows (every second)
bool g_governor_due;            // and the governor has not run since
kin::Vec3<fx::Real> g_v_m_s;  // the hand's commanded velocity, as far as g_qd has reached it
kin::Vec3<fx::Real> g_p_cmd;  // the hand's commanded position (drift correction)
kin::Vec3<fx::Real> g_drift_m_s;  // the drift correction, held between its updates
kin::Vec3<fx::Real> g_p_hand;  // the drift correction's hand position (FK of the references), for the report
kin::JacobianTrig<Fixed> g_pass_trig;  // the last motion pass's (the holding update reads it, update_holding)
kin::Vec3<fx::Real> g_kept_p_cmd;      // the commanded position the pass before the holding update started from
bool g_kept;                           // that pass ran, and the holding update has not yet read them
uint32_t g_p_hand_ms = 0u - kHandPositionAge_ms;  // and tick::now_ms() when it was (none yet: too old)
uint32_t g_faults;            // latched
uint16_t g_ms;
uint16_t g_hold_ms;  // since the drives were last held (a stop), saturating
fx::Real g_j1_stop_speed{0x7FFFFFFF};  // J1's speed from which the hand stops within kStopTravel_mm
uint16_t g_overrun_ms;  // reported while > 0: long enough for telemetry to see one missed tick
constexpr uint16_t kOverrunReport_ms = 500;
bool g_homed;
bool g_at_target;
bool g_moving;     // a joint move in running (to a stored pose), or the person taking one over
bool g_line_done;  // the move's references are on its target: the joints settle onto it
bool g_streaming;      // the last iteration's motion followed a streamed velocity
bool g_stream_halted;  // the stream stopped arriving: the joints halted, the stick waits for rest
uint8_t g_stream_halt_ms;
core::JointMove g_move;
kin::Vec3<fx::Real> g_move_p;  // the hand at the move's last measurement (hand_per_lead)
int32_t g_move_lead_at;        // and the lead joint's reference then
bool g_move_p_valid;
fx::Unit g_move_hand;          // the last measurement (0: none yet)
fx::Unit g_speed_scale;  // set_speed_scale(): 100 % from start() on
int32_t g_gripper_us_q15;  // pulse width, us x 32768
bool g_gripper_driven;     // the servo has a pulse: the person has moved the gripper since power-up
Settings* g_settings;
Status g_status;

bool stick_invalid(const control::JoystickOutput& stick) {
  return stick.status & (control::kJoystickRailX | control::kJoystickRailY);
}

// --- drives on, holding and off

// J1's stop follows the arm's inertia about the base axis (config/stop_config.h) while the
// pose is known; in homing, and before it, the stop's constants for the largest inertia. (With
// interrupts off: the stop hook reads the interval.)
void set_j1_stop(const control::StopConstants& k) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { steppers::rate(0).configure_stop(k); }
}

// The stop (SPEC 6): the bridges brake (both sides low: the worms hold), each stepper's train
// ends at once or ramps down at its stop's deceleration (steppers::halt_trains), its driver
// enabled: the arm holds where it stopped and the step counts stay the joints' angles. The
// stop hook (the safety button's and the switches' interrupts) has done the same already. The
// DC references stand where the joints are; the standstill watch starts.
WMRA_COLD void hold_drives() {
  bridges::all_off();
  steppers::halt_trains();
  for (uint8_t d = 0; d < 3; ++d) {
    g_servo[d].rest(g_dc[d].units);
    g_q.set(kDcJoint[d], g_dc[d].pot.angle(g_dc[d].units));
  }
  for (uint8_t j = 0; j < 6; ++j) g_qd[j] = fx::Real{0};
  g_hold_ms = 0;
}

// The steppers' drivers off (EN high): a released joint may be moved by hand or by gravity, so
// its count is no longer its angle and the steppers are homed again before the next motion.
WMRA_COLD void drives_off() {
  steppers::kill();
  bridges::all_off();
  g_homed = false;
}

// While the arm stands (stopped, faulted, waiting for the stick): a DC joint whose pot moves
// more than kStandstillMove_mdeg from where it came to rest is a fault (a slipping worm, a
// broken gear); and the optional release of the steppers' drivers.
WMRA_COLD void watch_standstill(uint8_t ticks) {
  const uint16_t before_ms = g_hold_ms;
  g_hold_ms = before_ms > 0xFFFFu - ticks ? 0xFFFFu : (uint16_t)(before_ms + ticks);
  if (before_ms < kStandstillSettle_ms) {
    if (g_hold_ms >= kStandstillSettle_ms) {
      for (uint8_t d = 0; d < 3; ++d) g_dc[d].still_units = g_dc[d].units;
    }
    return;
  }
  for (uint8_t d = 0; d < 3; ++d) {
    const int16_t moved = (int16_t)(g_dc[d].units - g_dc[d].still_units);
    if (moved > g_dc[d].standstill_units || moved < -g_dc[d].standstill_units)
      g_faults |= core::fault_mask(core::kFaultBitMovedWhileStopped);
  }
  if (kStepperReleaseAfterStop_ms != 0 && before_ms < kStepperReleaseAfterStop_ms && g_hold_ms >= kStepperReleaseAfterStop_ms)
    drives_off();
}

void outputs_on() {
  steppers::enable_drivers(true);
  bridges::enable();
}

// The DC references start at rest where the joints are (a stop at speed left their last speeds,
// whose change would be one tick's braking feedforward). The outputs stay off when the safety
// button or a switch stopped the arm after this iteration read them (the next one stops).
WMRA_COLD void drives_on() {
  steppers::resume();
  g_governor_due = false;  // not from holding duties of before the drives went off
  for (uint8_t d = 0; d < 3; ++d) {
    g_servo[d].rest(g_dc[d].units);
    g_q.set(kDcJoint[d], g_dc[d].pot.angle(g_dc[d].units));
    g_dc[d].reference_units = g_dc[d].units;
    g_dc[d].qd_prev = fx::Real{0};
  }
  for (uint8_t i = 0; i < 3; ++i) g_q.set(kStepperJoint[i], kStepperMap[i].angle(steppers::rate(i).position_steps()));
  inputs::enable_unless_stopped(&outputs_on);
}

// The move after homing goes to the ready pose with J6 at the ready angle's turn nearest where J6
// homed (core/ready_roll.h), worked out in the homing's last tick: the move's first tick is the
// heaviest of a start-up (240 cycles more with it there).
int32_t g_ready_angle[6];
WMRA_COLD void plan_ready_pose() {
  for (uint8_t j = 0; j < 6; ++j) g_ready_angle[j] = g_settings->pose_angle[0][j];
  constexpr int32_t kSlack = fx::angle_deg(Ratio{kSoftLimitMargin_deg + kHomeSwitch_deg[2], 1}).raw;
  g_ready_angle[5] = core::ready_roll(g_ready_angle[5], g_q.q.q[5].raw, fx::kAngleTurn, kLimits.joint[5].soft_min.raw,
                                      kLimits.joint[5].soft_max.raw, kSlack);
}

// --- homing

WMRA_COLD void homing_tick(uint16_t switches, uint8_t ticks) {
  bool all_done = true;
  for (uint8_t i = 0; i < 2; ++i) {
    g_homing[i].update((switches & kHomingSwitch[i]) != 0, steppers::running(i), steppers::rate(i));
    if (g_homing[i].failed()) g_faults |= core::fault_mask(core::kFaultBitHomingFailed);
    if (!g_homing[i].done()) all_done = false;
  }
  g_wrist.update((switches & inputs::kJ6ZeroSwitch) != 0, steppers::running(2), ticks, steppers::rate(2));
  if (g_wrist.failed()) g_faults |= core::fault_mask(core::kFaultBitHomingFailed);
  if (!g_wrist.done()) all_done = false;
  if (g_wrist.take_contradiction()) {  // the recorded angle is wrong: the next power-up sweeps
    wrist_angle::forget();
    g_wrist_rest.clear_recorded();
  }
  for (uint8_t i = 0; i < 3; ++i) g_q.set(kStepperJoint[i], kStepperMap[i].angle(steppers::rate(i).position_steps()));
  if (all_done && !g_homed) plan_ready_pose();
  g_homed = all_done;
}

// --- resolved rate

// how much the DC joints' lag allows: 1 up to the slow-down lag, 0 at the stop lag. The
// references in pot units are each servo's last run's (a tick old at most: at a DC joint's
// top speed 1.6 mrad, against lags of 15 and 50 mrad; after
// drives_on, where they were set to the measured angles, the measured units: the lag is then
// the round trip's rounding, far below the slow-down lag), which saves three conversions.
fx::Unit tracking_factor() {
  int32_t f = fx::kUnitOne;
  for (uint8_t d = 0; d < 3; ++d) {
    int32_t lag = g_dc[d].reference_units - g_dc[d].units;
    if (lag < 0) lag = -lag;
    if (lag <= g_lag_slow_units[d]) continue;
    const int32_t fd = lag >= g_lag_stop_units[d] ? 0 : (g_lag_stop_units[d] - lag) * g_lag_inverse[d];
    if (fd < f) f = fd;
  }
  return fx::Unit{(int16_t)(f > fx::kUnitOne ? fx::kUnitOne : f)};
}

// What each joint's drive can do now (updated with the holding effort): a DC joint lifting its
// load has the duty beyond its holding effort and the reserve; the steppers' ramps follow their
// speed limits.
core::DriveSpeeds g_drives = {{kLimits.joint[0].speed_rad_s, kLimits.joint[1].speed_rad_s, kLimits.joint[2].speed_rad_s,
                               kLimits.joint[3].speed_rad_s, kLimits.joint[4].speed_rad_s, kLimits.joint[5].speed_rad_s},
                              {kLimits.joint[0].speed_rad_s, kLimits.joint[1].speed_rad_s, kLimits.joint[2].speed_rad_s,
                               kLimits.joint[3].speed_rad_s, kLimits.joint[4].speed_rad_s, kLimits.joint[5].speed_rad_s},
                              0};

// The steppers' drives at their speed limits (J1's at most the one it stops from within
// kStopTravel_mm at the hand: update_j1_stop), and no drive towards a switch that is closed
// (the DC joints' speeds are the governor's, set just before or at its last run)
WMRA_COLD void stop_drives_at_switches() {
  for (uint8_t i = 0; i < 3; ++i) {
    const uint8_t j = kStepperJoint[i];
    g_drives.positive_rad_s[j] = g_drives.negative_rad_s[j] = kLimits.joint[j].speed_rad_s;
  }
  if (g_j1_stop_speed.raw < kLimits.joint[0].speed_rad_s.raw) g_drives.positive_rad_s[0] = g_drives.negative_rad_s[0] = g_j1_stop_speed;
  core::stop_towards_switches(g_drives, inputs::closed_switches() & kSwitchesArmed);
}

// the drift correction's velocity for a position error (Q23 m): error x gain, within the
// largest correction. Beyond the largest / gain the product is clamped anyway, and within it
// the error fits 16 bits: one 16x16 product (a 32-bit one is a library call, ~100 cycles).
constexpr int32_t kMaxCorrection = (int32_t)(kDriftMaxCorrection_mm_s / 1000.0 * core::kRealPerRad);
constexpr int32_t kMaxCorrectedError = kDriftGain_per_s > 0 ? kMaxCorrection / kDriftGain_per_s : 0;
static_assert(kMaxCorrectedError < 65536, "the drift correction's error within its clamp fits 16 bits");
static_assert(kDriftMaxCorrection_mm_s * 3 * kMaxHandSpeed_m_s.den <= kMaxHandSpeed_m_s.num * 1000,
              "kDriftMaxCorrection_mm_s at most a third of kMaxHandSpeed_m_s: a larger correction bends the hand's line");
// the link reads at most kMaxRxBytesPerTick a tick: at least what the line brings (10 bits a
// byte), or the receive ring overflows under a steady stream; more than the ring holds is moot
static_assert(kMaxRxBytesPerTick * 10ul * kLoopHz > board::kSerialBaud && kMaxRxBytesPerTick <= uart::kRxBytes,
              "kMaxRxBytesPerTick: above the serial line's bytes per tick, at most the receive ring's size");
fx::Real drift_correction(int32_t error) {
  if (error > kMaxCorrectedError) return fx::Real{kDriftGain_per_s > 0 ? kMaxCorrection : 0};
  if (error < -kMaxCorrectedError) return fx::Real{kDriftGain_per_s > 0 ? -kMaxCorrection : 0};
  const int32_t c = (int32_t)fx::mul_uu((uint16_t)(error < 0 ? -error : error), (uint16_t)kDriftGain_per_s);
  return fx::Real{error < 0 ? -c : c};
}

// The servo gets no pulse until the person first moves the stick in the gripper mode: the first
// pulse sends it to kGripperStart_us from wherever it is, which must never happen unasked
// (passing through the mode with the stick neutral moves nothing).
void gripper_tick(int16_t stick_y_q15, uint8_t ticks) {
  if (stick_y_q15 == 0 && !g_gripper_driven) return;
  g_gripper_driven = true;
  constexpr core::Scale kRate = core::scale_for(kGripperRate_us_per_s / (double)kLoopHz);
  constexpr int32_t kMin = (int32_t)kGripperMin_us << 15, kMax = (int32_t)kGripperMax_us << 15;
  g_gripper_us_q15 += core::apply(kRate, stick_y_q15) * ticks;  // us x 32768 per tick: y/32768 x rate x 32768
  if (g_gripper_us_q15 < kMin) g_gripper_us_q15 = kMin;
  if (g_gripper_us_q15 > kMax) g_gripper_us_q15 = kMax;
  tick::set_servo_pulse_us((uint16_t)(g_gripper_us_q15 >> 15));
}

// A stepper's ramp follows its joint's reference. One copy per stepper: with the stepper a
// constant its scales' shifts are constants too (a shift by a run-time count is a loop);
// flattened, so that apply() stays inlined with them whatever iterate's inlining budget (it
// was called out of line once the DC servos' loop left iterate: +27 cycles a tick, +332 B).
template <uint8_t kStepper>
__attribute__((flatten)) void track_stepper() {
  constexpr uint8_t j = kStepperJoint[kStepper];
  steppers::Rate& rate = steppers::rate(kStepper);
  const int32_t error = kStepperMap[kStepper].steps(g_q.q.q[j]) - rate.position_steps();
  rate.set_speed(core::tracking_speed_steps_s(kTracking[kStepper], kStepperMap[kStepper].speed_steps_s(g_qd[j]), error));
}

// The commanded position over the ticks that passed at once: each step times ticks is the
// same sum as a tick at a time. Flattened: apply() inlined with its constant Scale shifts by
// whole bytes (motion_tick called it for two of the three, its shift a loop by a run-time count).
__attribute__((flatten, noinline)) void integrate_commanded(uint8_t ticks) {
  constexpr core::Scale kPerTick = core::scale_for(1.0 / kLoopHz);
  // (a component at rest, most of a mode's, moves nothing: no product)
  if (g_v_m_s.x.raw != 0) g_p_cmd.x.raw += core::ticks_times(core::apply(kPerTick, g_v_m_s.x.raw), ticks);
  if (g_v_m_s.y.raw != 0) g_p_cmd.y.raw += core::ticks_times(core::apply(kPerTick, g_v_m_s.y.raw), ticks);
  if (g_v_m_s.z.raw != 0) g_p_cmd.z.raw += core::ticks_times(core::apply(kPerTick, g_v_m_s.z.raw), ticks);
}

__attribute__((noinline)) void motion_tick(const control::JoystickOutput& stick, const Requests& rq, uint8_t ticks) {
  const kin::JointAngles<Fixed>& q = g_q.q;
  // no joint 6: the twist, the hand's position and J^-1 do not use it (one sine and cosine less)
  kin::fill_jacobian_trig<Fixed>(q, g_pass_trig);  // in place: a copy for the holding update is a byte loop
  const kin::JacobianTrig<Fixed>& trig = g_pass_trig;

  const config::Mode mode = g_supervisor.mode();
  // initialised from the call (an assignment copied the returned twist, a 24-byte loop)
  // (w about the wrist axes, where J^-1 takes it: a telemetry command's turned there)
  kin::TwistWrist<Fixed> twist = rq.velocity_fresh
                                   ? velocity_twist(rq, trig)
                                   : core::stick_twist(mode, core::Stick{fx::Unit{stick.x_q15}, fx::Unit{stick.y_q15}});
  if (!rq.velocity_fresh && mode == config::Mode::gripper) {
    gripper_tick(config::kStickYSign > 0 ? stick.y_q15 : (int16_t)-stick.y_q15, ticks);
  }
  // both are one most of the time, and so is the factor: core::scaled then needs no product
  const fx::Unit tracking = tracking_factor();
  const fx::Unit factor = g_speed_scale.raw == fx::kUnitOne ? tracking : g_speed_scale * tracking;
  // (tested once here: scaled() tests it again for each of the six)
  if (factor.raw != fx::kUnitOne) {
    twist.v_m_s = {core::scaled(factor, twist.v_m_s.x), core::scaled(factor, twist.v_m_s.y), core::scaled(factor, twist.v_m_s.z)};
    twist.w5_rad_s = {core::scaled(factor, twist.w5_rad_s.x), core::scaled(factor, twist.w5_rad_s.y),
                      core::scaled(factor, twist.w5_rad_s.z)};
  }

  // the drift correction (update_drift's, held between its updates) goes into the twist in place
  // (a copy of the twist is a 24-byte loop); the commanded velocity, without it, is what the
  // commanded position integrates
  const kin::Vec3<fx::Real> v_cmd = twist.v_m_s;
  twist.v_m_s.x = v_cmd.x + g_drift_m_s.x;
  twist.v_m_s.y = v_cmd.y + g_drift_m_s.y;
  twist.v_m_s.z = v_cmd.z + g_drift_m_s.z;

  kin::JacobianInverse<Fixed> inv = kin::inverse_jacobian_wrist<Fixed>(trig, twist);
  const core::RateScale rates = core::rate_scale(q, trig, inv, kLimits, g_drives);
  const uint8_t slowed_by = g_drives.closed_switches ? core::named_switch_stop(rates.slowed_by, inv, g_drives.closed_switches) : rates.slowed_by;
  g_status.slowed_by = (uint8_t)(slowed_by | (tracking.raw < fx::kUnitOne ? core::kSlowTracking : 0));
  fx::Real max_change[6];  // a pass's is the table (32-bit products otherwise)
  if (ticks != kMotionPeriod_ticks) {
    for (uint8_t j = 0; j < 6; ++j) max_change[j] = fx::Real{kMaxSpeedChangePerTick[j].raw * ticks};
  }
  const fx::Unit k = core::limit_joint_acceleration(g_qd, inv.qd_rad_s, rates.scale, ticks == kMotionPeriod_ticks ? kMaxSpeedChangePerPass : max_change);
  // the hand's commanded velocity as far as g_qd has reached it; neither limit slowing it (most
  // ticks), g + (v - g) is v itself
  if (k.raw == fx::kUnitOne && rates.scale.raw == fx::kUnitOne) {
    g_v_m_s = v_cmd;
  } else {
    g_v_m_s.x = g_v_m_s.x + core::scaled(k, core::scaled(rates.scale, v_cmd.x) - g_v_m_s.x);
    g_v_m_s.y = g_v_m_s.y + core::scaled(k, core::scaled(rates.scale, v_cmd.y) - g_v_m_s.y);
    g_v_m_s.z = g_v_m_s.z + core::scaled(k, core::scaled(rates.scale, v_cmd.z) - g_v_m_s.z);
  }
  if (g_phase == kEarlyHoldingPhase) {  // (by component: a Vec3's assignment is a byte loop)
    g_kept_p_cmd.x = g_p_cmd.x;
    g_kept_p_cmd.y = g_p_cmd.y;
    g_kept_p_cmd.z = g_p_cmd.z;
    g_kept = true;
  }
  integrate_commanded(ticks);
  g_q.advance_ticks(ticks);
}

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

// A move from the references to `angles` (its line's shares follow over the next ticks)
WMRA_COLD void begin_move(const int32_t* angles) {
  int32_t from[6];
  for (uint8_t j = 0; j < 6; ++j) {
    from[j] = g_q.q.q[j].raw;
    g_qd[j] = fx::Real{0};
  }
  g_move.begin(from, angles);
  g_at_target = g_line_done = g_move_p_valid = false;
  g_move_hand = fx::Unit{0};
}

int32_t target_steps(uint8_t i) { return kStepperMap[i].steps(fx::Angle{g_move.target()[kStepperJoint[i]]}); }

// The hand's speed per unit of the move's lead joint's, from the hand's position (the references'
// FK) now and at the last measurement, once the lead has moved 32 counts (0.8 mrad) since:
// |dp| / dtheta_lead, as a Unit of m/rad over core::kReachScale_m (0: none yet).
WMRA_COLD fx::Unit hand_per_lead() {
  const kin::Vec3<fx::Real> p = kin::hand_position<Fixed>(kin::jacobian_trig<Fixed>(g_q.q));
  const int32_t lead_at = g_q.q.q[g_move.lead()].raw;
  if (g_move_p_valid) {
    const uint32_t dtheta = (uint32_t)(lead_at > g_move_lead_at ? lead_at - g_move_lead_at : g_move_lead_at - lead_at);
    // the components in Q19 m (within 16 bits: at most 7 mm in 4 ticks at the joints' limits)
    const int16_t dx = (int16_t)((p.x.raw - g_move_p.x.raw) >> 4), dy = (int16_t)((p.y.raw - g_move_p.y.raw) >> 4),
                  dz = (int16_t)((p.z.raw - g_move_p.z.raw) >> 4);
    const uint32_t dp_q19 = fx::isqrt32((uint32_t)fx::mul_ss(dx, dx) + (uint32_t)fx::mul_ss(dy, dy) + (uint32_t)fx::mul_ss(dz, dz));
    if (dtheta < 32) return g_move_hand;  // the baseline kept until the lead has moved enough
    // |dp| 2^-19 m / (dtheta / kAngleCountsPerRad rad) / 1.25 m x 2^15
    constexpr uint16_t kScale = (uint16_t)(core::kAngleCountsPerRad * 32768.0 / 524288.0 / core::kReachScale_m + 1);
    const uint32_t q15 = fx::mul_uu((uint16_t)(dp_q19 > 0xFFFF ? 0xFFFF : dp_q19), kScale) / dtheta;
    g_move_hand = fx::Unit{(int16_t)(q15 > 32767 ? 32767 : q15 == 0 ? 1 : q15)};
  }
  g_move_p = p;
  g_move_lead_at = lead_at;
  g_move_p_valid = true;
  return g_move_hand;
}

// A move's tick, every tick of it: the line's shares first (one a tick), then its speed cap
// every fourth tick (phases 1 and 5, which carry neither the holding update nor the governor),
// the references along the line, the steppers tracking them. Arrived: the references on the
// target, every stepper at rest on it and every DC joint's pot within the tolerance of it (the
// pots' angles, a conversion each, only then).
WMRA_COLD void move_tick(uint8_t phase) {
  if (!g_move.prepared()) {
    if (g_move.prepare(kMoveLimits)) g_move.set_speed_cap(kMoveLimits, g_drives, g_speed_scale, tracking_factor());
  } else if (!g_line_done) {
    if ((phase & 3) == 1) g_move.set_speed_cap(kMoveLimits, g_drives, g_speed_scale, tracking_factor(), hand_per_lead());
    int32_t references[6];
    for (uint8_t j = 0; j < 6; ++j) references[j] = g_q.q.q[j].raw;
    if (g_move.tick(references, g_qd)) {
      for (uint8_t j = 0; j < 6; ++j) {
        g_q.set(j, fx::Angle{g_move.target()[j]});
        g_qd[j] = fx::Real{0};
      }
      for (uint8_t i = 0; i < 3; ++i) steppers::rate(i).move_to(target_steps(i), kSettleSpeed[i]);
      g_line_done = true;
    } else {
      g_q.advance_ticks(1);
    }
  }
  if (!g_line_done) {
    track_stepper<0>();
    track_stepper<1>();
    track_stepper<2>();
  }
  bool arrived = g_line_done;
  for (uint8_t i = 0; arrived && i < 3; ++i) {
    if (steppers::rate(i).position_steps() != target_steps(i) || steppers::running(i)) arrived = false;
  }
  constexpr int32_t kTolerance = (int32_t)(kArrivedTolerance_mdeg / 1000.0 / 360.0 * fx::kAngleTurn);
  for (uint8_t d = 0; arrived && d < 3; ++d) {
    const int32_t error = g_dc[d].pot.angle(g_dc[d].units).raw - g_move.target()[kDcJoint[d]];
    if (error > kTolerance || error < -kTolerance) arrived = false;
  }
  g_at_target = arrived;
}

// A stream that stops arriving (no frame for protocol::kVelocityTimeout_ms) halts the joints as
// a stop does, without latching: the bridges brake, the step trains end (or, above a start/stop
// rate, ramp down), and the stick drives again once the trains are at rest and the DC joints
// have had kStreamHalt_ms to come to rest. Ramping the references down along the stick's ramps
// instead let the hand run on 28-34 mm past the last frame (SPEC 6: at rest within 0.3 s of
// it, at most 25 mm from 0.15 m/s; 100 ms of that at full speed before the timeout).
constexpr uint8_t kStreamHalt_ms = 60;
WMRA_COLD void halt_lost_stream() {
  bridges::all_off();
  steppers::halt_trains();
  for (uint8_t j = 0; j < 6; ++j) g_qd[j] = fx::Real{0};
  g_stream_halted = true;
  g_stream_halt_ms = 0;
}

// Every joint's reference where the joint is: a DC joint that arrived within
// kArrivedTolerance_mdeg of a move's target would otherwise go on to it with the stick neutral
// (J3 ended the move to the ready pose 13 mrad short and crept there over 3 s).
WMRA_COLD void start_running() {
  drives_on();
  stop_drives_at_switches();
  g_p_cmd = kin::hand_position<Fixed>(kin::jacobian_trig<Fixed>(g_q.q));
  g_drift_m_s = {fx::Real{0}, fx::Real{0}, fx::Real{0}};  // what it is with the commanded position where the hand is
  g_v_m_s = {fx::Real{0}, fx::Real{0}, fx::Real{0}};
  for (uint8_t j = 0; j < 6; ++j) g_qd[j] = fx::Real{0};
  g_moving = false;
  g_stream_halted = g_streaming = false;
}

WMRA_COLD void enter(core::ArmState state) {
  switch (state) {
    case core::ArmState::homing:
      drives_on();
      set_j1_stop(kStopConstants[0]);
      for (uint8_t i = 0; i < 2; ++i) g_homing[i].restart();
      g_wrist.restart();
      g_homed = false;
      inputs::arm_switches(kSwitchesArmedHoming);
      break;
    case core::ArmState::to_ready:
      if (g_prev_state == core::ArmState::wait_neutral) drives_on();  // the move again after a stop
      begin_move(g_ready_angle);
      inputs::arm_switches(kSwitchesArmed);
      break;
    case core::ArmState::running:
      start_running();
      inputs::arm_switches(kSwitchesArmed);
      break;
    default:
      hold_drives();
      inputs::arm_switches(0);
      break;
  }
}

// Drift correction (while the stick drives): towards the integrated commanded position from the
// hand's position; both are of the same references, sampled together, so the held correction
// has no lag term of its own.
void update_drift(const kin::JacobianTrig<Fixed>& trig, const kin::Vec3<fx::Real>& p_cmd) {
  const kin::Vec3<fx::Real>& p = g_p_hand = kin::hand_position<Fixed>(trig);
  g_p_hand_ms = tick::now_ms();
  g_drift_m_s = {drift_correction((p_cmd.x - p.x).raw), drift_correction((p_cmd.y - p.y).raw),
                 drift_correction((p_cmd.z - p.z).raw)};
}

// J1's stop from the pose: its start/stop interval from the inertia, and the speed from which
// the hand stops within kStopTravel_mm (the drives' bound for J1, applied by
// stop_drives_at_switches). The deceleration above the start/stop rate stays the largest
// inertia's: with the speed bound J1 runs faster than the start/stop rate only within 0.13 m of
// the base axis (the two speeds' ratio squared is 2 kStopTravel_mm N_r / (3 gear r)), and a
// division for it cost ~650 cycles in a tick shared with the serial link.
WMRA_SMALL void update_j1_stop(const kin::JacobianTrig<Fixed>& trig) {
  const core::BaseLoad load = core::base_load(trig);
  const uint16_t inertia_gm2 = (uint16_t)(load.inertia_gm2 + kJ1RotorAtJoint_gm2);
  const uint16_t interval = fx::isqrt32((uint32_t)inertia_gm2 * kJ1StartStopInterval2_per_gm2_q8 >> 8);
  set_j1_stop(control::StopConstants{kStopConstants[0].dv_q8_per_tick, interval});
  const uint16_t reach_mm = load.hand_reach_mm > 50 ? load.hand_reach_mm : 50;
  uint32_t speed2_q4 = kJ1StopSpeed2_q4 / fx::mul_uu(inertia_gm2, reach_mm);
  if (speed2_q4 > (1ul << 27)) speed2_q4 = 1ul << 27;
  const uint16_t speed_mrad_s = fx::isqrt32(speed2_q4 << 4);
  g_j1_stop_speed = fx::Real{(int32_t)fx::mul_uu(speed_mrad_s, 8388)};  // Q23 rad/s: 8,388.6 a mrad/s
}

// The holding effort, and while the stick drives the drift correction, from the references
// trig. While the stick drives, the motion pass a tick before kept its trig and commanded
// position (the references at that pass's start, two ticks old: the load's angle sums move a
// quarter of what they move between two updates, above, and the correction's hand position
// stays paired with its commanded one): a trig of its own made this drives' tick the loop's
// longest (~600 cycles more). Without them (the stick began driving since), the trig of the
// references as they are.
WMRA_SMALL void update_holding(bool stick_drives) {
  const bool kept = stick_drives && g_kept;
  g_kept = false;
  if (!kept) kin::fill_jacobian_trig<Fixed>(g_q.q, g_pass_trig);
  const kin::JacobianTrig<Fixed>& trig = g_pass_trig;
  const core::HoldingEffort holding = core::holding_effort(trig);
  for (uint8_t d = 0; d < 3; ++d) {
    const int16_t h = g_dc[d].holding_q15 = holding.duty_q15[d];
    g_dc[d].holding_effort_q15 = effort_for_duty(h);
  }
  if (stick_drives) update_drift(trig, kept ? g_kept_p_cmd : g_p_cmd);
}

// the speed governor, from the holding duties of the last update
WMRA_SMALL void update_governor() {
  // the model plans with the duty beyond the stiction's (the dead-zone inverse's slope), and
  // keeps the reserve's share of what is left after the holding effort for the PID
  constexpr int16_t kUsable_q15 = permille_q15(kDutySlope_permille);
  constexpr int16_t kPlanned_q15 = permille_q15(1000 - kDcDutyReserve_permille);
  // the planned share of each drive's full-duty speed (Unit{kPlanned_q15} * full-duty speed)
  static constexpr fx::Real kPlannedSpeed[3] = {
      fx::Real{fx::mul_q15_const(fx::real(Ratio{kDcFullDutySpeed_crad_s[0], 100}).raw, kPlanned_q15)},
      fx::Real{fx::mul_q15_const(fx::real(Ratio{kDcFullDutySpeed_crad_s[1], 100}).raw, kPlanned_q15)},
      fx::Real{fx::mul_q15_const(fx::real(Ratio{kDcFullDutySpeed_crad_s[2], 100}).raw, kPlanned_q15)}};
  // the duty that moves a DC joint at its speed limit without load (Q15)
  static constexpr int16_t kLimitDuty_q15[3] = {
      (int16_t)(32767L * kJointSpeedLimit_crad_s[kDcJoint[0]] / kDcFullDutySpeed_crad_s[0]),
      (int16_t)(32767L * kJointSpeedLimit_crad_s[kDcJoint[1]] / kDcFullDutySpeed_crad_s[1]),
      (int16_t)(32767L * kJointSpeedLimit_crad_s[kDcJoint[2]] / kDcFullDutySpeed_crad_s[2])};
  static_assert(kJointSpeedLimit_crad_s[kDcJoint[0]] <= kDcFullDutySpeed_crad_s[0] &&
                    kJointSpeedLimit_crad_s[kDcJoint[1]] <= kDcFullDutySpeed_crad_s[1] &&
                    kJointSpeedLimit_crad_s[kDcJoint[2]] <= kDcFullDutySpeed_crad_s[2],
                "a DC joint's speed limit within what its drive reaches at full duty");
  // the relay's fixed duty is not governed: it must not drive a joint past its speed limit
  // (at 600 permille J3 would turn at about 2 rad/s against 1.0)
  static_assert(!kDcUseRelay || (kRelayDuty_permille <= kDcMinDuty_permille + (int32_t)kDutySlope_permille * kLimitDuty_q15[0] / 32767 &&
                                 kRelayDuty_permille <= kDcMinDuty_permille + (int32_t)kDutySlope_permille * kLimitDuty_q15[1] / 32767 &&
                                 kRelayDuty_permille <= kDcMinDuty_permille + (int32_t)kDutySlope_permille * kLimitDuty_q15[2] / 32767),
                "the relay's duty within every DC joint's speed limit");
  for (uint8_t d = 0; d < 3; ++d) {
    const int16_t h = g_dc[d].holding_q15;
    // the speed governor: each way, the effort of the speed limit and of the load's lifting
    // (the feedforward's model at the limit speed, without the acceleration's term)
    g_servo[d].set_effort_bounds(
        effort_for_duty(control::saturate_i16((int32_t)kLimitDuty_q15[d] + core::lifting_effort_q15(h, 1))),
        effort_for_duty(control::saturate_i16((int32_t)kLimitDuty_q15[d] - core::lifting_effort_q15(h, -1))));
    const int16_t up = (int16_t)(kUsable_q15 - (h > 0 ? h : 0)), down = (int16_t)(kUsable_q15 - (h < 0 ? -h : 0));
    g_drives.positive_rad_s[kDcJoint[d]] = fx::Unit{up > 0 ? up : (int16_t)0} * kPlannedSpeed[d];
    g_drives.negative_rad_s[kDcJoint[d]] = fx::Unit{down > 0 ? down : (int16_t)0} * kPlannedSpeed[d];
  }
  stop_drives_at_switches();
}

constexpr int32_t kStandingSpeed = fx::real(Ratio{kDcStandingSpeed_mrad_s, 1000}).raw;
constexpr int32_t kMaxDcChange = kMaxSpeedChangePerTick[1].raw > kMaxSpeedChangePerTick[2].raw
                                     ? (kMaxSpeedChangePerTick[1].raw > kMaxSpeedChangePerTick[3].raw ? kMaxSpeedChangePerTick[1].raw
                                                                                                      : kMaxSpeedChangePerTick[3].raw)
                                     : (kMaxSpeedChangePerTick[2].raw > kMaxSpeedChangePerTick[3].raw ? kMaxSpeedChangePerTick[2].raw
                                                                                                      : kMaxSpeedChangePerTick[3].raw);
static_assert(kMaxDcChange < 32768, "a DC reference's change of speed in one tick fits 16 bits");

constexpr uint8_t kOverrunTicks = 8;  // past this many a call is one (the term is bounded below)
constexpr int16_t kOneOverTicks[kOverrunTicks + 1] = {0, 32767, 16384, 10923, 8192, 6554, 5461, 4681, 4096};

// One DC joint's servo, over the ticks since it last ran. Out of line: in the loop over the
// joints of a slot, avr-gcc carried a pointer into each of a dozen tables (~350 cycles an
// iteration).
__attribute__((noinline)) void run_dc_servo(uint8_t d, DcJoint& dc, core::DcServo& servo) {
  const uint8_t ticks = g_servo_elapsed;
  const int16_t reference = dc.pot.units(g_q.q.q[kDcJoint[d]]);
  dc.reference_units = reference;
  const int16_t lag = (int16_t)(reference - dc.units);  // [-16384 - 16368, 16383]
  if (lag > dc.lag_fault_units || lag < -dc.lag_fault_units) g_faults |= core::fault_mask(core::kFaultBitTracking);
  // a reference creeping slower than the standing speed (the drift correction's trickle) stands:
  // no effort of a motion, the servo parks and follows it a count at a time
  const fx::Real qd_raw = g_qd[kDcJoint[d]];
  const fx::Real qd = qd_raw.raw < kStandingSpeed && qd_raw.raw > -kStandingSpeed ? fx::Real{0} : qd_raw;
  // the change per tick: a servo's run spans `ticks` of them (its period, more after an
  // overrun). Past two ticks (after the longest iterations, which a 32-bit division would
  // lengthen further) a product by 1/ticks; a quarter instead moved S1's line by 0.6 mm.
  int32_t change = qd.raw - dc.qd_prev.raw;
  if (ticks == 2) change >>= 1;
  else if (ticks > 2) change = (fx::Unit{kOneOverTicks[ticks < kOverrunTicks ? ticks : kOverrunTicks]} * fx::Real{change}).raw;
  dc.qd_prev = qd;
  // one tick's change at most the acceleration limit's (a larger one: the reference started
  // or stopped standing), which fits 16 bits
  const int16_t accel = (int16_t)(change > kMaxDcChange ? kMaxDcChange : change < -kMaxDcChange ? -kMaxDcChange : change);
  // a reference that stands and stood (every term 0, and so the effort) or moves evenly (no
  // acceleration's term): no product for the missing terms
  int16_t feedforward_q15 = 0;
  if (qd.raw != 0 || accel != 0) {
    const bool slowing = (accel < 0) != (qd.raw < 0);  // the change opposes the speed
    const DcFeedforward& k = kDcFeedforward[d];
    int32_t duty = qd.raw == 0 ? 0 : ((k.per_speed * qd).raw >> 8) + core::lifting_effort_q15(dc.holding_q15, qd.raw);
    if (accel != 0) duty += fx::mul_ss(accel, slowing ? k.brake_q8 : k.accel_q8) >> 16;
    int16_t duty_q15 = control::saturate_i16(duty);
    asm("" : "+r"(duty_q15));  // one copy of the conversion below, not one per clamp's branch
    feedforward_q15 = effort_for_duty_inline(duty_q15);
  }
  bridges::set(d, servo.update(reference, dc.units, feedforward_q15, dc.holding_effort_q15, ticks));
}

// the three, each with its joint's and servo's state by address (from its index, the address
// sums took ~30 cycles a run; in iterate, the loop's pointers took its registers)
__attribute__((noinline)) void run_dc_servos() {
  for (uint8_t d = 0; d < 3; ++d) run_dc_servo(d, g_dc[d], g_servo[d]);
}

// The DC servos of this iteration's slot, and the holding effort in its phase. Without the
// stick's motion pass the holding update and the governor run a tick early, in the idle motion
// slot: in a move the drives' tick is the heaviest (the ramps every tick, the servos), and on
// the move's first the servos leave park (breakaway, the PID's restart) and the targets are
// converted: with the holding update too, the move to the ready pose's first took 16,238
// cycles, 14,199 without. The servos then read a holding effort of references one tick older
// (at move speed the load's angle sums differ by at most 1.8 mrad: 0.13 % of full duty). Where
// the stick starts or stops driving between the two phases, one update is skipped (a move begun
// at the holding phase: its first tick without it) or runs twice, and the governor's next run
// may come up to 32 ticks after its last: a move runs at half the speed limits, so the angle
// sums move no more than in the 16 ticks the governor's margin allows (above).
void dc_tick(uint8_t phase, uint8_t slot, bool stick_drives) {
  static_assert(kEarlyHoldingPhase % kDrivePeriod_ticks == kMotionSlot && kEarlyGovernorPhase % kDrivePeriod_ticks == kMotionSlot,
                "a tick before the holding update's and the governor's is the motion pass's");
  if (phase == (stick_drives ? kHoldingPhase : kEarlyHoldingPhase)) {
    update_holding(stick_drives);
    g_governor_due = g_holding_governs = !g_holding_governs;
  } else if (phase == (stick_drives ? kGovernorPhase : kEarlyGovernorPhase)) {
    if (g_governor_due) {
      g_governor_due = false;
      update_governor();
    } else if (g_homed) {
      update_j1_stop(g_pass_trig);  // the governor's idle turn, every 16 ticks: ~2,500 cycles
    }
  }
  if (slot == kDriveSlot) run_dc_servos();
}

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

// --- J6's turn (SPEC 5): its homing, its angle recorded at rest, its zero switch watched
constexpr int32_t steps_of_mdeg(uint8_t i, int32_t mdeg) { return steps_of(i, mdeg / 360000.0); }
// in flash: configure() copies it into g_wrist (as a constant it stayed in RAM besides, 55 bytes)
const core::WristHomingConfig kWristHomingConfig PROGMEM{
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

// J6's zero switch, once J6 is homed: closed where the count says J6 is not at a whole turn, the
// count is wrong (position_lost); J6's count is then taken to be within half a turn. And J6's
// angle, recorded once it comes to rest (core/rest_watch.h). Once a schedule period (8 ms: at
// J6's speed limit the switch's filter shows its cam closed for over 25 ms), in a tick whose
// stepper ramps have just counted their steps; every tick it cost 120 cycles a tick.
constexpr uint8_t kWristWatchPhase = kStepperSlot;
static_assert(kWristWatchPhase < kSchedulePeriod_ticks, "J6's watch in the schedule");
WMRA_COLD void watch_wrist(uint8_t ticks) {
  constexpr int32_t kTurn = (int32_t)kStepsPerJointTurn[2];
  const int32_t position = steppers::rate(2).position_steps();
  if (g_homed && inputs::j6_zero_closed()) {
    int32_t r = position;
    if (r > kTurn / 2) r -= kTurn;
    if (r < -kTurn / 2) r += kTurn;
    if (r > kJ6ZeroWatch_steps || r < -kJ6ZeroWatch_steps) {
      g_faults |= core::fault_mask(core::kFaultBitPositionLost);
      g_homed = false;
      g_wrist.set_belief(core::WristBelief::within_half_turn);
    }
  }
  if (g_wrist_rest.update(position, g_homed, ticks)) wrist_angle::record(kStepperMap[2].angle(position));
}

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
                                  (int16_t)(kRailMargin_counts * kPositionUnitsPerCount),
                                  (int16_t)((1023 - kRailMargin_counts) * kPositionUnitsPerCount), (uint8_t)kRailTime_ms},
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

// a lag of `mrad` in pot units, from the calibration's pot units over Angle counts (integers,
// like PotMap::make; Q24 counts per mrad): floor(units mrad K / counts / 2^24) =
// floor(floor(a K / 2^24) / counts) with a = units mrad (floors compose), the product a K in
// 16-bit halves (a 64-bit one linked libgcc's 64-bit multiply and division, ~700 B of flash):
// a K = ah kh 2^32 + (ah kl + al kh) 2^16 + al kl, each term within 32 bits for a < 2^24
constexpr uint32_t kAngleCountsPerMrad_q24 = (uint32_t)(core::kAngleCountsPerRad / 1000.0 * 16777216.0 + 0.5);
static_assert(kAngleCountsPerMrad_q24 < (1ul << 30), "ah kl + al kh fits 31 bits");
static_assert(kTrackingSlowFrom_mrad > 0 && kTrackingStopAt_mrad < 1024 && kTrackingFault_mrad < 1024 &&
                  1023 * 16 * 1023L < (1L << 24),
              "a calibration's span of pot units (< 2^14) times a lag in mrad fits 24 bits");
WMRA_COLD int32_t lag_units(uint16_t units, uint32_t counts, uint16_t mrad) {
  constexpr uint16_t kh = (uint16_t)(kAngleCountsPerMrad_q24 >> 16), kl = (uint16_t)kAngleCountsPerMrad_q24;
  const uint32_t a = fx::mul_uu(units, mrad);
  const uint16_t ah = (uint16_t)(a >> 16), al = (uint16_t)a;
  const uint32_t middle = fx::mul_uu(ah, kl) + fx::mul_uu(al, kh) + (fx::mul_uu(al, kl) >> 16);
  const uint32_t a_k_q24 = (fx::mul_uu(ah, kh) << 8) + (middle >> 8);  // floor(a K / 2^24)
  return (int32_t)(a_k_q24 / counts);
}

// a DC joint's pot map and its tracking thresholds in pot units, from the calibration
WMRA_COLD void configure_pot(const Settings& settings, uint8_t d) {
  using L = kin::JointLimits<Fixed>;
  const uint8_t j = kDcJoint[d];
  const int32_t at_min = settings.pot_at_min_counts_x16[d], at_max = settings.pot_at_max_counts_x16[d];
  g_dc[d].pot = core::PotMap::make(L::min[j], L::max[j], at_min, at_max);
  const uint16_t units = (uint16_t)(at_max - at_min);  // within [600, 1023] counts x 16 (settings.cpp)
  const uint32_t counts = (uint32_t)(L::max[j].raw - L::min[j].raw);
  g_lag_slow_units[d] = lag_units(units, counts, kTrackingSlowFrom_mrad);
  g_lag_stop_units[d] = lag_units(units, counts, kTrackingStopAt_mrad);
  const int32_t fault_units = lag_units(units, counts, kTrackingFault_mrad);
  g_dc[d].lag_fault_units = (int16_t)(fault_units > 32767 ? 32767 : fault_units);
  g_lag_inverse[d] = (int16_t)(32767 / (g_lag_stop_units[d] - g_lag_slow_units[d]));
  g_dc[d].standstill_units = (int16_t)lag_units(units, counts, (uint16_t)(kStandstillMove_mdeg * 3.14159265 / 180 + 0.5));
}

WMRA_COLD void configure(Settings& settings) {
  constexpr control::JoystickConfig kStick{1023,
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
  static_assert(control::joystick_check(kStick), "joystick configuration");
  g_stick.configure(kStick);
  g_stick.set_stored_centre(settings.stick_centre_counts[0], settings.stick_centre_counts[1]);
  g_button.configure(control::ButtonConfig{kButtonDebounce_ms, kButtonLongPress_ms});

  for (uint8_t i = 0; i < 3; ++i) {
    steppers::rate(i).configure(kRampConstants[i]);
    steppers::rate(i).configure_stop(kStopConstants[i]);
    if (i < 2) g_homing[i].configure(kHomingConfig[i]);
  }
  core::WristHomingConfig wrist;
  memcpy_P(&wrist, &kWristHomingConfig, sizeof wrist);
  g_wrist.configure(wrist);
  g_wrist_rest.configure(core::RestWatchConfig{(uint16_t)kJ6RestBeforeRecord_ms, (int16_t)steps_of_mdeg(2, kJ6RestBand_mdeg),
                                                (int16_t)steps_of_mdeg(2, kJ6RecordChange_mdeg)});

  for (uint8_t d = 0; d < 3; ++d) {
    configure_pot(settings, d);
    g_servo[d].configure(kDcServoConfig[d]);
  }
}

}  // namespace

WMRA_COLD void start(Settings& settings, const fx::Angle* j6_at_rest) {
  g_settings = &settings;
  configure(settings);
  // J6's count from its recorded angle: homing goes by it (core/wrist_homing.h)
  if (j6_at_rest) {
    const int32_t steps = kStepperMap[2].steps(*j6_at_rest);
    steppers::rate(2).set_position(steps);
    g_wrist_rest.set_recorded(steps);
    g_wrist.set_belief(core::WristBelief::exact);
  }
  adc::start(kAdcOrder, sizeof kAdcOrder, kAdcSweepPhase_us);
  set_speed_scale(100);
  g_gripper_us_q15 = (int32_t)kGripperStart_us << 15;
}

void stop_from_interrupt() {
  bridges::all_off();
  steppers::halt_trains();
}

void outputs_off() {
  bridges::all_off();
  steppers::kill();
}

namespace {
// An armed limit switch closed (the interrupt has stopped the arm). The moves and the stick keep
// the joints inside their soft limits, short of the switches: a stepper's switch that closes
// where the joint's count says it is not at the switch means the count is wrong (position_lost:
// the steppers are homed again before the next motion); otherwise the motion went into it.
WMRA_COLD void on_switch_closed(uint16_t closed) {
  using L = kin::JointLimits<Fixed>;
  constexpr int32_t kTolerance = (int32_t)(1.5 / 360.0 * fx::kAngleTurn);
  g_faults |= core::fault_mask(core::kFaultBitLimitUnexpected);
  steppers::count();
  for (uint8_t i = 0; i < 2; ++i) {  // J1, J5 (J6's zero switch is not armed)
    const uint8_t j = kStepperJoint[i];
    const int32_t angle = kStepperMap[i].angle(steppers::rate(i).position_steps()).raw;
    for (uint8_t high = 0; high < 2; ++high) {
      if (!(closed & (1u << (2 * j + high)))) continue;
      const int32_t off = angle - (high ? L::max[j].raw : L::min[j].raw);
      if (off > kTolerance || off < -kTolerance) {
        g_faults |= core::fault_mask(core::kFaultBitPositionLost);
        g_homed = false;
      }
    }
  }
}

// a re-arm's (out of iterate, which is at avr-gcc's limit of inlining growth: one more line in
// it and a scale's product in the steppers' tracking went into an out-of-line copy, 332 B)
WMRA_COLD void clear_faults() {
  g_faults = 0;
  for (uint8_t d = 0; d < 3; ++d) g_servo[d].reset_checks(g_dc[d].units);
}
}  // namespace

void iterate(Requests& rq, uint8_t ticks) {
  // --- inputs
  uint16_t adc[adc::kMaxChannels];
  adc::snapshot(adc);
  // the limit switches for homing, which is entered only from wait_home or wait_neutral: not
  // read while running or moving to the ready pose (the report reads them itself; a switch hit
  // while running is the interrupt's event below)
  const core::ArmState before = g_supervisor.state();
  const bool homing_possible = before != core::ArmState::running && before != core::ArmState::to_ready;
  const uint16_t switches = homing_possible ? inputs::closed_switches() : 0;
  const bool safety = inputs::take_safety_event() | inputs::safety_pressed();
  g_ms = (uint16_t)(g_ms + ticks);
  g_motion_elapsed = control::add_saturated_u8(g_motion_elapsed, ticks);
  if (ticks > 1) g_overrun_ms = kOverrunReport_ms;
  else if (g_overrun_ms > 0) --g_overrun_ms;
  // The slots advance by iteration: after an overrun no job is skipped.
  const uint8_t phase = g_phase = (uint8_t)((g_phase + 1) % kSchedulePeriod_ticks);
  const uint8_t slot = (uint8_t)(phase % kDrivePeriod_ticks);  // config::kMotionSlot, kDriveSlot
  const bool stepper_slot = phase % kStepperPeriod_ticks == kStepperSlot;
  // The stick and its button in the motion pass's slot, which alone uses them (sampled every
  // tick, every second shape was never used); the joystick's rail check, arming and ramps count
  // ticks, so a 2 ms sample period keeps their times. (In the drives' slot instead, that tick
  // took 10,135 cycles on average and the pass's 8,580: test_firmware_budgets.)
  g_stick_elapsed = control::add_saturated_u8(g_stick_elapsed, ticks);
  control::JoystickOutput stick = g_stick.output();
  control::ButtonEvent button = control::ButtonEvent::none;
  if (slot == kMotionSlot) {
    stick = g_stick.update(adc[kAdcStickX], adc[kAdcStickY], g_stick_elapsed);
    g_stick_elapsed = 0;
    button = g_button.update(inputs::joystick_button_down(), g_ms);
  }

  // --- checks: every reading, every tick, at the rails and for a jump (a jump is a change
  // within a tick: over a servo's period it would let a glitch twice as large through); the
  // motion checks (stall, sign error) with the servo, in its slot before it runs: the duty they
  // judge changes only then, so each of their windows spans the one duty (every tick, they cost
  // ~45 cycles a tick more and saw each duty twice).
  g_servo_elapsed = control::add_saturated_u8(g_servo_elapsed, ticks);
  const uint8_t servo_ticks = slot == kDriveSlot ? g_servo_elapsed : 0;
  for (uint8_t d = 0; d < 3; ++d) {
    // a 16-bit product (10-bit counts x 16): a 32-bit one is a shift loop
    static_assert(1023 * kPositionUnitsPerCount < 32768, "pot units of a 10-bit reading fit 16 bits");
    g_dc[d].units = (int16_t)(adc[kAdcPot + d] * kPositionUnitsPerCount);
    const uint8_t flags = g_servo[d].check(g_dc[d].units, ticks, servo_ticks);
    if (flags) g_faults |= core::dc_joint_faults(d, flags);  // a 32-bit shift by a run-time count is a loop
  }
  const uint16_t switch_closed = inputs::take_switch_event();
  if (switch_closed) on_switch_closed(switch_closed);

  // --- supervisor
  const bool long_press = button == control::ButtonEvent::long_press;
  const bool halted = before == core::ArmState::stopped || before == core::ArmState::fault;
  if (halted && (rq.rearm || long_press) && !safety) clear_faults();
  const bool stick_valid = !stick_invalid(stick);
  const bool stick_neutral = stick.x_q15 == 0 && stick.y_q15 == 0 && !(stick.status & control::kJoystickCalibrating);
  core::SupervisorInputs in{};
  in.safety_pressed = safety;
  in.faults = g_faults & core::kFaultsLatched;
  in.drives_at_rest = steppers::at_rest();
  in.stick_valid = stick_valid;
  in.stick_neutral = stick_neutral;
  in.short_press = button == control::ButtonEvent::press;
  in.long_press = long_press;
  in.button_down = g_button.down();
  in.rearm_command = rq.rearm;
  in.stop_command = rq.stop;
  in.home_command = rq.home;
  in.homed = g_homed;
  in.at_ready = g_at_target;
  g_supervisor.update(in, ticks);
  const core::ArmState state = g_supervisor.state();
  if (state != g_prev_state) {
    enter(state);
    g_prev_state = state;
  }

  // --- motion
  bool stick_drives = false;  // the motion pass's ticks count from the first tick it drives
  switch (state) {
    case core::ArmState::homing:
      homing_tick(switches, ticks);
      break;
    case core::ArmState::to_ready:
      move_tick(phase);
      break;
    case core::ArmState::running: {
      // A stick at a rail (unplugged, broken) moves nothing (SPEC 6), whatever else commands: a
      // move or a streamed velocity would go on where the person could not take it over. A
      // deflected stick takes a stream over, as it does a move: the stream ends (the link
      // refuses it until it has stopped arriving), it does not drive again when the stick is
      // let go.
      if (!stick_valid || !stick_neutral) {
        rq.stream_taken_over = rq.velocity_fresh;
        rq.velocity_fresh = false;
      } else if (g_streaming && !rq.velocity_fresh) {
        halt_lost_stream();
      }
      g_streaming = rq.velocity_fresh;
      int8_t pose_slot = rq.goto_slot;
      if (long_press && kLongPressWhileRunning == LongPress::go_to_stored_pose_0) pose_slot = 0;
      if (pose_slot >= 0 && stick_valid && (g_settings->pose_valid & (1 << pose_slot))) {
        begin_move(g_settings->pose_angle[pose_slot]);
        g_moving = true;
      }
      // the person takes over, or no stick: the move slows to rest along its line, then the
      // stick drives (the steppers, carrying the arm, are never cut at speed)
      if (g_moving && (!stick_neutral || !stick_valid || rq.velocity_fresh)) g_move.brake();
      if (g_moving) {
        move_tick(phase);
        if (g_at_target || (g_move.braking() && g_move.lead_speed().raw == 0)) start_running();
      } else if (g_stream_halted) {
        g_stream_halt_ms = control::add_saturated_u8(g_stream_halt_ms, ticks);
        if (g_stream_halt_ms >= kStreamHalt_ms && steppers::at_rest()) start_running();
      } else {
        if (slot == kMotionSlot) {
          motion_tick(stick, rq, g_motion_elapsed);
          g_motion_elapsed = 0;
        } else if (stepper_slot) {  // the ramps, run below, follow the references
          track_stepper<0>();
          track_stepper<1>();
          track_stepper<2>();
        }
        stick_drives = true;
      }
      break;
    }
    default:
      break;
  }
  if (!stick_drives) g_motion_elapsed = 0;
  if (g_supervisor.drives_enabled()) {
    dc_tick(phase, slot, stick_drives);
  } else {
    watch_standstill(ticks);
  }
  if (slot == kDriveSlot) g_servo_elapsed = 0;
  // the steppers' ramps with this iteration's commands: while the stick drives in their slot,
  // and the steps made counted in the tick before it only, for its tracking (a tick old, as in
  // homing and the moves to a pose, which service the ramps every tick: their sequences read the
  // ramps' state a tick after a command). Nothing else reads the counts while the stick drives;
  // the readers outside it (the report, the drives off, a move or a brake begun) count first.
  g_ramp_elapsed = control::add_saturated_u8(g_ramp_elapsed, ticks);
  if (stepper_slot || state != core::ArmState::running || g_moving || g_stream_halted) {
    steppers::service(g_ramp_elapsed);
    g_ramp_elapsed = 0;
  } else if ((g_phase + 1) % kStepperPeriod_ticks == kStepperSlot) {  // (the global: phase kept live to here cost ~70 cycles)
    steppers::count();
  }
  g_wrist_elapsed = control::add_saturated_u8(g_wrist_elapsed, ticks);
  if (phase == kWristWatchPhase) {
    watch_wrist(g_wrist_elapsed);
    g_wrist_elapsed = 0;
  }

  rq.stop = rq.rearm = rq.home = false;
  rq.goto_slot = -1;
}

// The report is put together when it is asked for (a state frame, every 20 ms), from what the
// last iteration left: not field by field every tick.
WMRA_COLD const Status& status() {
  g_status.state = g_supervisor.state();
  g_status.mode = g_supervisor.mode();
  const control::JoystickOutput stick = g_stick.output();
  g_status.faults = g_faults | (stick_invalid(stick) ? core::fault_mask(core::kFaultBitStickInvalid) : 0) |
                    (g_overrun_ms > 0 ? core::fault_mask(core::kFaultBitLoopOverrun) : 0);
  g_status.switches = inputs::closed_switches();
  g_status.stick_q15[0] = stick.x_q15;
  g_status.stick_q15[1] = stick.y_q15;
  steppers::count();  // while the stick drives the loop counts the steps every fourth tick only
  for (uint8_t i = 0; i < 3; ++i)
    g_status.q_measured[kStepperJoint[i]] = kStepperMap[i].angle(steppers::rate(i).position_steps());
  for (uint8_t d = 0; d < 3; ++d) g_status.q_measured[kDcJoint[d]] = g_dc[d].pot.angle(g_dc[d].units);
  for (uint8_t j = 0; j < 6; ++j) g_status.qd_rad_s[j] = g_qd[j];
  // the drift correction's while the stick drives; in the other states and the moves to a pose
  // (light iterations) the references' FK here
  const uint32_t now_ms = tick::now_ms();
  if (now_ms - g_p_hand_ms < kHandPositionAge_ms) {
    g_status.p_m = g_p_hand;
  } else {
    g_status.p_m = kin::hand_position<Fixed>(kin::jacobian_trig<Fixed>(g_q.q));
    g_p_hand_ms = now_ms - kHandPositionAge_ms;  // kept old: 2^32 ms on (49.7 days) it would read as fresh
  }
  return g_status;
}

bool select_mode(config::Mode m) { return g_supervisor.select_mode(m); }

// the report keeps the percent (the scale's percent, rounded, was a 32-bit division a frame)
void set_speed_scale(uint8_t percent) {
  g_status.speed_scale_pct = percent > 100 ? 100 : percent;
  g_speed_scale = fx::Unit{(int16_t)((int32_t)g_status.speed_scale_pct * fx::kUnitOne / 100)};
}

WMRA_COLD bool store_pose(uint8_t slot) {
  if (slot >= kPoseSlots || g_supervisor.state() != core::ArmState::running) return false;
  // within the soft stops: a DC joint's reference is where it stood (drives_on), up to a park
  // band past a stop, and load_settings drops a pose beyond one
  for (uint8_t j = 0; j < 6; ++j) {
    const int32_t a = g_q.q.q[j].raw, lo = kLimits.joint[j].soft_min.raw, hi = kLimits.joint[j].soft_max.raw;
    g_settings->pose_angle[slot][j] = a < lo ? lo : a > hi ? hi : a;
  }
  g_settings->pose_valid |= (uint8_t)(1 << slot);
  save_settings(*g_settings);
  return true;
}

// Only with the drives off: the joint's measured angle moves with its calibration, and a
// servo holding it would drive it to the old angle. drives_on() starts from the new one.
CalibrationChange calibrate_pot(uint8_t joint, int16_t at_min_counts_x16, int16_t at_max_counts_x16) {
  if (joint < 2 || joint > 4) return CalibrationChange::bad_argument;
  if (g_supervisor.drives_enabled()) return CalibrationChange::refused;
  const uint8_t d = (uint8_t)(joint - 2);
  if (!app::set_pot_calibration(*g_settings, d, at_min_counts_x16, at_max_counts_x16, g_dc[d].units))
    return CalibrationChange::bad_argument;
  configure_pot(*g_settings, d);
  return CalibrationChange::ok;
}

protocol::CalibrationMsg calibration() {
  protocol::CalibrationMsg m{};
  for (uint8_t d = 0; d < 3; ++d) {
    m.at_min_counts_x16[d] = g_settings->pot_at_min_counts_x16[d];
    m.at_max_counts_x16[d] = g_settings->pot_at_max_counts_x16[d];
    m.reading_counts_x16[d] = (int16_t)g_dc[d].units;
  }
  m.from_command = g_settings->pot_calibrated;
  return m;
}

// The centre in use: a person sends this with the stick released, after a power-up with it
// released (a centre taken from a held stick would be stored as it is, hence the guide's steps).
WMRA_COLD bool store_stick_centre(bool store) {
  const control::JoystickOutput stick = g_stick.output();
  uint16_t x = 0, y = 0;
  if (store) {
    if (stick.status != 0 || stick.x_q15 != 0 || stick.y_q15 != 0) return false;  // calibrated, armed, neutral
    x = g_stick.centre(0);
    y = g_stick.centre(1);
  }
  if (!app::set_stick_centre(*g_settings, x, y)) return false;
  g_stick.set_stored_centre(x, y);
  return true;
}

bool pose_valid(uint8_t slot) { return slot < kPoseSlots && (g_settings->pose_valid & (1 << slot)); }

}  // namespace app
}  // namespace wmra
