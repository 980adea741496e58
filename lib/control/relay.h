// Seed 1's sampled relay with a dead zone (three-level on-off control), the configurable
// alternative to the PID for a DC joint.
//
// The law (Miranda's thesis, chapter 4, eq. 4.8), with E' the dead-zone half-width ("maximum allowed
// error"), sampled every period and held until the next sample:
//     H = +1 if E >= E',  0 if |E| < E',  -1 if E <= -E'
// and the duty is H times the drive amplitude. E' = 0 is the ideal on-off relay; at E = 0 its
// two outer cases overlap, and this picks 0 (no drive at zero error). The thesis uses no
// hysteresis and lists it as future work; hysteresis_counts > 0 keeps the drive on until |E|
// falls below E' - h (default 0: the thesis's law, stateless). The thesis analyses it on
// G(s) = K_m / (s (tau s + 1)) (K_m = 2.4 rad/(V s), tau = 0.255 s); its printed velocity
// solution (4.22, 4.24) is wrong, the corrected sample map is in
// test_relay_button, which checks the relay on it: an on-off relay limit-cycles about the target, a
// wide enough dead zone settles inside +-E'.
// Integer only: the error is a 32-bit difference of position units; the duty is Q15.
#pragma once

#include <stdint.h>

#include "control/control_math.h"

namespace wmra {
namespace control {

struct RelayConfig {
  int32_t dead_zone_counts;   // E' >= 0
  int32_t hysteresis_counts;  // h in [0, E'] (0: the thesis's law)
  int16_t drive_q15;          // duty when on, (0, 32767]
};

enum class RelayStatus : uint8_t { ok = 0, invalid };

constexpr RelayStatus relay_check(const RelayConfig& c) {
  return (c.dead_zone_counts < 0 || c.hysteresis_counts < 0 || c.hysteresis_counts > c.dead_zone_counts ||
          c.drive_q15 <= 0)
             ? RelayStatus::invalid
             : RelayStatus::ok;
}

class Relay {
 public:
  RelayStatus configure(const RelayConfig& c) {
    const RelayStatus s = relay_check(c);
    if (s != RelayStatus::ok) return s;
    c_ = c;
    level_ = 0;
    configured_ = true;
    return s;
  }

  // H in {-1, 0, +1} for one sample
  int8_t level(int32_t setpoint, int32_t measurement) {
    if (!configured_) return 0;
    const int32_t e = sub_saturated(setpoint, measurement);
    const int32_t on = c_.dead_zone_counts > 0 ? c_.dead_zone_counts : 1;       // E' (and E != 0)
    int32_t stay = c_.dead_zone_counts - c_.hysteresis_counts;                   // E' - h
    if (stay < 1) stay = 1;
    if (e >= on || (level_ > 0 && e >= stay)) {
      level_ = 1;
    } else if (e <= -on || (level_ < 0 && e <= -stay)) {
      level_ = -1;
    } else {
      level_ = 0;
    }
    return level_;
  }

  // The duty (Q15) for one sample
  int16_t update(int32_t setpoint, int32_t measurement) {
    const int8_t h = level(setpoint, measurement);
    return h > 0 ? c_.drive_q15 : h < 0 ? (int16_t)-c_.drive_q15 : (int16_t)0;
  }

 private:
  RelayConfig c_{0, 0, 1};
  bool configured_ = false;
  int8_t level_ = 0;
};

}  // namespace control
}  // namespace wmra
