// Plausibility checks on a DC joint, which the firmware turns into faults: fed once
// per sample with the duty it applied and the position it read, it raises latched flags for
//   stall       the drive is at or above drive_threshold (saturated; or at the caller's bound
//               below it, set_drive_bounds) for stall_samples and the joint has not moved
//               stall_progress units forward in that window;
//   sign_error  under that drive the joint moves against it by sign_distance units (measured
//               from the furthest point it reached forward), after a grace period that lets
//               it coast out of its previous motion when the drive reverses;
//   jump        the reading changes by more than max_step units in one sample: faster than
//               the joint can move (a wiper lifting, a broken wire, a noisy channel);
//   rail        the reading is outside [rail_low, rail_high] for rail_samples samples in a row
//               (an open or shorted potentiometer reads at a rail).
// A rail or jump sample is not used for the motion checks. The motion checks may run at a lower
// rate than the readings' (update's motion_samples): with a servo that changes its duty every
// few samples, each window then spans one duty, and a glitch is still caught at the reading
// it is in. Positions are 16-bit (pot units:
// ADC counts x 16); the checks use only comparisons and 16-bit differences, saturated to
// +-32767 where signed (every threshold is below that, so the saturation changes no decision).
// Flags stay set until reset().
#pragma once

#include <stdint.h>

#include "control/control_math.h"

namespace wmra {
namespace control {

enum PlausibilityFault : uint8_t {
  kFaultStall = 1,
  kFaultSignError = 2,
  kFaultJump = 4,
  kFaultRail = 8,
};

struct PlausibilityConfig {
  int16_t drive_threshold_q15;  // |duty| at or above which the joint must move, > 0
  uint16_t stall_samples;       // > 0
  int16_t stall_progress;       // units forward within stall_samples, > 0
  uint16_t sign_grace_samples;  // after a reversal of the drive
  int16_t sign_distance;        // units against the drive, > 0
  int16_t max_step;             // largest plausible |change| per sample, > 0
  int16_t rail_low;             // readings below are a rail
  int16_t rail_high;            // readings above are a rail
  uint8_t rail_samples;         // > 0
};

enum class PlausibilityStatus : uint8_t { ok = 0, invalid };

constexpr PlausibilityStatus plausibility_check(const PlausibilityConfig& c) {
  return (c.drive_threshold_q15 <= 0 || c.stall_samples == 0 || c.stall_progress <= 0 || c.sign_distance <= 0 ||
          c.max_step <= 0 || c.rail_low >= c.rail_high || c.rail_samples == 0)
             ? PlausibilityStatus::invalid
             : PlausibilityStatus::ok;
}

class PlausibilityMonitor {
 public:
  PlausibilityStatus configure(const PlausibilityConfig& c) {
    const PlausibilityStatus s = plausibility_check(c);
    if (s != PlausibilityStatus::ok) return s;
    c_ = c;
    up_q15_ = down_q15_ = c.drive_threshold_q15;
    configured_ = true;
    reset(0);
    return s;
  }

  // Clears the flags; position is the present reading.
  // The drive's saturation as the caller bounds it now, each way (magnitudes): a drive held
  // below drive_threshold (a speed governor) is saturated at its bound, and a joint that does
  // not move under it is stalled. Lowers a threshold only (to at least 1).
  void set_drive_bounds(int16_t up_q15, int16_t down_q15) {
    up_q15_ = lowered(up_q15);
    down_q15_ = lowered(down_q15);
  }

  void reset(int16_t position) {
    faults_ = 0;
    prev_ = position;
    have_prev_ = false;
    drive_dir_ = 0;
    rail_count_ = 0;
  }

