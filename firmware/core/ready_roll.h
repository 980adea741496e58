// J6's target in the move to the ready pose: the ready angle's turn nearest where J6 stands
// (the hand's orientation is the same a whole turn on). J6 homed at +-360 deg, from an angle
// recorded beyond half a turn, then does not roll a whole turn back to 0 near the person's
// face. A turn beyond a soft stop by at most slack ends at that stop (J6 a few degrees off the
// ready angle, inside its soft limits); further beyond, the turn on the inside is taken.
// Angles in one unit (the firmware's Angle counts), the ready angle within the soft stops; where
// no other turn fits between them, the ready angle itself.
#pragma once

#include <stdint.h>

namespace wmra {
namespace core {

inline int32_t ready_roll(int32_t ready, int32_t present, int32_t turn, int32_t soft_min, int32_t soft_max, int32_t slack) {
  int32_t t = ready;
  while (present - t > turn / 2) t += turn;
  while (t - present > turn / 2) t -= turn;
  if (t > soft_max) t = t - soft_max <= slack ? soft_max : t - turn;
  if (t < soft_min) t = soft_min - t <= slack ? soft_min : t + turn;
  return t < soft_min || t > soft_max ? ready : t;
}

}  // namespace core
}  // namespace wmra
