// The arm's top-level states (SPEC sections 5 and 6), as a pure state machine: inputs are
// what the drivers and the other blocks report each control tick, outputs say what may move.
//
//   boot -> wait_neutral -> homing -> to_ready -> running
//   any state -> stopped  while the safety button is pressed, or on a stop command (latched:
//                         re-arm after release)
//   any state -> fault    on a fault (latched: re-arm once the fault has cleared)
// Re-arming (a long press or the serial command) from stopped or fault goes back to
// wait_neutral, so nothing moves until the stick has been seen neutral again; from there the
// steppers are homed again unless `homed` still holds (the firmware drops it when a stepper
// was turning as its driver went off: it coasted, and its step count is no longer its angle),
// and a move to the ready pose that a stop cut short is made again: the arm runs only from the
// ready pose's side of the singular home (SPEC 5). A short press in running cycles the modes of
// config::kModeCycle.
// A home command forgets the homing and, from running, goes back through wait_neutral.
// The stick must be neutral for kNeutralHold_ms before any motion is enabled; a stick that
// is not valid (at a rail: unplugged or broken) counts as not neutral.
#pragma once

#include <stdint.h>

#include "config/modes_config.h"

namespace wmra {
namespace core {

enum class ArmState : uint8_t { boot, wait_neutral, homing, to_ready, running, stopped, fault };

inline const char* to_string(ArmState s) {
  switch (s) {
    case ArmState::boot: return "boot";
    case ArmState::wait_neutral: return "wait_neutral";
    case ArmState::homing: return "homing";
    case ArmState::to_ready: return "to_ready";
    case ArmState::running: return "running";
    case ArmState::stopped: return "stopped";
    case ArmState::fault: return "fault";
  }
  return "?";
}

// what the rest of the firmware reports at one control tick
struct SupervisorInputs {
  bool safety_pressed;  // the safety button is pressed (or its wire broken)
  uint32_t faults;      // latched fault bits of the safety checks; 0 when clear
  bool stick_valid;     // both stick channels inside their rails
  bool stick_neutral;   // inside the centre dead zone
  bool short_press;     // one-tick events from the button logic
  bool long_press;
  bool rearm_command;  // from the serial link
  bool stop_command;
  bool home_command;
  bool homed;          // every stepper has found its switch
  bool at_ready;       // the move to the ready pose has arrived
  bool drives_at_rest;  // no stepper is still braking from a stop
};

class Supervisor {
 public:
  static constexpr uint16_t kNeutralHold_ms = 500;

  ArmState state() const { return state_; }
  config::Mode mode() const { return config::kModeCycle[mode_index_]; }
  // the joints may be driven (motor drivers enabled)
  bool drives_enabled() const {
    return state_ == ArmState::homing || state_ == ArmState::to_ready || state_ == ArmState::running;
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
    // (not during the move to the ready pose, just homed, which the link refuses it in: kept
    // as a flag, it homed the arm at some later re-arm, where the person expected it to stay)
    if (in.home_command && state_ != ArmState::to_ready) homed_ = false;
    if (in.safety_pressed || in.stop_command) {
      state_ = ArmState::stopped;
      return;
    }
    if (in.faults != 0 && state_ != ArmState::stopped) {
      state_ = ArmState::fault;
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
          state_ = !(in.homed && homed_) ? ArmState::homing : reached_ready_ ? ArmState::running : ArmState::to_ready;
        }
        break;
      case ArmState::homing:
        if (in.homed) {
          state_ = ArmState::to_ready;
          homed_ = true;
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
  bool homed_ = true;  // false after a home command, until homing has finished again
  bool reached_ready_ = false;  // the move to the ready pose after the last homing has arrived
};

}  // namespace core
}  // namespace wmra
