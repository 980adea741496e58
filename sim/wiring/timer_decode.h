// What an output-compare pin carries, decoded from the timer's registers as the datasheet
// defines them (simavr 1.6 models the pins of some PWM modes and not others: this does not
// depend on it). Pure functions of register values, so the host tests check them directly.
#pragma once

#include <cstdint>

#include "wmra_mega/board.h"

namespace wmra {
namespace m2560 {

struct TimerSnapshot {
  uint8_t tccra = 0, tccrb = 0;
  uint16_t ocr[3] = {0, 0, 0};
  uint16_t icr = 0;
  bool sixteen_bit = false;
};

enum class Wave : uint8_t { normal, ctc, fast_pwm, phase_pwm, reserved };

struct TimerMode {
  Wave wave;
  uint16_t top;
  bool top_is_ocra;  // OCRnA holds TOP (so channel A is not a PWM output)
};

TimerMode timer_mode(const TimerSnapshot& t);

// How the pin of compare channel `ch` is driven:
//   port:   COM = 0 (or a reserved COM in this mode): the pin is a plain port pin;
//   pwm:    a PWM waveform of the given duty (fraction of the period at high level);
//   events: set, cleared or toggled by compare matches outside PWM (follow the pin itself).
struct PinDrive {
  enum class Source : uint8_t { port, pwm, events } source;
  double duty;
};
PinDrive compare_pin_drive(const TimerSnapshot& t, board::Channel ch);

}  // namespace m2560
}  // namespace wmra
