// One DC joint's position servo: the reference (pot units) in, a duty out, with the
// plausibility checks of its potentiometer and motion.
//
// Controller: the PID of lib/control/pid.h, or seed 1's relay with dead zone (config). Parking:
// a worm-geared joint holds itself unpowered, so once the error has stayed within park_units
// for park_ticks the duty is 0 and the PID restarts bumplessly from rest every tick, until the
// error leaves twice the band; holding with the integral's effort would draw current (about
// 20 A stretched) for nothing. The checks get the duty that was applied during the tick that
// ends with the reading, as PlausibilityMonitor requires.
#pragma once

#include <stdint.h>

#include "control/pid.h"
#include "control/plausibility.h"
#include "control/relay.h"

namespace wmra {
namespace core {

struct DcServoConfig {
  bool use_relay;
  control::PidConfig pid;
  control::RelayConfig relay;
  control::PlausibilityConfig checks;
  int32_t park_units;
  uint16_t park_ticks;
};

class DcServo {
 public:
  bool configure(const DcServoConfig& c) {
    c_ = c;
    return pid_.configure(c.pid) == control::PidStatus::ok && relay_.configure(c.relay) == control::RelayStatus::ok &&
           checks_.configure(c.checks) == control::PlausibilityStatus::ok && c.park_units >= 0;
  }

  // from rest at the measured position (start-up, and after the bridge was switched off)
  void rest(int32_t measured_units) {
    pid_.start(measured_units, measured_units, 0);
    parked_ = true;
    in_band_ = 0;
    applied_ = 0;
  }
  void reset_checks(int32_t measured_units) { checks_.reset(measured_units); }

  // The reading of this tick: runs the checks (on the duty applied since the last reading).
  uint8_t check(int32_t measured_units) { return checks_.update(applied_, measured_units); }

  // The duty for the next tick.
  int16_t update(int32_t reference_units, int32_t measured_units) {
    const int32_t e = reference_units - measured_units;
    const uint32_t error = (uint32_t)(e < 0 ? -e : e);
    if (parked_) {
      if (error > 2 * (uint32_t)c_.park_units) {
        parked_ = false;
        in_band_ = 0;
      } else {
        pid_.start(reference_units, measured_units, 0);
        applied_ = 0;
        return 0;
      }
    }
    in_band_ = error <= (uint32_t)c_.park_units ? (uint16_t)(in_band_ + 1) : 0;
    if (in_band_ >= c_.park_ticks) {
      parked_ = true;
      pid_.start(reference_units, measured_units, 0);
      applied_ = 0;
      return 0;
    }
    applied_ = c_.use_relay ? relay_.update(reference_units, measured_units) : pid_.update(reference_units, measured_units);
    return applied_;
  }

  bool parked() const { return parked_; }
  int16_t applied() const { return applied_; }

 private:
  DcServoConfig c_{};
  control::Pid pid_;
  control::Relay relay_;
  control::PlausibilityMonitor checks_;
  bool parked_ = true;
  uint16_t in_band_ = 0;
  int16_t applied_ = 0;
};

}  // namespace core
}  // namespace wmra
