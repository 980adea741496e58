// The arm's controller board: an Arduino Mega 2560 wired as in Table 3.9 of seed 2.
//
// A portable description (no AVR registers), so that the firmware's drivers and the simulator
// read one pin map: each signal is a port letter and bit of the ATmega2560, plus, for the
// outputs that a timer drives, the timer and its compare channel. The drivers turn these into
// register accesses; the simulator into simavr IRQs. A second board is a second folder with
// the same names.
//
// Timer plan (one timer group per job, checked below):
//   Timer5  step generation: the three STEP pins are OC5A/B/C (normal mode, 250 kHz tick)
//   Timer4  BTS7960 PWM: J3 L (OC4A), J3 R (OC4B), J2 L (OC4C), 20 kHz
//   Timer3  BTS7960 PWM: J4 R (OC3A), 20 kHz
//   Timer2  BTS7960 PWM: J2 R (OC2B), 20 kHz (OCR2A is the TOP, so OC2A is not used)
//   Timer0  BTS7960 PWM: J4 L (OC0B), 20 kHz (OCR0A is the TOP, so OC0A is not used)
//   Timer1  the 1 kHz system tick (compare A), the ADC sweep's start at a phase of the tick
//           (compare B) and the gripper servo pulse on OC1C (D13), normal mode, 2 MHz
// The BTS7960 takes PWM up to 25 kHz; the 8-bit timers reach 20 kHz only with a TOP of 99,
// so the L/R sides of J2 and J4 have 100 duty steps on one side and 800 on the other.
#pragma once

#include <stdint.h>

