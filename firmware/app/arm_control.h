// The arm's control as the rest of the firmware sees it: start(), one iteration per 1 kHz tick
// (iterate, arm_control.cpp), the stop hooks, the report and the link's commands. The data path,
// file by file: the stick and the pots (arm_control.cpp, the inputs) -> the twist, J^-1 and the
// limits (motion.cpp) or a move to a pose (joint_moves.cpp) or homing (homing.cpp) -> the joints'
// references (arm.h) -> the DC servos (dc_drives.cpp) and the stepper ramps (stepper_drives.cpp)
// -> the pins (lib/drivers). Which job runs in which tick: tick_plan.h. Everything that decides is
// in firmware/core and lib/ (host-tested); the app wires it to the drivers. The serial link
// (link.h) reads the report and sends requests through Requests.
#pragma once

#include <stdint.h>

#include "core/supervisor.h"
#include "kinematics/fixed_point.h"
#include "kinematics/fixed_trig.h"
#include "kinematics/forward_kinematics.h"
#include "protocol/messages.h"

namespace wmra {
namespace app {

struct Settings;

// requests from the serial link, taken by the next iteration
struct Requests {
  bool stop, rearm, home;
  int8_t goto_slot;  // -1: none
  bool velocity_fresh;
  bool stream_taken_over;  // set by the iteration: a deflected stick took the stream over (link.cpp)
  int16_t v_mm_s[3];
  int16_t w_mrad_s[3];
  // the jog (core/jog.h): its joint (1..6) and speed, kept from its last command; fresh while
  // its commands keep coming (each within the stream's timeout); new, the tick one was accepted
  uint8_t jog_joint;
  int16_t jog_mrad_s;
  bool jog_fresh, jog_new;
};

// What a command's checks read of the arm: status()'s flags, without the joints' angles and the
// hand's FK (~2,500 cycles), so that a command costs little more than its reply
struct Condition {
  core::ArmState state;
  uint32_t faults;
  uint16_t switches;
  int16_t stick_q15[2];
  bool busy;  // running, a move to a pose or a stream is under way (or the stream's halt)
};

// what telemetry reports
struct Status {
  core::ArmState state;
  config::Mode mode;
  uint32_t faults;
  uint8_t slowed_by;
  uint16_t switches;
  fx::Angle q_measured[6];
  fx::Real qd_rad_s[6];
  // the hand (frame-6 origin) from the references' FK, base frame: while the stick drives the
  // drift correction's (computed at most kHandPositionAge_ms before), otherwise status()'s own
  kin::Vec3<fx::Real> p_m;
  int16_t stick_q15[2];
  uint8_t speed_scale_pct;
};

// The drift correction's FK runs every eighth iteration; an iteration that overran counts a tick
// more. Its position is reported while younger than this (the state frame took ~1,200 cycles for
// its own trig and FK, after an iteration that may have left it none): at the hand's top speed
// 0.15 m/s it is at most 1.2 mm behind the frame's angles (2.4 after an overrun).
constexpr uint8_t kHandPositionAge_ms = 16;

// The limit switches armed while the arm runs or moves to a pose (bits as inputs.h's: 2j the
// low end's, 2j+1 the high end's); J6's zero switch is passed in normal motion.
constexpr uint16_t kSwitchesArmed = 0x3FF;

// j6_at_rest: J6's angle recorded in EEPROM (wrist_angle.h), nullptr when none is
void start(Settings& settings, const fx::Angle* j6_at_rest);
// one control iteration; `ticks` control ticks (1 ms) passed since the last one (more than one:
// the loop overran, and the references advance by the time that passed)
void iterate(Requests& requests, uint8_t ticks);
void stop_from_interrupt();  // the stop hook of the safety button and the limit switches: the arm held
void outputs_off();          // a hang's (watchdog.h): every output off, the steppers' drivers too
const Status& status();
Condition condition();
bool select_mode(config::Mode m);
void set_speed_scale(uint8_t percent);
bool store_pose(uint8_t slot);
bool pose_valid(uint8_t slot);
enum class CalibrationChange : uint8_t { ok, refused, bad_argument };
// joint 2..4: its pot counts x 16 at its limits, or both 0 for joints_config.h's (settings.h)
CalibrationChange calibrate_pot(uint8_t joint, int16_t at_min_counts_x16, int16_t at_max_counts_x16);
protocol::CalibrationMsg calibration();
// store: the stick's calibrated centre becomes the one every power-up's must agree with
// (refused unless the stick is calibrated, armed and reads neutral, and the centre within
// kStickCentreTolerance_counts of mid-scale); otherwise the stored centre is forgotten
bool store_stick_centre(bool store);

}  // namespace app
}  // namespace wmra
