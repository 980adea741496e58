// When J6's angle is recorded (written when J6 comes to rest, never in a loop): once J6
// has stayed within band_steps of where it stopped for rest_ms while its count is its angle
// (homed), if it stands at least min_change_steps from the angle last recorded. At rest means
// within the band, not a count that does not change: a stepper held by its tracking loop may
// dither a step or two about its reference. At most one record per rest: J6 must leave the band
// before the next, so a J6 that stands writes nothing more however long it stands, and one that
// moves on without staying rest_ms in a band writes nothing while it moves.
#pragma once

#include <stdint.h>

namespace wmra {
namespace core {

struct RestWatchConfig {
  uint16_t rest_ms;
  int16_t band_steps;
  int16_t min_change_steps;
};

class RestWatch {
 public:
  void configure(const RestWatchConfig& c) { c_ = c; }
  // the angle (steps) the EEPROM holds, or none
  void set_recorded(int32_t steps) {
    recorded_ = steps;
    has_recorded_ = true;
  }
  void clear_recorded() { has_recorded_ = false; }

  // One tick: true when the position is to be recorded now (it is then the one recorded).
  bool update(int32_t position_steps, bool trusted, uint8_t ticks) {
    if (!trusted || beyond(position_steps - anchor_, c_.band_steps)) {
      anchor_ = position_steps;
      still_ms_ = 0;
      return false;
    }
    if (still_ms_ >= c_.rest_ms) return false;  // this rest's decision is made
    still_ms_ = (uint16_t)(still_ms_ + ticks);
    if (still_ms_ < c_.rest_ms) return false;
    if (has_recorded_ && !beyond(position_steps - recorded_, c_.min_change_steps - 1)) return false;
    set_recorded(position_steps);
    return true;
  }

 private:
  static bool beyond(int32_t d, int16_t limit) { return d > limit || d < -limit; }

  RestWatchConfig c_{};  // configure()
  int32_t anchor_ = 0;   // where the present rest began
  int32_t recorded_ = 0;
  uint16_t still_ms_ = 0;
  bool has_recorded_ = false;
};

}  // namespace core
}  // namespace wmra