namespace wmra {
namespace board {

enum class Port : uint8_t { A, B, C, D, E, F, G, H, J, K, L };

struct Pin {
  Port port;
  uint8_t bit;
  uint8_t arduino;  // the number printed on the Mega's header, for people wiring the arm
};

enum class Timer : uint8_t { t0, t1, t2, t3, t4, t5 };
enum class Channel : uint8_t { a, b, c };

// an output-compare pin: the pin is fixed by the chip once the timer and channel are chosen
struct ComparePin {
  Pin pin;
  Timer timer;
  Channel channel;
};

struct StepperPins {
  Pin enable;  // DRV8825 EN, active low
  Pin dir;
  ComparePin step;
};

struct BridgePins {  // BTS7960: PWM on one side drives, the other side is held at 0
  ComparePin left;
  ComparePin right;
};

struct LimitPins {
  Pin low;   // the switch at the joint's lower limit
  Pin high;  // the switch at the joint's upper limit (J6 has only its zero switch, in `low`)
  bool has_high;
};

constexpr uint8_t kJoints = 6;

// Steppers: J1, J5, J6 (joint index 0, 4, 5)
constexpr StepperPins kStepperJ1 = {{Port::C, 7, 30}, {Port::C, 5, 32}, {{Port::L, 4, 45}, Timer::t5, Channel::b}};
constexpr StepperPins kStepperJ5 = {{Port::A, 4, 26}, {Port::A, 6, 28}, {{Port::L, 5, 44}, Timer::t5, Channel::c}};
constexpr StepperPins kStepperJ6 = {{Port::A, 0, 22}, {Port::A, 2, 24}, {{Port::L, 3, 46}, Timer::t5, Channel::a}};

// DC joints: J2, J3, J4 (joint index 1, 2, 3)
constexpr BridgePins kBridgeJ2 = {{{Port::H, 5, 8}, Timer::t4, Channel::c}, {{Port::H, 6, 9}, Timer::t2, Channel::b}};
constexpr BridgePins kBridgeJ3 = {{{Port::H, 3, 6}, Timer::t4, Channel::a}, {{Port::H, 4, 7}, Timer::t4, Channel::b}};
constexpr BridgePins kBridgeJ4 = {{{Port::G, 5, 4}, Timer::t0, Channel::b}, {{Port::E, 3, 5}, Timer::t3, Channel::a}};

// ADC channels (A0..A7 are ADC0..7; simavr models only these)
constexpr uint8_t kAdcJoystickX = 1;
constexpr uint8_t kAdcJoystickY = 0;
constexpr uint8_t kAdcPotJ2 = 2;
constexpr uint8_t kAdcPotJ3 = 3;
constexpr uint8_t kAdcPotJ4 = 4;

// Limit switches, closed = pulled to ground (inputs with pull-ups). Port B pins are PCINT0..6;
// D18..D21 are INT3..INT0.
constexpr LimitPins kLimits[kJoints] = {
    {{Port::B, 5, 11}, {Port::B, 6, 12}, true},   // J1
    {{Port::D, 0, 21}, {Port::D, 1, 20}, true},   // J2
    {{Port::D, 2, 19}, {Port::D, 3, 18}, true},   // J3
    {{Port::B, 4, 10}, {Port::B, 3, 50}, true},   // J4
    {{Port::B, 2, 51}, {Port::B, 1, 52}, true},   // J5
    {{Port::B, 0, 53}, {Port::B, 0, 53}, false},  // J6: one zero switch
};

constexpr Pin kJoystickButton = {Port::E, 5, 3};  // INT5, closed = low
// INT4. A normally-closed button to ground with the pull-up on: low while closed, high when
// pressed or when its wire breaks, so a broken wire stops the arm as the button would.
constexpr Pin kSafetyButton = {Port::E, 4, 2};
constexpr ComparePin kGripperServo = {{Port::B, 7, 13}, Timer::t1, Channel::c};
constexpr Pin kTimingProbe = {Port::L, 0, 49};  // high for the whole of each control iteration

// UART0 (the USB serial of the Mega): telemetry and commands at 115200 baud
constexpr uint32_t kSerialBaud = 115200;
// The crystal: the one definition of the CPU clock (the toolchain's F_CPU, for avr-libc's
// delay and baud helpers, must agree)
constexpr uint32_t kCpuHz = 16000000;
#ifdef F_CPU
static_assert(F_CPU == kCpuHz, "F_CPU (toolchain/avr-gcc.cmake's AVR_F_CPU) is the board's clock");
#endif

// --- the timer plan, checked
constexpr bool same_pin(Pin a, Pin b) { return a.port == b.port && a.bit == b.bit; }
constexpr bool on(ComparePin p, Timer t) { return p.timer == t; }

static_assert(on(kStepperJ1.step, Timer::t5) && on(kStepperJ5.step, Timer::t5) && on(kStepperJ6.step, Timer::t5),
              "all STEP pins must be on Timer5: one timer group for step generation");
static_assert(kStepperJ1.step.channel != kStepperJ5.step.channel && kStepperJ1.step.channel != kStepperJ6.step.channel &&
                  kStepperJ5.step.channel != kStepperJ6.step.channel,
              "each stepper needs its own Timer5 compare channel");
constexpr bool bridge_timer(ComparePin p) {
  return p.timer == Timer::t0 || p.timer == Timer::t2 || p.timer == Timer::t3 || p.timer == Timer::t4;
}
static_assert(bridge_timer(kBridgeJ2.left) && bridge_timer(kBridgeJ2.right) && bridge_timer(kBridgeJ3.left) &&
                  bridge_timer(kBridgeJ3.right) && bridge_timer(kBridgeJ4.left) && bridge_timer(kBridgeJ4.right),
              "BTS7960 PWM only on Timers 0, 2, 3 and 4: Timer5 steps, Timer1 ticks");
// The 8-bit timers use OCRnA as their TOP for 20 kHz, so only their B channel can be a PWM output.
constexpr bool usable_pwm(ComparePin p) {
  return !((p.timer == Timer::t0 || p.timer == Timer::t2) && p.channel == Channel::a);
}
static_assert(usable_pwm(kBridgeJ2.left) && usable_pwm(kBridgeJ2.right) && usable_pwm(kBridgeJ3.left) &&
                  usable_pwm(kBridgeJ3.right) && usable_pwm(kBridgeJ4.left) && usable_pwm(kBridgeJ4.right),
              "channel A of Timers 0 and 2 is their TOP register, not a PWM output");
static_assert(on(kGripperServo, Timer::t1), "the gripper servo shares Timer1 with the system tick");
static_assert(!same_pin(kSafetyButton, kJoystickButton), "two buttons on one pin");
// every digital pin above once, each a bit of its port (a J6 without a high switch has none)
constexpr Pin kDigitalPins[] = {
    kStepperJ1.enable,      kStepperJ1.dir,          kStepperJ1.step.pin,     kStepperJ5.enable,       kStepperJ5.dir,
    kStepperJ5.step.pin,    kStepperJ6.enable,       kStepperJ6.dir,          kStepperJ6.step.pin,     kBridgeJ2.left.pin,
    kBridgeJ2.right.pin,    kBridgeJ3.left.pin,      kBridgeJ3.right.pin,     kBridgeJ4.left.pin,      kBridgeJ4.right.pin,
    kLimits[0].low,         kLimits[0].high,         kLimits[1].low,          kLimits[1].high,         kLimits[2].low,
    kLimits[2].high,        kLimits[3].low,          kLimits[3].high,         kLimits[4].low,          kLimits[4].high,
    kLimits[5].low,         kLimits[5].high,         kJoystickButton,         kSafetyButton,           kGripperServo.pin,
    kTimingProbe};
constexpr uint8_t kFirstLimitPin = 15;  // kLimits' pins in kDigitalPins, low and high per joint
constexpr bool unused_pin(uint8_t i) {
  return i >= kFirstLimitPin && i < kFirstLimitPin + 2 * kJoints && (i - kFirstLimitPin) % 2 == 1 &&
         !kLimits[(i - kFirstLimitPin) / 2].has_high;
}
constexpr bool pins_distinct() {
  for (uint8_t i = 0; i < sizeof kDigitalPins / sizeof kDigitalPins[0]; ++i) {
    if (unused_pin(i)) continue;
    if (kDigitalPins[i].bit > 7) return false;
    for (uint8_t k = 0; k < i; ++k)
      if (!unused_pin(k) && same_pin(kDigitalPins[i], kDigitalPins[k])) return false;
  }
  return true;
}
static_assert(pins_distinct(), "board pins: each pin (port and bit 0..7) used by one signal only");
static_assert(kAdcJoystickX != kAdcJoystickY && kAdcPotJ2 != kAdcPotJ3 && kAdcPotJ2 != kAdcPotJ4 && kAdcPotJ3 != kAdcPotJ4 &&
                  kAdcJoystickX != kAdcPotJ2 && kAdcJoystickX != kAdcPotJ3 && kAdcJoystickX != kAdcPotJ4 &&
                  kAdcJoystickY != kAdcPotJ2 && kAdcJoystickY != kAdcPotJ3 && kAdcJoystickY != kAdcPotJ4,
              "board analog inputs: each channel read for one signal only");
static_assert(kAdcJoystickX < 8 && kAdcJoystickY < 8 && kAdcPotJ2 < 8 && kAdcPotJ3 < 8 && kAdcPotJ4 < 8,
              "analog inputs on A0..A7 (one ADC mux bank, and what simavr models)");

}  // namespace board
}  // namespace wmra
