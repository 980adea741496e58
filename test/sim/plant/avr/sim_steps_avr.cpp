// Step trains on the three STEP pins from Timer5's compare outputs, as the firmware makes them:
// normal mode at 2 MHz, toggle on compare, OCR5x += half a period in each compare ISR. Each
// channel stops after its count. The main loop toggles D49 (PL0, the STEP pins' port) with
// read-modify-write, which must not disturb the step pins.
#include "board_io.h"

using namespace wmra;
using io::Channel;
using io::ComparePin;

namespace {

struct Train {
  ComparePin pin;
  uint16_t half_period;  // timer ticks (0.5 us)
  uint16_t edges;        // two per step
};

// J1: 250 Hz, 100 steps; J5: 4 kHz, 1000 steps; J6: 2.5 kHz, 500 steps
constexpr Train kTrains[3] = {
    {board::kStepperJ1.step, 4000, 200},
    {board::kStepperJ5.step, 250, 2000},
    {board::kStepperJ6.step, 400, 1000},
};
volatile uint16_t edges_left[3] = {kTrains[0].edges, kTrains[1].edges, kTrains[2].edges};

inline void on_compare(uint8_t i) {
  const Train& t = kTrains[i];
  io::ocr(t.pin) += t.half_period;
  if (--edges_left[i] == 0) {
    io::set_com(t.pin, 0);  // disconnect: the pin is PORTL again (low)
    TIMSK5 &= (uint8_t) ~(1 << (OCIE5A + (uint8_t)t.pin.channel));
  }
}

constexpr uint8_t train_of(Channel c) {
  return kTrains[0].pin.channel == c ? 0 : kTrains[1].pin.channel == c ? 1 : 2;
}

}  // namespace

ISR(TIMER5_COMPA_vect) { on_compare(train_of(Channel::a)); }
ISR(TIMER5_COMPB_vect) { on_compare(train_of(Channel::b)); }
ISR(TIMER5_COMPC_vect) { on_compare(train_of(Channel::c)); }

int main() {
  const board::StepperPins* s[3] = {&board::kStepperJ1, &board::kStepperJ5, &board::kStepperJ6};
  for (uint8_t i = 0; i < 3; ++i) {
    io::write(s[i]->enable, true);  // disabled until set up
    io::output(s[i]->enable);
    io::output(s[i]->dir);
    io::output(s[i]->step.pin);
  }
  io::output(board::kTimingProbe);
  io::write(board::kStepperJ1.dir, true);   // J1 and J6 positive, J5 negative
  io::write(board::kStepperJ5.dir, false);
  io::write(board::kStepperJ6.dir, true);

  TCCR5A = 0;
  TCCR5B = 0;
  TCNT5 = 0;
  // force every OC5x low: COM = clear, then a forced compare
  for (uint8_t i = 0; i < 3; ++i) io::set_com(kTrains[i].pin, 2);
  TCCR5C = (1 << FOC5A) | (1 << FOC5B) | (1 << FOC5C);
  for (uint8_t i = 0; i < 3; ++i) {
    io::ocr(kTrains[i].pin) = kTrains[i].half_period;
    io::set_com(kTrains[i].pin, 1);  // toggle on compare
    io::write(s[i]->enable, false);
  }
  TIFR5 = 0xFF;
  TIMSK5 = (1 << OCIE5A) | (1 << OCIE5B) | (1 << OCIE5C);
  sei();
  TCCR5B = (1 << CS51);  // 2 MHz
  for (;;) {
    PORTL |= 1;  // D49: read-modify-write of the STEP pins' port
    PORTL &= (uint8_t)~1;
  }
}
