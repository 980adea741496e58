// Homing of one stepper joint to its switch, one decision per control tick:
//
//   seek_fast   towards the switch at the fast speed (from the switch: back off first)
//   brake       the switch closed: brake to rest at the ramp's acceleration
//   back_off    move back_off_steps away from it
//   seek_slow   towards it again at the slow speed (the switch's RC filter delays its edge by
//               tens of ms: slowly, that delay costs a fraction of a mrad)
//   settle      it closed: brake, and set the position count so that the step at which the
//               switch closed (its filter's delay, trigger_lag_steps, before it was seen) is
//               home_steps
//   done / failed (no switch within max_travel_steps, or still closed after backing off)
//
// The ramp is the joint's StepRamp (commanded by the caller inside its Command scope); moving
// says whether the joint still steps.
#pragma once

#include <stdint.h>

namespace wmra {
namespace core {

struct HomingConfig {
  int8_t dir;                 // +1: the switch is in the positive direction
  int32_t fast_steps_s;
  int32_t slow_steps_s;
  int32_t back_off_steps;
  int32_t home_steps;         // the joint's position where the switch closes, moving in dir
  int32_t max_travel_steps;   // seeking further than this without a switch is a failure
  int32_t trigger_lag_steps;  // steps made at the slow speed between the switch closing and being seen
};

enum class HomingPhase : uint8_t { idle, seek_fast, brake, back_off, seek_slow, settle, done, failed };

class StepperHoming {
 public:
  void configure(const HomingConfig& c) {
    c_ = c;
    phase_ = HomingPhase::idle;
  }
  void restart() { phase_ = HomingPhase::idle; }

  HomingPhase phase() const { return phase_; }
  bool done() const { return phase_ == HomingPhase::done; }
  bool failed() const { return phase_ == HomingPhase::failed; }

  template <class Ramp>
  void update(bool switch_closed, bool moving, Ramp& ramp) {
    const int32_t position = ramp.position_steps();
    switch (phase_) {
      case HomingPhase::idle:
        start_ = position;
        if (switch_closed) {
          back_off(ramp, position);
        } else {
          ramp.set_speed(c_.dir * c_.fast_steps_s);
          phase_ = HomingPhase::seek_fast;
        }
        break;
      case HomingPhase::seek_fast:
        if (switch_closed) {
          ramp.stop();
          phase_ = HomingPhase::brake;
        } else if (travelled(position) > c_.max_travel_steps) {
          fail(ramp);
        }
        break;
      case HomingPhase::brake:
        if (!moving) back_off(ramp, position);
        break;
      case HomingPhase::back_off:
        if (moving) break;
        if (switch_closed) {
          fail(ramp);
        } else {
          start_ = position;
          ramp.set_speed(c_.dir * c_.slow_steps_s);
          phase_ = HomingPhase::seek_slow;
        }
        break;
      case HomingPhase::seek_slow:
        if (switch_closed) {
          trigger_ = position;
          ramp.stop();
          phase_ = HomingPhase::settle;
        } else if (travelled(position) > 2 * c_.back_off_steps) {
          fail(ramp);
        }
        break;
      case HomingPhase::settle:
        if (!moving) {
          ramp.set_position(c_.home_steps + c_.dir * c_.trigger_lag_steps + (position - trigger_));
          phase_ = HomingPhase::done;
        }
        break;
      case HomingPhase::done:
      case HomingPhase::failed:
        break;
    }
  }

 private:
  int32_t travelled(int32_t position) const { return position > start_ ? position - start_ : start_ - position; }
  template <class Ramp>
  void back_off(Ramp& ramp, int32_t position) {
    ramp.move_to(position - c_.dir * c_.back_off_steps, (uint32_t)c_.fast_steps_s);
    phase_ = HomingPhase::back_off;
  }
  template <class Ramp>
  void fail(Ramp& ramp) {
    ramp.stop();
    phase_ = HomingPhase::failed;
  }

  HomingConfig c_{1, 0, 0, 0, 0, 0, 0};
  HomingPhase phase_ = HomingPhase::idle;
  int32_t start_ = 0;
  int32_t trigger_ = 0;
};

}  // namespace core
}  // namespace wmra
