// The jog in the firmware (jog.h).
#include "app/jog.h"

#include "app/arm.h"
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
    // a DC joint's angle is its pot's; a stepper's count is its angle once homed
    const bool angle_known = g_arm.homed || (j >= config::kDcJoint[0] && j <= config::kDcJoint[2]);
    wanted[j] = core::jog_speed(j, rq.jog_mrad_s, angle_known, g_arm.q.q, config::kMotionLimits, g_arm.drives, closed_switches);
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
