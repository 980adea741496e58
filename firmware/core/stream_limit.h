// The velocity stream's speed limits as lengths, as the stick's disc makes them (full
// deflection is the hand's or the wrist's top speed, in any direction). Clamped axis by axis, a
// host's (1, 1, 1) at the limit would move the hand at sqrt(3) times it. A vector longer than
// its limit is scaled down, its direction kept, to within the limit.
#pragma once

#include <stdint.h>

#include "kinematics/fixed_trig.h"

namespace wmra {
namespace core {

// v: a command's three components (mm/s or mrad/s, any int16); limit in the same unit (one copy
// for both of a command's vectors: a rare path)
__attribute__((noinline)) inline void limit_length(int16_t (&v)[3], uint16_t limit) {
  uint32_t square = 0;  // at most 3 x 2^30: fits
  for (uint8_t i = 0; i < 3; ++i) {
    const uint16_t m = v[i] < 0 ? (uint16_t)-v[i] : (uint16_t)v[i];
    square += fx::mul_uu(m, m);
  }
  if (square <= fx::mul_uu(limit, limit)) return;
  // the root rounded down, plus one: more than the length, so the result is within the limit
  const uint16_t over_length = (uint16_t)(fx::isqrt32(square) + 1);
  for (uint8_t i = 0; i < 3; ++i) v[i] = (int16_t)((int32_t)v[i] * limit / over_length);
}

}  // namespace core
}  // namespace wmra
