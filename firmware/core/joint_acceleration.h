// The joint references' acceleration limit: the joint velocities move from last tick's towards
// the resolved rate's by one common fraction k of the difference, the largest with every
// joint's change within its limit.
//
// Why the references and not only the drives: a stepper's ramp accelerates at its own limit
// (J1 0.6 rad/s^2, it carries the arm), so a reference that stops as fast as the stick's fall
// runs ahead of the joint, which overshoots and comes back (16 mrad on J1, S8); and a joint that
// lags its reference while the others do not moves the hand off its line. One k for all joints
// keeps qd on the straight path in joint space from the old velocity to the new one, so the
// hand's velocity changes along a straight path too (to first order, J constant over a tick),
// and a velocity that met the speed limits and soft limits before and after meets them in
// between.
#pragma once

#include <stdint.h>

#include "core/resolved_rate.h"

namespace wmra {
namespace core {

// qd_rad_s: last tick's references, changed in place towards the wanted velocities,
// scaled(s, wanted_rad_s[j]) (the resolved rate's common factor, applied here in place: a pass
// of its own over the joints cost ~170 cycles with s = 1). max_change_rad_s: each joint's
// largest change over the ticks that passed. Returns k.
inline fx::Unit limit_joint_acceleration(fx::Real* qd_rad_s, fx::Real* wanted_rad_s, fx::Unit s, const fx::Real* max_change_rad_s) {
  fx::Unit k{(int16_t)fx::kUnitOne};
  for (uint8_t j = 0; j < arm::kJoints; ++j) {
    if (s.raw != fx::kUnitOne) wanted_rad_s[j] = scaled(s, wanted_rad_s[j]);
    k = limit_scale(k, wanted_rad_s[j] - qd_rad_s[j], max_change_rad_s[j]);
  }
  if (k.raw == fx::kUnitOne) {
    // a Real at a time (the empty asm keeps the four-byte moves, unrolled: 96 cycles, 144 B):
    // avr-gcc made the six one 24-byte block move, a loop of a byte a step (~210 cycles); an asm
    // loop of four-byte steps cost the joint loop above its registers (net -8 cycles)
    for (uint8_t j = 0; j < arm::kJoints; ++j) {
      int32_t w = wanted_rad_s[j].raw;
      asm("" : "+r"(w));
      qd_rad_s[j].raw = w;
    }
  } else {
    for (uint8_t j = 0; j < arm::kJoints; ++j) qd_rad_s[j] = qd_rad_s[j] + k * (wanted_rad_s[j] - qd_rad_s[j]);
  }
  return k;
}

}  // namespace core
}  // namespace wmra
