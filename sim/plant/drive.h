// The mechanics shared by every joint drive: one rotating coordinate (the motor side of the
// joint's gear) with inertia, stiction, Coulomb and viscous friction, an external load that a
// self-locking gear never lets drive the motor, and hard stops.
#pragma once

namespace wmra {
namespace plant {

struct DriveFriction {
  double static_nm = 0;   // breakaway: the drive stays at rest while |net torque| is below it
  double coulomb_nm = 0;  // while moving
  double viscous_nm_per_rad_s = 0;
};

struct DriveState {
  double angle_rad = 0;  // motor side
  double speed_rad_s = 0;
};

// One step of length dt.
//   motor_nm: torque the motor applies; load_nm: torque the load applies (e.g. gravity through
//   the gear), both on the same coordinate.
//   self_locking: the gear cannot be back-driven: a load that pushes the drive the way it is
//   going (or the way the motor pushes it) does nothing; one that opposes it is felt in full;
//   unpowered, the drive holds.
//   overrun_inertia_kgm2: the part of the inertia (the load's) that a self-locking gear stops
//   with the motor: when the drive slows down, the load cannot drive the gear, so only the rest
//   of the inertia carries the motion on.
//   stop_low/stop_high: hard stops on angle_rad (the drive stops dead there).
// Returns true when the drive is against a hard stop.
bool drive_step(DriveState& s, double inertia_kgm2, const DriveFriction& f, double motor_nm, double load_nm,
                bool self_locking, double stop_low_rad, double stop_high_rad, double dt,
                double overrun_inertia_kgm2 = 0);

}  // namespace plant
}  // namespace wmra
