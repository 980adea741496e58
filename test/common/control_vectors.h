// Deterministic scenarios for every firmware-side block of lib/control, and the text form of
// their outputs. Compiled into an AVR image and into a host test, which compare the text byte
// for byte: the integer code must give the same results on the ATmega2560 and on the host.
#pragma once

#include <stdint.h>

#include "control/button.h"
#include "control/joystick.h"
#include "control/pid.h"
#include "control/plausibility.h"
#include "control/relay.h"
#include "control/seed0_stepper_controller.h"
#include "control/step_ramp.h"
#include "kinematics_vectors.h"

namespace wmra {
namespace control_vectors {

using vectors::Lcg;
using vectors::hex;

// FNV-1a over the bytes of a stream of values: one line per batch keeps the console short
struct Hash {
  uint32_t h = 2166136261u;
  void add(uint32_t v) {
    for (uint8_t i = 0; i < 4; ++i) {
      h ^= (uint8_t)(v >> (8 * i));
      h *= 16777619u;
    }
  }
};

template <class Put>
void line(Put& put, char tag, uint32_t a, uint32_t b, uint32_t c) {
  put(tag);
  hex(put, a, 8);
  put(' ');
  hex(put, b, 8);
  put(' ');
  hex(put, c, 8);
  put('\n');
}

// Step ramp: random speed commands and moves, 12 batches of 3000 steps
template <class Put>
void emit_ramp(Put& put) {
  control::StepRamp<2000000> r;
  r.configure({50000, 100});
  Lcg rng{11u};
  for (uint8_t batch = 0; batch < 12; ++batch) {
    if (batch % 4 == 3) {
      r.move_to(rng.in_range(-20000, 20000), (uint32_t)rng.in_range(100, 20000));
    } else {
      r.set_speed(rng.in_range(-21000, 21000));
    }
    Hash h;
    for (uint16_t i = 0; i < 3000; ++i) {  // up to level 3000: table and interpolation blocks
      const control::StepRamp<2000000>::Step s = r.next();
      h.add(s.interval_ticks);
      h.add((uint32_t)(int32_t)s.dir);
      h.add(r.last_interval_q16());
    }
    line(put, 'R', h.h, (uint32_t)r.position_steps(), r.level());
  }
  line(put, 'T', r.interval_at_level(300), r.interval_at_level(70000), control::StepRamp<2000000>::interval_for_speed_unclamped(12345));
}

template <class Put>
void emit_seed0(Put& put) {
  for (uint8_t variant = 0; variant < 2; ++variant) {
    control::Seed0StepperController c;
    c.configure(control::Seed0Config{variant ? control::Seed0Variant::firmware : control::Seed0Variant::thesis, 13 * 256,
                                     512, 50, 1000, 1, 10, 512, 25});
    Lcg rng{22u + variant};
    Hash h;
    int32_t target = 0, pos = 0;
    for (uint16_t k = 0; k < 600; ++k) {
      if (k % 50 == 0) target = rng.in_range(-4000, 4000);
      const int32_t v = c.update(target, pos);
      pos += v / 100 + rng.in_range(-1, 1);
      h.add((uint32_t)v);
    }
    line(put, 'S', h.h, (uint32_t)pos, (uint32_t)c.last_command());
  }
}

template <class Put>
void emit_pid_relay(Put& put) {
  control::Pid pid;
  pid.configure(control::PidConfig{{655, 105, 102}, 32767, 600, 2000, 50});
  control::Relay relay;
  relay.configure({38, 5, 20000});
  Lcg rng{33u};
  Hash hp, hr;
  int32_t sp = 8000, m = 8000;
  pid.start(sp, m, 0);
  for (uint16_t k = 0; k < 2000; ++k) {
    if (k % 97 == 0) sp = rng.in_range(0, 16368);
    m += rng.in_range(-40, 40);
    if (k % 331 == 0) m = rng.in_range(-32767, 32767);  // garbage readings too: anywhere in the positions' int16
    m = m < -32767 ? -32767 : m > 32767 ? 32767 : m;
    hp.add((uint32_t)pid.update(sp, m));
    hp.add((uint32_t)pid.integral_q23());
    hr.add((uint32_t)relay.update(sp, m));
  }
  line(put, 'P', hp.h, hr.h, (uint32_t)pid.effort_q15());
}

template <class Put>
void emit_plausibility(Put& put) {
  control::PlausibilityMonitor m;
  m.configure(control::PlausibilityConfig{29490, 250, 48, 100, 80, 48, 128, 16240, 5});
  Lcg rng{44u};
  Hash h;
  int32_t pos = 8000;
  for (uint16_t k = 0; k < 3000; ++k) {
    const int16_t duty = (int16_t)rng.in_range(-32767, 32767);
    pos += rng.in_range(-20, 20);
    if (k == 1500) pos = 20000;  // a rail
    if (k == 1600) pos = 8000;
    if (k % 1000 == 999) m.reset(pos);
    h.add(m.update(duty, pos));
  }
  line(put, 'L', h.h, (uint32_t)pos, m.faults());
}

template <class Put>
void emit_joystick_button(Put& put) {
  control::Joystick j;
  j.configure(control::JoystickConfig{1023, 8, 50, 16, 24, 100, 655, 9830, 33, 164, 100});
  control::Button b;
  b.configure({20, 1000});
  Lcg rng{55u};
  Hash hj, hb;
  uint16_t x = 512, y = 500;
  for (uint16_t k = 0; k < 6000; ++k) {
    if (k > 200 && k % 400 == 0) {
      x = (uint16_t)rng.in_range(0, 1023);
      y = (uint16_t)rng.in_range(0, 1023);
    }
    if (k % 400 == 200) x = y = 511;
    const uint16_t nx = (uint16_t)(x + rng.in_range(-2, 2)), ny = (uint16_t)(y + rng.in_range(-2, 2));
    const control::JoystickOutput o = j.update(nx > 1023 ? 1023 : nx, ny > 1023 ? 1023 : ny);
    hj.add((uint32_t)o.x_q15);
    hj.add((uint32_t)o.y_q15);
    hj.add(o.status);
    const bool level = (k / 300) % 2 ? (k % 7 != 0) : (k % 97 < 40);
    hb.add((uint32_t)b.update(level, (uint16_t)(k * 3 + 65000)));
  }
  // a stick whose travel ends before the rails, held at full deflection: the output saturates
  // at 32767 and the rate limit must not wrap past it (int is 16 bits on the AVR)
  control::Joystick full;
  full.configure(control::JoystickConfig{1023, 20, 5, 16, 12, 60, 655, 9830, 109, 218, 300, 440});
  for (uint16_t k = 0; k < 3000; ++k) {
    const uint16_t phase = k / 500;
    const uint16_t at = phase == 0 ? 512 : phase % 2 ? 975 : 45;
    const control::JoystickOutput o = full.update((uint16_t)(at + rng.in_range(-2, 2)), (uint16_t)(1023 - at));
    hj.add((uint32_t)o.x_q15);
    hj.add((uint32_t)o.y_q15);
  }
  line(put, 'J', hj.h, hb.h, (uint32_t)j.centre(0) << 16 | j.centre(1));
}

template <class Put>
void emit_all(Put& put) {
  emit_ramp(put);
  emit_seed0(put);
  emit_pid_relay(put);
  emit_plausibility(put);
  emit_joystick_button(put);
  put('E');
  put('N');
  put('D');
  put('\n');
}

}  // namespace control_vectors
}  // namespace wmra
