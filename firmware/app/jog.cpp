// The jog in the firmware (jog.h).
#include "app/jog.h"

#include "app/arm.h"
#include "app/homing.h"
#include "app/stepper_drives.h"
#include "config/derived.h"
#include "core/jog.h"
#include "core/joint_acceleration.h"

namespace wmra {
namespace app {
namespace jog {

void tick(const Requests& rq, bool stick_rests, uint16_t closed_switches, uint8_t ticks) {
  fx::Real wanted[6] = {fx::Real{0}, fx::Real{0}, fx::Real{0}, fx::Real{0}, fx::Real{0}, fx::Real{0}};
  const uint8_t j = (uint8_t)(rq.jog_joint - 1);
  if (rq.jog_fresh && stick_rests && j < 6) {
    // a DC joint's angle is its pot's; a stepper's count is its angle once homed, and J6's
    // before that where its angle was recorded at rest (its count starts there); otherwise the
    // count started at 0 at power-up
    const bool dc = j >= config::kDcJoint[0] && j <= config::kDcJoint[2];
    const bool angle_known = g_arm.homed || dc || (j == config::kStepperJoint[2] && homing::j6_angle_exact());
    const fx::Angle origin = dc ? fx::Angle{0} : stepper_drives::angle_of(j == config::kStepperJoint[0] ? 0 : j == config::kStepperJoint[1] ? 1 : 2, 0);
    wanted[j] = core::jog_speed(j, rq.jog_mrad_s, angle_known, g_arm.q.q, config::kMotionLimits, g_arm.drives, closed_switches, origin);
  }
  fx::Real max_change[6];
  for (uint8_t k = 0; k < 6; ++k) max_change[k] = fx::Real{config::kMaxSpeedChangePerTick[k].raw * ticks};
  core::limit_joint_acceleration(g_arm.q.qd_rad_s, wanted, fx::Unit{(int16_t)fx::kUnitOne}, max_change);
  g_arm.q.advance_ticks(ticks);
  stepper_drives::track();
}

bool at_rest() {
  for (uint8_t k = 0; k < 6; ++k)
    if (g_arm.q.qd_rad_s[k].raw != 0) return false;
  return true;
}

}  // namespace jog
}  // namespace app
}  // namespace wmra
