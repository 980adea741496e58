// BTS7960 PWM on the board's timer plan, the pots and the joystick through the ADC, a limit
// switch on PCINT0 and the safety button on INT4.
//   0..500 ms   J2 +50 % (OC4C), J3 -40 % (OC4B), J4 L OCR0B = 0 (a 1 % spike) and R 30 % (OC3A)
//   500 ms      all bridges off (compare outputs disconnected, ports low)
//   600 ms      averages of 16 conversions of A0..A4 on the console: "adc CH COUNTS"
//   750 ms      J2 +50 % again and the J1 driver enabled, until the safety button's interrupt
//               switches every output off
// The PCINT0 and INT4 handlers log their times (ms, from Timer1) on the console.
#include "board_io.h"

using namespace wmra;

namespace {

volatile uint16_t ms;
volatile uint16_t pcint_ms = 0xFFFF;
volatile uint8_t pcint_pinb;
volatile uint16_t estop_ms = 0xFFFF;

void bridges_off() {
  const board::BridgePins* b[3] = {&board::kBridgeJ2, &board::kBridgeJ3, &board::kBridgeJ4};
  for (uint8_t i = 0; i < 3; ++i) {
    io::set_com(b[i]->left, 0);
    io::set_com(b[i]->right, 0);
    io::write(b[i]->left.pin, false);
    io::write(b[i]->right.pin, false);
  }
}

uint16_t adc(uint8_t ch) {
  ADMUX = (uint8_t)((1 << REFS0) | ch);
  ADCSRA |= 1 << ADSC;
  while (ADCSRA & (1 << ADSC)) {
  }
  return ADC;
}

uint16_t now_ms() {
  cli();
  const uint16_t t = ms;  // two bytes: not torn by the tick
  sei();
  return t;
}

void wait_until(uint16_t t) {
  while ((int16_t)(now_ms() - t) < 0) {
  }
}

}  // namespace

ISR(TIMER1_COMPA_vect) { ms++; }
ISR(PCINT0_vect) {
  if (pcint_ms == 0xFFFF) {
    pcint_ms = ms;
    pcint_pinb = PINB;
  }
}
ISR(INT4_vect) {
  bridges_off();
  io::write(board::kStepperJ1.enable, true);
  if (estop_ms == 0xFFFF) estop_ms = ms;
}

int main() {
  // 1 kHz clock on Timer1 (CTC, /8, OCR1A = 1999)
  OCR1A = 1999;
  TCCR1B = (1 << WGM12) | (1 << CS11);
  TIMSK1 = 1 << OCIE1A;

  // the bridges' pins
  const board::BridgePins* b[3] = {&board::kBridgeJ2, &board::kBridgeJ3, &board::kBridgeJ4};
  for (uint8_t i = 0; i < 3; ++i) {
    io::output(b[i]->left.pin);
    io::output(b[i]->right.pin);
  }
  // Timers 3 and 4: fast PWM, TOP = ICR = 799, /1: 20 kHz
  ICR4 = 799;
  TCCR4A = 1 << WGM41;
  TCCR4B = (1 << WGM43) | (1 << WGM42) | (1 << CS40);
  ICR3 = 799;
  TCCR3A = 1 << WGM31;
  TCCR3B = (1 << WGM33) | (1 << WGM32) | (1 << CS30);
  // Timers 0 and 2: fast PWM, TOP = OCRnA = 99, /8: 20 kHz
  OCR0A = 99;
  TCCR0A = (1 << WGM01) | (1 << WGM00);
  TCCR0B = (1 << WGM02) | (1 << CS01);
  OCR2A = 99;
  TCCR2A = (1 << WGM21) | (1 << WGM20);
  TCCR2B = (1 << WGM22) | (1 << CS21);

  io::ocr(board::kBridgeJ2.left) = 399;  // (399 + 1) / 800 = 50 %
  io::set_com(board::kBridgeJ2.left, 2);
  io::ocr(board::kBridgeJ3.right) = 319;  // 40 %
  io::set_com(board::kBridgeJ3.right, 2);
  io::reg8(m2560::timer_registers(board::kBridgeJ4.left.timer).ocr[(int)board::kBridgeJ4.left.channel]) = 0;
  io::set_com(board::kBridgeJ4.left, 2);  // OCR = 0 in fast PWM: one count in 100
  io::ocr(board::kBridgeJ4.right) = 239;  // 30 %
  io::set_com(board::kBridgeJ4.right, 2);

  // J4's lower limit switch (PB4 = PCINT4) and the safety button (INT4, any change)
  io::input_pullup(board::kLimits[3].low);
  PCMSK0 = (uint8_t)(1 << board::kLimits[3].low.bit);
  PCICR = 1 << PCIE0;
  io::input_pullup(board::kSafetyButton);
  EICRB = 1 << ISC40;
  EIFR = 1 << INTF4;
  EIMSK = 1 << INT4;

  io::output(board::kStepperJ1.enable);
  io::write(board::kStepperJ1.enable, true);
  ADCSRA = (1 << ADEN) | 7;
  sei();

  wait_until(500);
  bridges_off();
  wait_until(600);
  for (uint8_t ch = 0; ch < 5; ++ch) {
    uint32_t sum = 0;
    for (uint8_t i = 0; i < 16; ++i) sum += adc(ch);
    probe::print("adc ");
    probe::print_uint(ch);
    probe::put(' ');
    probe::print_uint((sum + 8) / 16);
    probe::put('\n');
  }
  probe::print("pcint ");
  probe::print_uint(pcint_ms);
  probe::put(' ');
  probe::print_uint(pcint_pinb);
  probe::put('\n');

  wait_until(750);
  io::set_com(board::kBridgeJ2.left, 2);
  io::write(board::kStepperJ1.enable, false);
  while (true) {
    cli();
    const bool pressed = estop_ms != 0xFFFF;
    sei();
    if (pressed) break;
  }
  probe::print("estop ");
  probe::print_uint(estop_ms);
  probe::put('\n');
  for (;;) {
  }
}
