// The joystick button: debounce, short press and long press, as a pure function of the
// sampled level and the time (ms). Poll it from the control loop; no interrupt needed.
//
// Why not seed 2's way: its firmware takes the falling edge in an interrupt and ignores
// further edges for 500 ms, so a bounce on release can count as a press and two quick presses
// are lost. Here a level counts only after it has been stable for debounce_ms; a short press
// is reported on release (so that a press that grows long is not also a short one), a long
// press once, when the hold reaches long_press_ms. Times are uint16 ms and compared by modular
// difference, so the 65-second wrap of a millisecond counter is harmless.
#pragma once

#include <stdint.h>

namespace wmra {
namespace control {

enum class ButtonEvent : uint8_t { none = 0, press, long_press };

struct ButtonConfig {
  uint16_t debounce_ms;    // e.g. 20
  uint16_t long_press_ms;  // e.g. 1000, > debounce_ms
};

class Button {
 public:
  bool configure(const ButtonConfig& c) {
    if (c.debounce_ms == 0 || c.long_press_ms <= c.debounce_ms || c.long_press_ms > 30000) return false;
    c_ = c;
    down_ = raw_ = false;
    long_sent_ = false;
    configured_ = true;
    return true;
  }

  // raw_down: the pin says pressed (after the caller's polarity); now_ms: a free-running clock
  ButtonEvent update(bool raw_down, uint16_t now_ms) {
    if (!configured_) return ButtonEvent::none;
    if (raw_down != raw_) {
      raw_ = raw_down;
      raw_since_ = now_ms;
    }
    if (raw_ != down_ && (uint16_t)(now_ms - raw_since_) >= c_.debounce_ms) {
      down_ = raw_;
      if (down_) {
        down_since_ = raw_since_;
        long_sent_ = false;
      } else if (!long_sent_) {
        return ButtonEvent::press;
      }
    }
    if (down_ && !long_sent_ && (uint16_t)(now_ms - down_since_) >= c_.long_press_ms) {
      long_sent_ = true;
      return ButtonEvent::long_press;
    }
    return ButtonEvent::none;
  }

  bool down() const { return down_; }  // debounced level

 private:
  ButtonConfig c_{20, 1000};
  bool configured_ = false;
  bool raw_ = false;
  bool down_ = false;
  bool long_sent_ = false;
  uint16_t raw_since_ = 0;
  uint16_t down_since_ = 0;
};

}  // namespace control
}  // namespace wmra
