// The output-compare pins decoded from the timer registers, against the ATmega2560 datasheet.
#include <gtest/gtest.h>

#include "wiring/timer_decode.h"

using namespace wmra;
using m2560::PinDrive;
using m2560::TimerSnapshot;
using Source = PinDrive::Source;
using board::Channel;

namespace {
TimerSnapshot eight_bit(uint8_t tccra, uint8_t tccrb, uint8_t ocra, uint8_t ocrb) {
  TimerSnapshot t;
  t.tccra = tccra;
  t.tccrb = tccrb;
  t.ocr[0] = ocra;
  t.ocr[1] = ocrb;
  return t;
}
TimerSnapshot sixteen_bit(uint8_t tccra, uint8_t tccrb, uint16_t icr, uint16_t a, uint16_t b, uint16_t c) {
  TimerSnapshot t;
  t.tccra = tccra;
  t.tccrb = tccrb;
  t.icr = icr;
  t.ocr[0] = a;
  t.ocr[1] = b;
  t.ocr[2] = c;
  t.sixteen_bit = true;
  return t;
}
}  // namespace

TEST(TimerDecode, EightBitFastPwmWithOcraTop) {
  // WGM 7, /8, COM0B = 2: the board's 20 kHz on Timers 0 and 2 (TOP = 99)
  auto t = eight_bit(0x23, 0x0A, 99, 24);
  PinDrive d = m2560::compare_pin_drive(t, Channel::b);
  EXPECT_EQ(d.source, Source::pwm);
  EXPECT_DOUBLE_EQ(d.duty, 0.25);
  t.ocr[1] = 0;  // a one-count spike, not zero
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::b).duty, 0.01);
  t.ocr[1] = 99;  // OCR = TOP: constantly high
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::b).duty, 1.0);
  t.ocr[1] = 150;  // beyond TOP: never cleared
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::b).duty, 1.0);
  t.tccra = 0x33;  // COM0B = 3: inverting
  t.ocr[1] = 24;
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::b).duty, 0.75);
  t.tccra = 0x03;  // COM0B = 0: the port
  EXPECT_EQ(m2560::compare_pin_drive(t, Channel::b).source, Source::port);
  t.tccra = 0x13;  // COM0B = 1 in fast PWM: reserved, the port
  EXPECT_EQ(m2560::compare_pin_drive(t, Channel::b).source, Source::port);
}

TEST(TimerDecode, SixteenBitFastPwmWithIcrTop) {
  // WGM 14, /1, ICR = 799: the board's 20 kHz on Timers 3 and 4
  const auto t = sixteen_bit(0xAA, 0x19, 799, 399, 0, 799);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::a).duty, 0.5);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::b).duty, 1.0 / 800);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::c).duty, 1.0);
  EXPECT_EQ(m2560::timer_mode(t).top, 799);
}

TEST(TimerDecode, PhaseCorrectPwm) {
  // WGM 10 (phase correct, TOP = ICR), COM = 2: OCR / TOP, 0 is really 0
  const auto t = sixteen_bit(0xA2, 0x11, 400, 100, 0, 0);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::a).duty, 0.25);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(t, Channel::b).duty, 0.0);
  // 8-bit WGM 5 (phase correct, TOP = OCRA): channel B
  const auto e = eight_bit(0x21, 0x09, 200, 50);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(e, Channel::b).duty, 0.25);
}

TEST(TimerDecode, NonPwmModesFollowTheCompareEvents) {
  // Timer5 in normal mode, toggle on compare: the step pins
  const auto t = sixteen_bit(0x54, 0x02, 0, 100, 200, 300);
  EXPECT_EQ(m2560::timer_mode(t).wave, m2560::Wave::normal);
  for (Channel c : {Channel::a, Channel::b, Channel::c}) EXPECT_EQ(m2560::compare_pin_drive(t, c).source, Source::events);
  // a PWM mode with the clock stopped keeps its output: follow the events too
  const auto stopped = sixteen_bit(0xAA, 0x18, 799, 399, 0, 0);
  EXPECT_EQ(m2560::compare_pin_drive(stopped, Channel::a).source, Source::events);
  // COM = 1 toggles OCnA in fast PWM with TOP = OCRnA: a 50 % square wave
  const auto toggle = sixteen_bit(0x43, 0x19, 0, 999, 0, 0);
  EXPECT_DOUBLE_EQ(m2560::compare_pin_drive(toggle, Channel::a).duty, 0.5);
}
