// Homing and the stepper joints' positions kept true (homing.h).
#include "app/homing.h"

#include <avr/pgmspace.h>

#include "app/arm.h"
#include "app/flash_config.h"
#include "app/joint_moves.h"
#include "app/stepper_drives.h"
#include "app/wrist_angle.h"
#include "config/derived.h"
#include "core/homing.h"
#include "core/rest_watch.h"
#include "core/wrist_homing.h"
#include "drivers/inputs.h"
#include "drivers/steppers.h"

namespace wmra {
namespace app {
namespace homing {

namespace {

using namespace config;

core::StepperHoming g_homing[2];  // J1, J5
core::WristHoming g_wrist;         // J6
core::RestWatch g_wrist_rest;      // when J6's angle is recorded

const core::HomingConfig kHomingConfigInFlash[2] PROGMEM = {kHomingConfig[0], kHomingConfig[1]};
const core::WristHomingConfig kWristHomingConfigInFlash PROGMEM = kWristHomingConfig;

}  // namespace

void configure() {
  for (uint8_t i = 0; i < 2; ++i) g_homing[i].configure(from_flash(kHomingConfigInFlash[i]));
  g_wrist.configure(from_flash(kWristHomingConfigInFlash));
  g_wrist_rest.configure(core::RestWatchConfig{(uint16_t)kJ6RestBeforeRecord_ms, (int16_t)steps_of_mdeg(2, kJ6RestBand_mdeg),
                                                (int16_t)steps_of_mdeg(2, kJ6RecordChange_mdeg)});
}

void set_j6_recorded(const fx::Angle* j6_at_rest) {
  if (!j6_at_rest) return;
  const int32_t steps = stepper_drives::steps_of(2, *j6_at_rest);
  steppers::rate(2).set_position(steps);
  g_wrist_rest.set_recorded(steps);
  g_wrist.set_belief(core::WristBelief::exact);
}

bool j6_angle_exact() { return g_wrist.belief() == core::WristBelief::exact; }

void restart() {
  for (uint8_t i = 0; i < 2; ++i) g_homing[i].restart();
  g_wrist.restart();
  g_arm.homed = false;
}

void tick(uint16_t switches, uint8_t ticks) {
  bool all_done = true;
  for (uint8_t i = 0; i < 2; ++i) {
    g_homing[i].update((switches & kHomingSwitch[i]) != 0, steppers::running(i), steppers::rate(i));
    if (g_homing[i].failed()) raise_fault(core::kFaultBitHomingFailed);
    if (!g_homing[i].done()) all_done = false;
  }
  g_wrist.update((switches & inputs::kJ6ZeroSwitch) != 0, steppers::running(2), ticks, steppers::rate(2));
  if (g_wrist.failed()) raise_fault(core::kFaultBitHomingFailed);
  if (!g_wrist.done()) all_done = false;
  if (g_wrist.take_contradiction()) {  // the recorded angle is wrong: the next power-up sweeps
    wrist_angle::forget();
    g_wrist_rest.clear_recorded();
  }
  stepper_drives::references_from_counts();
  if (all_done && !g_arm.homed) joint_moves::plan_ready_pose();
  g_arm.homed = all_done;
}

// J6's zero switch, once J6 is homed: closed where the count says J6 is not at a whole turn, the
// count is wrong (position_lost); J6's count is then taken to be within half a turn. At J6's
// speed limit the switch's filter shows its cam closed for over 25 ms, so once a plan cycle
// (8 ms) is often enough.
void watch_wrist(uint8_t ticks, bool in_move) {
  constexpr int32_t kTurn = (int32_t)kStepsPerJointTurn[2];
  const int32_t position = steppers::rate(2).position_steps();
  if (g_arm.homed && inputs::j6_zero_closed()) {
    int32_t r = position;
    if (r > kTurn / 2) r -= kTurn;
    if (r < -kTurn / 2) r += kTurn;
    if (r > kJ6ZeroWatch_steps || r < -kJ6ZeroWatch_steps) {
      raise_fault(core::kFaultBitPositionLost);
      g_arm.homed = false;
      g_wrist.set_belief(core::WristBelief::within_half_turn);
    }
  }
  if (g_wrist_rest.update(position, g_arm.homed && !in_move, ticks)) wrist_angle::record(stepper_drives::angle_of(2, position));
}

// The moves and the stick keep the joints inside their soft limits, short of the switches: a
// closing switch is the limit_unexpected fault, and position_lost too where the joint's count
// says it is not at that switch (J1, J5; J6's zero switch is not armed).
void on_switch_closed(uint16_t closed) {
  using L = kin::JointLimits<kin::Fixed>;
  constexpr int32_t kTolerance = (int32_t)(1.5 / 360.0 * fx::kAngleTurn);
  raise_fault(core::kFaultBitLimitUnexpected);
  steppers::count();
  for (uint8_t i = 0; i < 2; ++i) {
    const uint8_t j = kStepperJoint[i];
    const int32_t angle = stepper_drives::angle(i).raw;
    for (uint8_t high = 0; high < 2; ++high) {
      if (!(closed & (1u << (2 * j + high)))) continue;
      const int32_t off = angle - (high ? L::max[j].raw : L::min[j].raw);
      if (off > kTolerance || off < -kTolerance) {
        raise_fault(core::kFaultBitPositionLost);
        g_arm.homed = false;
      }
    }
  }
}

}  // namespace homing
}  // namespace app
}  // namespace wmra
