// The joint references' integration by a tick or two (core::JointReferences::advance_all, an asm loop
// on the AVR) in 64-bit arithmetic, and the velocities its checks draw. Shared by the host test
// (the portable twin) and the AVR image (the asm), so that both meet the same reference.
#pragma once

#include <stdint.h>

#include "core/joint_map.h"
#include "kinematics_vectors.h"

namespace wmra {
namespace vectors {

struct AdvancedJoint {
  int32_t q;
  uint16_t fraction;
};

// q + floor((floor((qd m - lo8(qd) lo8(m)) / 2^16) + fraction) / 2^16), the angle wrapping in
// 32 bits, and the new fraction: the low 16 bits of the inner sum. Two ticks' step: the
// product / 2^15.
inline AdvancedJoint reference_advance(int32_t q, uint16_t fraction, int32_t qd, bool two_ticks = false) {
  const int16_t m = core::kRateToAngleQ16PerTick.m;
  const int64_t product = (int64_t)qd * m - (int64_t)(qd & 0xFF) * (m & 0xFF);
  const int64_t sum_q16 = (product >> (two_ticks ? 15 : 16)) + fraction;
  return AdvancedJoint{(int32_t)((uint32_t)q + (uint32_t)(int32_t)(sum_q16 >> 16)), (uint16_t)sum_q16};
}

// the n-th velocity: every 8th one of the extremes (the sign and byte boundaries), the others
// random, shifted down by n mod 24 bits (the arm's speeds are far below 2^31)
inline int32_t advance_velocity(Lcg& rng, uint32_t n) {
  static const int32_t kExtremes[] = {INT32_MIN, INT32_MIN + 1, -65536, -256, -255, -1, 0, 1, 255, 256, 65535, INT32_MAX};
  const uint8_t kCount = sizeof(kExtremes) / sizeof(kExtremes[0]);
  if (n % 8 == 0) return kExtremes[(n / 8) % kCount];
  return (int32_t)rng.next() >> (n % 24);
}

}  // namespace vectors
}  // namespace wmra
