// J6's homing (docs/arm-guide.md, using the arm), one decision per control tick. J6's zero switch closes once a turn,
// within edge_steps of each whole turn (0, +-360 deg), so J6's position alone does not tell its
// turn: the homing goes by what the count is believed to be.
//
//   exact             the count is J6's angle: its angle at rest from EEPROM at power-up, or the
//                     count since the last homing. J6 goes to the switch of the whole turn nearest
//                     the count (at most half a turn and the cam away); at +-360 deg it comes
//                     from inside its range. The switch must be where the count says, within
//                     tolerance_steps: closed at the start only on the cam, open there only at
//                     its edge, no closing on the way, a closing in the slow approach. Anything
//                     else contradicts the count (the wrist was turned while J6 was not driven):
//                     J6 stops where it is and the homing fails.
//   within_half_turn  the count is within half a turn of the angle: no angle at power-up (the
//                     installer leaves J6 near 0), or J6's switch closed where its count said it
//                     could not be. Sweeps that widen either way from where J6 starts
//                     (sweep_steps, each from the sweep's start) find the nearest switch, and its
//                     turn is the whole turn nearest the count there. They reach half a turn
//                     less the cam either way: from (-180, 180) deg (a power-up without an angle)
//                     they stay within +-358 deg; beyond, the switches at +-360 deg stop them.
//   contradicted      a homing found the count wrong: J6 does not move and the homing fails at
//                     once, until a power-up (set_belief) with J6 set near 0 by hand.
//
// All three end the same way: fast to approach_steps before the cam's edge, slowly onto the
// edge, and the count set from the step at which the switch closed (its filter's delay at the
// slow speed corrected). No phase turns J6 past a switch: every closing stops it, and the fast
// speed's overrun stays within the cam (joints_config.h), so J6 never passes +-360 deg whatever
// the belief. A homing that ends sets the belief to exact.
//
// The ramp is J6's StepRate (commanded by the caller inside its Command scope); moving says
// whether J6 still steps; ticks are the control ticks (ms) since the last update.
#pragma once

#include <stdint.h>

namespace wmra {
namespace core {

struct WristHomingConfig {
  int32_t turn_steps;
  int32_t range_steps;      // J6 turns within +-range_steps of zero
  int32_t edge_steps;       // the switch closes this far before each whole turn, from either side
  int32_t approach_steps;   // the slow approach starts this far before the edge
  int32_t tolerance_steps;  // an exact count is within this of J6's angle
  int32_t fast_steps_s;
  int32_t slow_steps_s;
  int32_t fast_lag_steps;  // steps made between the switch closing and being seen, at each speed
  int32_t slow_lag_steps;
  uint16_t settle_ms;  // the switch's filter settled after J6 stops
  int8_t dir_at_zero;  // the direction J6 approaches 0 in when it starts on the cam
  int32_t sweep_steps[4];
};

// (within_half_turn 0: a homing that nobody told otherwise, all-zero, as the firmware keeps it in .bss)
enum class WristBelief : uint8_t { within_half_turn, exact, contradicted };

class WristHoming {
 public:
  enum class Phase : uint8_t { idle, sweep, sweep_brake, sweep_settle, approach, approach_settle, seek_slow, settle, done, failed };

  void configure(const WristHomingConfig& c) {
    c_ = c;
    phase_ = Phase::idle;
  }
  void set_belief(WristBelief b) { belief_ = b; }
  WristBelief belief() const { return belief_; }
  void restart() { phase_ = Phase::idle; }

  Phase phase() const { return phase_; }
  bool done() const { return phase_ == Phase::done; }
  bool failed() const { return phase_ == Phase::failed; }
  // once after a homing that found the count wrong (the caller forgets the recorded angle)
  bool take_contradiction() {
    const bool c = contradiction_;
    contradiction_ = false;
    return c;
  }

  template <class Ramp>
  void update(bool closed, bool moving, uint8_t ticks, Ramp& ramp) {
    const int32_t p = ramp.position_steps();
    switch (phase_) {
      case Phase::idle:
        begin(closed, p, ramp);
        break;
      case Phase::sweep:
        if (caught(closed, p, ramp, Phase::sweep_brake)) break;
        if (!moving && p == target_) {
          waited_ms_ = 0;
          phase_ = Phase::sweep_settle;
        }
        break;
      case Phase::sweep_brake:
        if (!moving) found(ramp);
        break;
      case Phase::sweep_settle:  // the leg's end: the switch may have closed as J6 stopped
        if (closed) {
          trigger_ = p;
          found(ramp);
        } else if (settled(ticks)) {
          ++leg_;
          next_leg(p, ramp);
        }
        break;
      case Phase::approach:
        if (closed && !was_closed_) {
          give_up(ramp);
        } else if (!moving && p == start_) {
          waited_ms_ = 0;
          phase_ = Phase::approach_settle;
        }
        break;
      case Phase::approach_settle:
        if (!settled(ticks)) break;
        if (closed) {
          give_up(ramp);
        } else {
          ramp.move_to(bound_, (uint32_t)c_.slow_steps_s);
          phase_ = Phase::seek_slow;
        }
        break;
      case Phase::seek_slow:
        if (caught(closed, p, ramp, Phase::settle)) break;
        if (!moving && p == bound_) give_up(ramp);
        break;
      case Phase::settle:
        if (!moving) {
          ramp.set_position(zero_ - toward(c_.edge_steps - c_.slow_lag_steps) + (p - trigger_));
          belief_ = WristBelief::exact;
          phase_ = Phase::done;
        }
        break;
      case Phase::done:
      case Phase::failed:
        break;
    }
    was_closed_ = closed;
  }

