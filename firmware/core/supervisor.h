// The arm's top-level states (docs/arm-guide.md, using the arm), as a pure state machine: inputs are
// what the drivers and the other blocks report each control tick, outputs say what may move.
//
//   boot -> wait_neutral -> wait_home -> homing -> to_ready -> running
//   any state -> stopped  while the safety button is pressed, or on a stop command (latched:
//                         re-arm after release)
//   any state -> fault    on a fault (latched: re-arm once the fault has cleared)
// Nothing moves until the person asks: after every reset the arm waits in wait_home,
// drives off, until a long press of the joystick button or a home command starts the homing.
// wait_home is entered only with the stick valid and neutral for kNeutralHold_ms and is left
// for wait_neutral as soon as it is not, so an ask counts only with the stick at rest: a long
// press or a home command in boot or wait_neutral (stick not yet calibrated, deflected, at a
// rail) starts nothing and is not remembered; the link refuses a home command there. A long
// press counts only where it began in wait_home, so with the stick neutral for the whole
// press: one begun with the stick deflected (let go before the press is long) or a button
// held since before the wait (stuck, or a hand resting on it at power-up) starts nothing until
// the button has been released in the wait and pressed again.
// Re-arming (a long press or the serial command) from stopped or fault goes back to
// wait_neutral, so nothing moves until the stick has been seen neutral again; from there the
// arm goes on only where its steppers are still homed (their counts are their angles: `homed`),
// making again a move to the ready pose that a stop cut short (the arm runs only from the
// ready pose's side of the singular home); otherwise it waits in wait_home for the
// person again: a re-arm never starts a homing.
// A home command in running stops the arm (drives off, wait_neutral) and homes it once the
// stick has been neutral; a stop or a fault before the homing begins drops that request. A
// short press in running cycles the modes of config::kModeCycle.
// A stick that is not valid (at a rail: unplugged or broken) counts as not neutral.
// A jog (bring-up: one joint turned while jog commands keep coming, core/jog.h) starts from
// wait_home or from running (the link accepts one only with the stick neutral and, in running,
// no move or stream under way); the drives are on meanwhile, and when the jog is over (no
// command for the stream's timeout, or the stick deflected, and the joint at rest) the arm goes
// back: to running where its steppers are homed, to wait_home otherwise.
//   wait_home -> jog -> wait_home        running -> jog -> running
#pragma once

#include <stdint.h>

#include "config/modes_config.h"

namespace wmra {
namespace core {

// The values are the state frame's (docs/telemetry.md): a new state takes the next number.
enum class ArmState : uint8_t { boot, wait_neutral, homing, to_ready, running, stopped, fault, wait_home, jog };
constexpr ArmState kLastArmState = ArmState::jog;

inline const char* to_string(ArmState s) {
  switch (s) {
    case ArmState::boot: return "boot";
    case ArmState::wait_neutral: return "wait_neutral";
    case ArmState::homing: return "homing";
    case ArmState::to_ready: return "to_ready";
    case ArmState::running: return "running";
    case ArmState::stopped: return "stopped";
    case ArmState::fault: return "fault";
    case ArmState::wait_home: return "wait_home";
    case ArmState::jog: return "jog";
  }
  return "?";
}

// A home command starts a homing in wait_home (whose stick is valid and neutral) and stops the
// arm to home it in running; the link refuses it in every other state, where it starts nothing
// (in homing and to_ready a homing is under way or just done: cutting their drives at speed to
// home again would let J1 coast).
inline bool accepts_home(ArmState s) { return s == ArmState::wait_home || s == ArmState::running; }

// what the rest of the firmware reports at one control tick
struct SupervisorInputs {
  bool safety_pressed;  // the safety button is pressed (or its wire broken)
  uint32_t faults;      // latched fault bits of the safety checks; 0 when clear
  bool stick_valid;     // both stick channels inside their rails
  bool stick_neutral;   // inside the centre dead zone
  bool short_press;     // one-tick events from the button logic
  bool long_press;      // held for kButtonLongPress_ms
  bool button_down;     // the button's debounced level
  bool rearm_command;  // from the serial link
  bool stop_command;
  bool home_command;
  bool homed;          // every stepper has found its switch and its count is still its angle
  bool at_ready;       // the move to the ready pose has arrived
  bool drives_at_rest;  // no stepper is still braking from a stop
  bool jog_command;     // the link accepted a jog command this tick
  bool jog_over;        // no jog command for the timeout (or the stick deflected), the joint at rest
};

class Supervisor {
 public:
  static constexpr uint16_t kNeutralHold_ms = 500;

