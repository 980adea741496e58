// The modes that a short press of the joystick button cycles through, and how the stick's
// axes map to hand motion in each (docs/arm-guide.md, using the arm; Torres's action planes). A mirrored mounting of the stick
// is a sign change here.
#pragma once

#include <stdint.h>

namespace wmra {
namespace config {

enum class Mode : uint8_t { xy, xz, r1, r2, gripper };

constexpr Mode kModeCycle[] = {Mode::xy, Mode::xz, Mode::r1, Mode::r2, Mode::gripper};
constexpr uint8_t kModeCount = sizeof(kModeCycle) / sizeof(kModeCycle[0]);

// +1 or -1 per stick axis: stick +X and +Y as seen by the person
constexpr int8_t kStickXSign = 1;
constexpr int8_t kStickYSign = 1;

static_assert(kModeCount >= 1 && kModeCount <= 8, "kModeCycle: one to eight modes");
constexpr bool modes_each_once() {
  for (uint8_t i = 0; i < kModeCount; ++i) {
    if ((uint8_t)kModeCycle[i] > (uint8_t)Mode::gripper) return false;
    for (uint8_t k = 0; k < i; ++k)
      if (kModeCycle[k] == kModeCycle[i]) return false;
  }
  return true;
}
static_assert(modes_each_once(), "kModeCycle: each entry a Mode, each mode once (a repeat is a press that seems to do nothing)");
static_assert((kStickXSign == 1 || kStickXSign == -1) && (kStickYSign == 1 || kStickYSign == -1), "kStickXSign, kStickYSign: +1 or -1");

}  // namespace config
}  // namespace wmra
