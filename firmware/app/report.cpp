// What telemetry and the commands' checks read of the arm (status(), condition(), calibration():
// arm_control.h), put together when asked for from what the last iteration left.
#include "app/arm.h"
#include "app/dc_drives.h"
#include "app/motion.h"
#include "app/stepper_drives.h"
#include "config/joints_config.h"
#include "drivers/inputs.h"
#include "drivers/steppers.h"

namespace wmra {
namespace app {

bool stick_invalid(const control::JoystickOutput& stick) {
  return stick.status & (control::kJoystickRailX | control::kJoystickRailY);
}

Condition condition() {
  const control::JoystickOutput stick = g_arm.stick.output();
  Condition c;
  c.state = g_arm.supervisor.state();
  c.faults = g_arm.faults | (stick_invalid(stick) ? core::fault_mask(core::kFaultBitStickInvalid) : 0) |
             (g_arm.overrun_ms > 0 ? core::fault_mask(core::kFaultBitLoopOverrun) : 0);
  c.switches = inputs::closed_switches();
  c.stick_q15[0] = stick.x_q15;
  c.stick_q15[1] = stick.y_q15;
  c.busy = running_busy();
  return c;
}

const Status& status() {
  Status& s = g_arm.status;
  const Condition c = condition();
  s.state = c.state;
  s.mode = g_arm.supervisor.mode();
  s.faults = c.faults;
  s.switches = c.switches;
  s.stick_q15[0] = c.stick_q15[0];
  s.stick_q15[1] = c.stick_q15[1];
  steppers::count();  // while the stick drives the loop counts the steps only before the ramps' ticks
  for (uint8_t i = 0; i < 3; ++i) s.q_measured[config::kStepperJoint[i]] = stepper_drives::angle(i);
  for (uint8_t d = 0; d < 3; ++d) s.q_measured[config::kDcJoint[d]] = dc_drives::angle(d);
  for (uint8_t j = 0; j < 6; ++j) s.qd_rad_s[j] = g_arm.q.qd_rad_s[j];
  // the drift correction's while the stick drives; in the other states and the moves to a pose
  // (light iterations) the references' FK here
  if (!motion::recent_hand_position(s.p_m)) s.p_m = kin::hand_position<kin::Fixed>(kin::jacobian_trig<kin::Fixed>(g_arm.q.q));
  return s;
}

protocol::CalibrationMsg calibration() {
  protocol::CalibrationMsg m{};
  for (uint8_t d = 0; d < 3; ++d) {
    m.at_min_counts_x16[d] = g_arm.settings->pot_at_min_counts_x16[d];
    m.at_max_counts_x16[d] = g_arm.settings->pot_at_max_counts_x16[d];
    m.reading_counts_x16[d] = dc_drives::units(d);
  }
  m.from_command = g_arm.settings->pot_calibrated;
  return m;
}

}  // namespace app
}  // namespace wmra