  ArmState state() const { return state_; }
  config::Mode mode() const { return config::kModeCycle[mode_index_]; }
  // the joints may be driven (motor drivers enabled)
  bool drives_enabled() const {
    return state_ == ArmState::homing || state_ == ArmState::to_ready || state_ == ArmState::running || state_ == ArmState::jog;
  }
  // the stick may command the hand
  bool stick_enabled() const { return state_ == ArmState::running; }

  // a mode of the cycle, chosen directly (serial command); false if it is not in the cycle or
  // the arm is not running
  bool select_mode(config::Mode m) {
    if (state_ != ArmState::running) return false;
    for (uint8_t i = 0; i < config::kModeCount; ++i) {
      if (config::kModeCycle[i] == m) {
        mode_index_ = i;
        return true;
      }
    }
    return false;
  }

  // one control tick of dt_ms milliseconds
  void update(const SupervisorInputs& in, uint16_t dt_ms) {
    if (in.safety_pressed || in.stop_command) {
      state_ = ArmState::stopped;
      home_requested_ = false;
      return;
    }
    if (in.faults != 0 && state_ != ArmState::stopped) {
      state_ = ArmState::fault;
      home_requested_ = false;
      return;
    }
    const bool rearm = in.long_press || in.rearm_command;
    neutral_ms_ = in.stick_valid && in.stick_neutral ? saturating_add(neutral_ms_, dt_ms) : 0;
    switch (state_) {
      case ArmState::boot:
        state_ = ArmState::wait_neutral;
        break;
      case ArmState::wait_neutral:
        // (a stepper still braking from a stop: its count is not yet where it rests)
        if (neutral_ms_ >= kNeutralHold_ms && in.drives_at_rest) {
          state_ = home_requested_ ? ArmState::homing
                   : !in.homed     ? ArmState::wait_home
                   : reached_ready_ ? ArmState::running
                                    : ArmState::to_ready;
          home_requested_ = false;
          released_waiting_ = !in.button_down;
        }
        break;
      case ArmState::wait_home:
        if (neutral_ms_ < kNeutralHold_ms) {
          state_ = ArmState::wait_neutral;
        } else if ((in.long_press && released_waiting_) || in.home_command) {
          state_ = ArmState::homing;
        } else if (in.jog_command) {
          state_ = ArmState::jog;
        }
        released_waiting_ |= !in.button_down;
        break;
      case ArmState::jog:
        if (in.jog_over) state_ = in.homed ? ArmState::running : ArmState::wait_home;
        break;
      case ArmState::homing:
        if (in.homed) {
          state_ = ArmState::to_ready;
          reached_ready_ = false;
        }
        break;
      case ArmState::to_ready:
        if (in.at_ready) {
          state_ = ArmState::running;
          reached_ready_ = true;
        }
        break;
      case ArmState::running:
        if (in.home_command) {
          state_ = ArmState::wait_neutral;
          neutral_ms_ = 0;
          home_requested_ = true;
        } else if (in.jog_command) {
          state_ = ArmState::jog;
        } else if (in.short_press) {
          mode_index_ = (uint8_t)((mode_index_ + 1) % config::kModeCount);
        }
        break;
      case ArmState::stopped:
      case ArmState::fault:
        if (rearm && in.faults == 0) {
          state_ = ArmState::wait_neutral;
          neutral_ms_ = 0;
        }
        break;
    }
  }

 private:
  static uint16_t saturating_add(uint16_t a, uint16_t b) { return (uint16_t)(a > 0xFFFFu - b ? 0xFFFFu : a + b); }

  ArmState state_ = ArmState::boot;
  uint8_t mode_index_ = 0;
  uint16_t neutral_ms_ = 0;
  bool home_requested_ = false;  // a home command in running, until the homing begins or a stop
  bool released_waiting_ = false;  // the button was up at a tick of this wait_home: a press began in it
  bool reached_ready_ = false;  // the move to the ready pose after the last homing has arrived
};

}  // namespace core
}  // namespace wmra
