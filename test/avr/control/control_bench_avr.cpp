// Cycle cost of the control blocks' hot calls on the ATmega2560 (run by avr-run, which times
// the regions; region 1 is the empty region it subtracts).
#include "control/button.h"
#include "control/joystick.h"
#include "control/pid.h"
#include "control/plausibility.h"
#include "control/relay.h"
#include "control/seed0_stepper_controller.h"
#include "control/step_ramp.h"
#include "kinematics_vectors.h"
#include "probe.h"

using namespace wmra;
using namespace wmra::control;

namespace {

volatile uint32_t sink;
volatile int32_t input_speed = 20000;
// inputs go through volatile variables so that the compiler cannot move their computation
// (the LCG's modulo is a 32-bit division) into a timed region
volatile int32_t in_target, in_pos;
volatile uint16_t in_x, in_y;

enum Region : uint8_t {
  kEmpty = 1,
  kRampCruise,
  kRampAccel,
  kRampBrake,
  kRampSetSpeed,
  kSeed0,
  kPid,
  kRelay,
  kPlausibility,
  kJoystick,
  kButton,
};

StepRamp<2000000> ramp;
Seed0StepperController seed0;
Pid pid;
Relay relay;
PlausibilityMonitor monitor;
Joystick stick;
Button button;

}  // namespace

int main() {
  probe::name_region(kEmpty, "empty");
  probe::name_region(kRampCruise, "ramp_next_cruise");
  probe::name_region(kRampAccel, "ramp_next_accelerating");
  probe::name_region(kRampBrake, "ramp_next_braking");
  probe::name_region(kRampSetSpeed, "ramp_set_speed");
  probe::name_region(kSeed0, "seed0_update");
  probe::name_region(kPid, "pid_update");
  probe::name_region(kRelay, "relay_update");
  probe::name_region(kPlausibility, "plausibility_update");
  probe::name_region(kJoystick, "joystick_update");
  probe::name_region(kButton, "button_update");
  for (uint8_t i = 0; i < 16; ++i) {
    probe::start(kEmpty);
    probe::stop(kEmpty);
  }

  // step ramp, 2 MHz ticks, 50,000 steps/s^2, top speed 20 kHz: every step of a ramp from
  // rest to 20 kHz (4,000 levels: the table below 257, interpolation blocks above), cruise
  // steps, and every step of the braking back to rest
  ramp.configure({50000, 100});
  probe::start(kRampSetSpeed);
  ramp.set_speed(input_speed);
  probe::stop(kRampSetSpeed);
  uint32_t acc = 0;
  for (;;) {
    const uint32_t level = ramp.level();
    probe::start(kRampAccel);
    const StepRamp<2000000>::Step s = ramp.next();
    probe::stop(kRampAccel);
    acc += s.interval_ticks;
    if (ramp.level() == level) break;  // reached the speed
  }
  for (uint16_t i = 0; i < 500; ++i) {
    probe::start(kRampCruise);
    const StepRamp<2000000>::Step s = ramp.next();
    probe::stop(kRampCruise);
    acc += s.interval_ticks;
  }
  ramp.set_speed(0);
  for (;;) {
    probe::start(kRampBrake);
    const StepRamp<2000000>::Step s = ramp.next();
    probe::stop(kRampBrake);
    if (!s.interval_ticks) break;
    acc += s.interval_ticks;
  }
  for (uint8_t i = 0; i < 50; ++i) {
    probe::start(kRampSetSpeed);
    ramp.set_speed(input_speed - i * 397);
    probe::stop(kRampSetSpeed);
  }
  sink = acc;

  vectors::Lcg rng{99u};
  seed0.configure(Seed0Config{Seed0Variant::firmware, 13 * 256, 512, 50, 1000, 1, 10, 512, 25});
  pid.configure(PidConfig{{655, 105, 102}, 32767, 600, 2000, 50});
  relay.configure({38, 5, 20000});
  monitor.configure(PlausibilityConfig{29490, 250, 48, 100, 80, 48, 128, 16240, 5});
  stick.configure(JoystickConfig{1023, 8, 50, 16, 24, 100, 655, 9830, 33, 164, 100});
  button.configure({20, 1000});
  for (uint8_t i = 0; i < 120; ++i) stick.update(512, 510);  // calibrated and armed
  int32_t pos = 8000;
  for (uint16_t k = 0; k < 200; ++k) {
    in_target = rng.in_range(6000, 10000);
    pos += rng.in_range(-30, 30);
    in_pos = pos;
    in_x = (uint16_t)rng.in_range(100, 900);
    in_y = (uint16_t)rng.in_range(100, 900);
    const int32_t target = in_target;
    pos = in_pos;
    const uint16_t x = in_x, y = in_y;
    probe::start(kSeed0);
    int32_t v = seed0.update(target, pos);
    probe::stop(kSeed0);
    probe::start(kPid);
    const int16_t duty = pid.update(target, pos);
    probe::stop(kPid);
    probe::start(kRelay);
    v += relay.update(target, pos);
    probe::stop(kRelay);
    probe::start(kPlausibility);
    v += monitor.update(duty, pos);
    probe::stop(kPlausibility);
    probe::start(kJoystick);
    const JoystickOutput o = stick.update(x, y);
    probe::stop(kJoystick);
    probe::start(kButton);
    v += (int32_t)button.update((k / 40) & 1, (uint16_t)(k * 3));
    probe::stop(kButton);
    sink = (uint32_t)v + (uint32_t)o.x_q15;
  }
  probe::print("done\n");
  probe::finish();
}
