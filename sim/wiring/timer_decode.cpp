#include "timer_decode.h"

namespace wmra {
namespace m2560 {

TimerMode timer_mode(const TimerSnapshot& t) {
  const int wgm = (t.tccra & 3) | (((t.tccrb >> 3) & (t.sixteen_bit ? 3 : 1)) << 2);
  const uint16_t ocra = t.ocr[0];
  if (!t.sixteen_bit) {
    switch (wgm) {
      case 0: return {Wave::normal, 0xFF, false};
      case 1: return {Wave::phase_pwm, 0xFF, false};
      case 2: return {Wave::ctc, ocra, true};
      case 3: return {Wave::fast_pwm, 0xFF, false};
      case 5: return {Wave::phase_pwm, ocra, true};
      case 7: return {Wave::fast_pwm, ocra, true};
      default: return {Wave::reserved, 0xFF, false};
    }
  }
  switch (wgm) {
    case 0: return {Wave::normal, 0xFFFF, false};
    case 1: return {Wave::phase_pwm, 0xFF, false};
    case 2: return {Wave::phase_pwm, 0x1FF, false};
    case 3: return {Wave::phase_pwm, 0x3FF, false};
    case 4: return {Wave::ctc, ocra, true};
    case 5: return {Wave::fast_pwm, 0xFF, false};
    case 6: return {Wave::fast_pwm, 0x1FF, false};
    case 7: return {Wave::fast_pwm, 0x3FF, false};
    case 8: return {Wave::phase_pwm, t.icr, false};  // phase and frequency correct
    case 9: return {Wave::phase_pwm, ocra, true};
    case 10: return {Wave::phase_pwm, t.icr, false};
    case 11: return {Wave::phase_pwm, ocra, true};
    case 12: return {Wave::ctc, t.icr, false};
    case 14: return {Wave::fast_pwm, t.icr, false};
    case 15: return {Wave::fast_pwm, ocra, true};
    default: return {Wave::reserved, 0xFFFF, false};
  }
}

PinDrive compare_pin_drive(const TimerSnapshot& t, board::Channel ch) {
  const int com = (t.tccra >> (6 - 2 * (int)ch)) & 3;
  if (com == 0) return {PinDrive::Source::port, 0};
  const TimerMode m = timer_mode(t);
  const bool clock_on = (t.tccrb & 7) != 0;
  if (m.wave == Wave::normal || m.wave == Wave::ctc || m.wave == Wave::reserved || !clock_on) {
    return {PinDrive::Source::events, 0};
  }
  if (com == 1) {
    // in PWM modes COM = 1 toggles OCnA on each match when OCRnA is TOP (a 50 % square wave at
    // half the PWM frequency); for every other channel it leaves the pin to the port
    if (ch == board::Channel::a && m.top_is_ocra) return {PinDrive::Source::pwm, 0.5};
    return {PinDrive::Source::port, 0};
  }
  const uint16_t ocr = t.ocr[(int)ch];
  double high;
  if (m.top == 0) {
    high = 1.0;
  } else if (m.wave == Wave::fast_pwm) {
    // set at BOTTOM, cleared on the match: OCR + 1 counts of TOP + 1 (OCR = 0 is a one-count
    // spike; OCR >= TOP never clears: constantly high)
    high = ocr >= m.top ? 1.0 : (ocr + 1.0) / (m.top + 1.0);
  } else {
    // phase correct: cleared on the match up, set on the match down: OCR of TOP
    high = ocr >= m.top ? 1.0 : (double)ocr / m.top;
  }
  return {PinDrive::Source::pwm, com == 2 ? high : 1.0 - high};
}

}  // namespace m2560
}  // namespace wmra
