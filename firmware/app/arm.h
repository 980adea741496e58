// The arm's state that more than one of the loop's jobs reads or writes, in one place: the
// supervisor, the person's inputs, the joints' references, what the drives can do, the faults.
// Each job keeps what only it uses in its own file (dc_drives.cpp, motion.cpp, ...).
#pragma once

#include <stdint.h>

#include "app/arm_control.h"
#include "app/settings.h"
#include "control/button.h"
#include "control/joystick.h"
#include "core/faults.h"
#include "core/joint_map.h"
#include "core/resolved_rate.h"
#include "core/supervisor.h"

namespace wmra {
namespace app {

struct Arm {
  core::Supervisor supervisor;
  control::Joystick stick;
  control::Button button;
  // the joints' references (angles and speeds): the motion pass and the moves write them, the
  // drives follow them
  core::JointReferences q;
  // what each joint's drive can do now, each way: the DC joints' from the speed governor, the
  // steppers' from their limits and J1's stop (stepper_drives.cpp), none towards a closed switch
  core::DriveSpeeds drives;
  uint32_t faults;          // latched (core/faults.h bits) until a re-arm clears them
  bool homed;               // the steppers' counts are their joints' angles
  fx::Unit speed_scale;     // set_speed_scale()
  // J1's largest change of speed in a tick at this pose (stepper_drives::update_j1_stop): its lag
  // behind its field while it accelerates is part of its stop's travel (config/stop_config.h)
  fx::Real j1_max_change_per_tick;
  // and slowing down: the acceleration limit the pose's inertia allows (kJ1AccelMultiples)
  fx::Real j1_max_brake_per_tick;
  // J5's speeding up a lift of the wrist at this pose: the torque its motor has left beyond the
  // wrist's gravity (stepper_drives::update_wrist_load)
  fx::Real j5_max_change_per_tick;
  int8_t j5_lift_way;  // the way J5 turns to lift the wrist: +1, -1, or 0 (no gravity about it)
  Settings* settings;       // in RAM, saved to EEPROM on a change
  Status status;            // the report's; the motion pass leaves what slowed it there
  uint16_t overrun_ms;      // the loop overran: reported while > 0
};
extern Arm g_arm;

// the stick at a rail (unplugged, broken)
bool stick_invalid(const control::JoystickOutput& stick);
// running, with a move to a pose or a stream under way (or the stream's halt)
bool running_busy();
inline void raise_fault(uint8_t bit) { g_arm.faults |= core::fault_mask(bit); }

}  // namespace app
}  // namespace wmra