 private:
  static int32_t magnitude(int32_t x) { return x < 0 ? -x : x; }
  // x steps in the approach's direction (a sign, not a 32-bit product)
  int32_t toward(int32_t x) const { return dir_ > 0 ? x : -x; }
  // the whole turn nearest steps, within the range
  int32_t nearest_turn(int32_t steps) const {
    int32_t z = 0;
    while (steps - z > c_.turn_steps / 2 && z + c_.turn_steps <= c_.range_steps) z += c_.turn_steps;
    while (z - steps > c_.turn_steps / 2 && z - c_.turn_steps >= -c_.range_steps) z -= c_.turn_steps;
    return z;
  }
  // the side a whole turn is approached from: +-360 deg from inside the range; 0 from the side J6
  // is on (on the cam, dir_at_zero)
  int8_t approach_dir(int32_t zero, int32_t p) const {
    if (zero != 0) return zero > 0 ? 1 : -1;
    if (p < -c_.edge_steps) return 1;
    if (p > c_.edge_steps) return -1;
    return c_.dir_at_zero;
  }
  bool settled(uint8_t ticks) {
    waited_ms_ = (uint16_t)(waited_ms_ + ticks);
    return waited_ms_ >= c_.settle_ms;
  }

  template <class Ramp>
  void begin(bool closed, int32_t p, Ramp& ramp) {
    if (belief_ == WristBelief::contradicted) {
      fail(ramp);
      return;
    }
    if (belief_ == WristBelief::exact) {
      zero_ = nearest_turn(p);
      dir_ = approach_dir(zero_, p);
      const int32_t off = magnitude(p - zero_);
      if (closed ? off > c_.edge_steps + c_.tolerance_steps : off + c_.tolerance_steps < c_.edge_steps) {
        give_up(ramp);
        return;
      }
      approach(zero_ - toward(c_.edge_steps + c_.approach_steps), zero_, closed, ramp);
    } else if (closed) {
      // on a cam: its turn is the whole turn nearest the count, its edge on the approach's side
      // within two half widths of here: backed off a half width and the run-up, J6 is off the
      // cam by at least the run-up less a half width; the edge is met before here (a half width
      // on, for the filter's delay)
      zero_ = nearest_turn(p);
      dir_ = approach_dir(zero_, zero_);
      approach(p - toward(c_.edge_steps + c_.approach_steps), p + toward(c_.edge_steps / 2), closed, ramp);
    } else {
      origin_ = p;
      leg_ = 0;
      next_leg(p, ramp);
    }
  }
  template <class Ramp>
  void next_leg(int32_t p, Ramp& ramp) {
    for (; leg_ < 4; ++leg_) {
      const int32_t target = origin_ + c_.sweep_steps[leg_];
      if (target == p) continue;
      target_ = target;
      dir_ = target > p ? 1 : -1;
      ramp.move_to(target, (uint32_t)c_.fast_steps_s);
      phase_ = Phase::sweep;
      return;
    }
    fail(ramp);
  }
  // A sweep's switch, seen at trigger_ moving in dir_: the cam's edge, the filter's delay at the
  // fast speed before, and its turn the whole turn nearest the count there
  template <class Ramp>
  void found(Ramp& ramp) {
    const int32_t zero_count = trigger_ - toward(c_.fast_lag_steps - c_.edge_steps);
    zero_ = nearest_turn(zero_count);
    approach(zero_count - toward(c_.edge_steps + c_.approach_steps), zero_count, true, ramp);
  }
  // fast to start (off the cam, on the side dir_ comes from), then slowly towards bound
  template <class Ramp>
  void approach(int32_t start, int32_t bound, bool closed, Ramp& ramp) {
    start_ = start;
    bound_ = bound;
    was_closed_ = closed;
    ramp.move_to(start, (uint32_t)c_.fast_steps_s);
    phase_ = Phase::approach;
  }
  // the switch seen closed while J6 moves: where, and J6 brakes
  template <class Ramp>
  bool caught(bool closed, int32_t p, Ramp& ramp, Phase next) {
    if (!closed) return false;
    trigger_ = p;
    ramp.stop();
    phase_ = next;
    return true;
  }
  // the switch is not where the belief says: an exact count is wrong, J6 stops
  template <class Ramp>
  void give_up(Ramp& ramp) {
    if (belief_ == WristBelief::exact) {
      belief_ = WristBelief::contradicted;
      contradiction_ = true;
    }
    fail(ramp);
  }
  template <class Ramp>
  void fail(Ramp& ramp) {
    ramp.stop();
    phase_ = Phase::failed;
  }

  WristHomingConfig c_{};
  WristBelief belief_ = WristBelief::within_half_turn;
  Phase phase_ = Phase::idle;
  bool was_closed_ = false;
  bool contradiction_ = false;
  int8_t dir_ = 0;   // set by each approach and leg
  uint8_t leg_ = 0;
  uint16_t waited_ms_ = 0;
  int32_t origin_ = 0;   // the sweep's start
  int32_t target_ = 0;   // the sweep leg's end
  int32_t trigger_ = 0;  // where the switch was seen closing
  int32_t zero_ = 0;     // the whole turn homed to (steps)
  int32_t start_ = 0;    // the slow approach's start
  int32_t bound_ = 0;    // and how far it goes
};


}  // namespace core
}  // namespace wmra
