// The speed a stepper's ramp is asked for so that its step count follows the reference angle:
// the reference's own speed plus a correction of the position error.
//
// Why not a plain proportional correction. The ramp reaches a new speed only at its
// acceleration limit a, so a gain k on the error overshoots once k |e| exceeds the speed the
// ramp can still brake from within |e|, sqrt(2 a |e|): a stepper that lagged (after a stop of
// the reference, a singular slow-down) then swings around the reference, and on J1, which
// carries the arm at a = 0.6 rad/s^2, that swing was 0.1 rad wide and lost steps. Capping the
// correction at sqrt(2 (a/2) |e|) = sqrt(a |e|) brakes in time with half the acceleration to
// spare (the "square-root controller" of time-optimal positioning); below |e| = a / k^2 the
// linear term is the smaller one and settles the last steps without a kink.
#pragma once

#include <stdint.h>

#include "kinematics/fixed_trig.h"

namespace wmra {
namespace core {

struct StepperTracking {
  int16_t gain_per_s;      // k
  int32_t accel_steps_s2;  // a, the ramp's limit
  int32_t slowest_steps_s;  // the ramp's slowest speed: below it a speed is a stop
  // derived once (a constexpr table folds them at compile time): two 32-bit divisions per
  // call cost ~600 cycles on the AVR
  uint32_t linear_up_to = (uint32_t)accel_steps_s2 / ((uint32_t)gain_per_s * (uint32_t)gain_per_s);
  uint32_t e_max = 0xFFFFFFFFu / (uint32_t)accel_steps_s2;  // a e within 32 bits
};

// A reference slower than the ramp's slowest speed (standing, or creeping: the drift
// correction's ~1 mrad/s at rest after a motion) has a step's error left alone: the ramp starts
// at its slowest speed (a step per 50 ms, the linear term's for one step) and stops within a step
// of it, so correcting one step steps the joint back and forth about such a reference, every
// 50 ms for as long as it creeps. A moving reference keeps the correction of every step: without
// it the step rates follow the stick's release 24 ms later.
constexpr uint32_t kTrackingDeadband_steps = 1;

inline int32_t tracking_speed_steps_s(const StepperTracking& c, int32_t reference_speed_steps_s, int32_t error_steps) {
  const uint32_t e = (uint32_t)(error_steps < 0 ? -error_steps : error_steps);
  uint32_t correction;
  const bool creeping = reference_speed_steps_s < c.slowest_steps_s && reference_speed_steps_s > -c.slowest_steps_s;
  if (creeping && e <= kTrackingDeadband_steps) {
    correction = 0;
  } else if (e <= c.linear_up_to) {
    correction = e * (uint32_t)c.gain_per_s;
  } else {
    correction = fx::isqrt32((uint32_t)c.accel_steps_s2 * (e < c.e_max ? e : c.e_max));
  }
  return reference_speed_steps_s + (error_steps < 0 ? -(int32_t)correction : (int32_t)correction);
}

}  // namespace core
}  // namespace wmra