  // One sample: the reading, its rail and jump checks, and the motion checks if motion_samples
  // is not 0. samples: the sample periods since the last reading (a caller that overran): the
  // joint may have moved that many steps. motion_samples: the sample periods since the motion
  // checks last ran (their counts advance by that many), during which duty_q15 was applied
  // throughout: by default every sample's. Returns the latched flags.
  uint8_t update(int16_t duty_q15, int16_t position, uint8_t samples = 1) { return update(duty_q15, position, samples, samples); }
  // Not inlined: one copy serves the three DC joints (inlined in the caller's loop it took the
  // registers of the code around it: the firmware's stick gate, 146 cycles a tick more on
  // average, against its 60 % CPU load at 59.1 %).
  __attribute__((noinline)) uint8_t update(int16_t duty_q15, int16_t position, uint8_t samples, uint8_t motion_samples) {
    if (!configured_) return faults_;
    if (position < c_.rail_low || position > c_.rail_high) {
      rail_count_ = add_saturated_u8(rail_count_, samples);
      if (rail_count_ >= c_.rail_samples) faults_ |= kFaultRail;
      drive_dir_ = 0;  // restart the motion checks on good data
      return faults_;
    }
    rail_count_ = 0;
    // the largest plausible change over the samples (one sample, the usual call: no product)
    // over several samples capped at 65535, past every 16-bit distance: the same decision
    const uint16_t max_change = samples == 1 ? (uint16_t)c_.max_step : max_step_over(samples);
    if (have_prev_ && distance_u16(position, prev_) > max_change) {
      faults_ |= kFaultJump;
      prev_ = position;
      drive_dir_ = 0;
      return faults_;
    }
    prev_ = position;
    have_prev_ = true;
    if (motion_samples == 0) return faults_;

    const int8_t dir = duty_q15 >= up_q15_ ? 1 : duty_q15 <= -down_q15_ ? -1 : 0;
    if (dir == 0) {
      drive_dir_ = 0;
      return faults_;
    }
    if (dir != drive_dir_) {  // a new window of saturated drive
      drive_dir_ = dir;
      stall_anchor_ = position;
      stall_count_ = 0;
      grace_ = c_.sign_grace_samples;
      peak_ = position;
      return faults_;
    }
    // forward motion of the joint, in the drive's sense
    const int16_t forward =
        dir > 0 ? sub_saturated_i16(position, stall_anchor_) : sub_saturated_i16(stall_anchor_, position);
    if (forward >= c_.stall_progress) {
      stall_anchor_ = position;
      stall_count_ = 0;
    } else if ((stall_count_ = (uint16_t)(stall_count_ + motion_samples)) >= c_.stall_samples) {
      faults_ |= kFaultStall;
      stall_count_ = c_.stall_samples;
    }
    if (grace_ > 0) {
      grace_ = grace_ > motion_samples ? (uint16_t)(grace_ - motion_samples) : (uint16_t)0;
      peak_ = position;
    } else {
      const int16_t ahead = dir > 0 ? sub_saturated_i16(position, peak_) : sub_saturated_i16(peak_, position);
      if (ahead > 0) {
        peak_ = position;
      } else if (ahead <= -c_.sign_distance) {
        faults_ |= kFaultSignError;
      }
    }
    return faults_;
  }

  uint8_t faults() const { return faults_; }

 private:
  uint16_t max_step_over(uint8_t samples) const {
    const uint32_t m = fx::mul_uu((uint16_t)c_.max_step, samples);
    return (uint16_t)(m > 65535 ? 65535 : m);
  }

  PlausibilityConfig c_{1, 1, 1, 0, 1, 1, 0, 1, 1};
  // drive_threshold_q15 each way, or below it the caller's bound (set_drive_bounds)
  int16_t up_q15_ = 1, down_q15_ = 1;
  int16_t lowered(int16_t bound_q15) const {
    const int16_t t = bound_q15 < 1 ? (int16_t)1 : bound_q15;
    return t < c_.drive_threshold_q15 ? t : c_.drive_threshold_q15;
  }
  bool configured_ = false;
  uint8_t faults_ = 0;
  int16_t prev_ = 0;
  bool have_prev_ = false;
  int8_t drive_dir_ = 0;
  int16_t stall_anchor_ = 0;
  uint16_t stall_count_ = 0;
  uint16_t grace_ = 0;
  int16_t peak_ = 0;
  uint8_t rail_count_ = 0;
};

}  // namespace control
}  // namespace wmra
