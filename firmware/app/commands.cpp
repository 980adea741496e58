// The serial link's commands on the arm that are not motion requests (arm_control.h): the mode,
// the speed scale, storing a pose, a pot's calibration, the stick's stored centre.
#include "app/arm.h"
#include "app/dc_drives.h"
#include "config/derived.h"

namespace wmra {
namespace app {

bool select_mode(config::Mode m) { return g_arm.supervisor.select_mode(m); }

// The report keeps the percent. The scale, floor(percent x kUnitOne / 100), as a product and a
// shift: the 32-bit division took ~570 cycles a command (a flood of them at the line's rate, 25 %
// of the CPU). kScalePerPercent_q16 is the least constant for which the product floors alike for
// every percent, checked below.
constexpr uint32_t kScalePerPercent_q16 = 21474182;
constexpr bool scale_product_exact(uint8_t pct = 0) {
  return pct > 100 || (((uint32_t)pct * kScalePerPercent_q16 >> 16) == (uint32_t)pct * fx::kUnitOne / 100 && scale_product_exact(pct + 1));
}
static_assert(scale_product_exact(), "the speed scale's product floors as percent x kUnitOne / 100 does");
void set_speed_scale(uint8_t percent) {
  g_arm.status.speed_scale_pct = percent > 100 ? 100 : percent;
  g_arm.speed_scale = fx::Unit{(int16_t)((uint32_t)g_arm.status.speed_scale_pct * kScalePerPercent_q16 >> 16)};
}

// Within the soft stops: a DC joint's reference is where it stood (dc_drives::start), up to a
// park band past a stop, and load_settings drops a pose beyond one.
bool store_pose(uint8_t slot) {
  if (slot >= kPoseSlots || g_arm.supervisor.state() != core::ArmState::running) return false;
  for (uint8_t j = 0; j < 6; ++j) {
    const int32_t a = g_arm.q.q.q[j].raw, lo = config::kMotionLimits.joint[j].soft_min.raw, hi = config::kMotionLimits.joint[j].soft_max.raw;
    g_arm.settings->pose_angle[slot][j] = a < lo ? lo : a > hi ? hi : a;
  }
  g_arm.settings->pose_valid |= (uint8_t)(1 << slot);
  save_settings(*g_arm.settings);
  return true;
}

bool pose_valid(uint8_t slot) { return slot < kPoseSlots && (g_arm.settings->pose_valid & (1 << slot)); }

// Only with the drives off: the joint's measured angle moves with its calibration, and a servo
// holding it would drive it to the old angle. The drives start from the new one.
CalibrationChange calibrate_pot(uint8_t joint, int16_t at_min_counts_x16, int16_t at_max_counts_x16) {
  if (joint < 2 || joint > 4) return CalibrationChange::bad_argument;
  if (g_arm.supervisor.drives_enabled()) return CalibrationChange::refused;
  const uint8_t d = (uint8_t)(joint - 2);
  if (!app::set_pot_calibration(*g_arm.settings, d, at_min_counts_x16, at_max_counts_x16, dc_drives::units(d)))
    return CalibrationChange::bad_argument;
  dc_drives::configure_pot(*g_arm.settings, d);
  return CalibrationChange::ok;
}

// The centre in use: a person sends this with the stick released, after a power-up with it
// released (a centre taken from a held stick would be stored as it is, hence the guide's steps).
bool store_stick_centre(bool store) {
  const control::JoystickOutput stick = g_arm.stick.output();
  uint16_t x = 0, y = 0;
  if (store) {
    if (stick.status != 0 || stick.x_q15 != 0 || stick.y_q15 != 0) return false;  // calibrated, armed, neutral
    x = g_arm.stick.centre(0);
    y = g_arm.stick.centre(1);
  }
  if (!app::set_stick_centre(*g_arm.settings, x, y)) return false;
  g_arm.stick.set_stored_centre(x, y);
  return true;
}

}  // namespace app
}  // namespace wmra
