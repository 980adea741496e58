// A hybrid stepper and its load on the motor shaft, driven one step at a time by an indexer,
// for any step size (full, half or micro steps): the load-angle model of sim/plant's
// StepperJoint, which is fixed at the arm's 1/32 microstep, with the step size and the motor as
// parameters (seed 0 half-steps an AK85H). To be unified with it.
//
// Model. The indexer's field points at the commanded angle theta_c (steps x step angle). The
// rotor feels the pull of the field, T = T_po(omega) sin(N_r (theta_c - theta)) (N_r teeth,
// so the electrical angle is N_r theta), plus the drive's damping on its speed against the step
// train's rate (one step over the time since the step before: sim/plant smooths the field's
// 1/32-microstep staircase over 2 ms instead, which at half steps would leave a ripple that
// saturates the torque), within the pull-out torque T_po(omega): the holding torque up to a corner speed,
// T_hold omega_c / omega above it (a supply that can no longer push the rated current). Detent
// torque -T_d sin(4 N_r theta) (a well every full step); viscous friction on the shaft;
// J theta'' = sum. As long as the needed torque (J alpha + friction) stays below the pull-out
// torque, the rotor trails the field by a load angle below 90 electrical degrees and follows
// every step; when the step train asks more (too fast, or speeding up too hard) the lag grows
// past 180 degrees and the rotor falls into the next well: one electrical period, i.e. 4 full
// steps, is lost. Lost steps are counted each time that happens (with hysteresis: the rotor
// must be 1.2 pi past its well).
#pragma once

#include <cstdint>

#include "plant/drive.h"

namespace wmra {
namespace jointsim {

struct StepperRotorParams {
  double holding_torque_nm;
  double detent_torque_nm;
  double corner_speed_rad_s;        // pull-out torque is the holding torque up to here
  double inertia_kgm2;              // rotor and load at the motor shaft
  double viscous_nm_per_rad_s;      // at the motor shaft
  double damping_ratio;             // of the drive's damping on the swing about the field
  int rotor_teeth;                  // N_r (50 for 1.8 deg)
  int steps_per_electrical_period;  // 4 full steps, 8 half steps, 4 x microsteps
};

class StepperRotor {
 public:
  explicit StepperRotor(const StepperRotorParams& p);

  void step(int direction);  // one step of the indexer, +1 or -1 (the field jumps at once)
  void advance(double dt);   // integrate the rotor over dt (a few tens of us at most)

  double angle_rad() const { return s_.angle_rad; }  // from the power-up detent
  double speed_rad_s() const { return s_.speed_rad_s; }
  double angle_steps() const { return s_.angle_rad / step_rad_; }
  double commanded_rad() const { return commanded_ * step_rad_; }
  int64_t steps_commanded() const { return commanded_; }
  int64_t steps_lost() const { return lost_; }
  double pull_out_torque_nm() const;  // at the present speed
  double step_rad() const { return step_rad_; }

 private:
  StepperRotorParams p_;
  double step_rad_;
  double stiffness_nm_per_rad_;  // T_hold N_r: the field's spring near its well
  plant::DriveState s_;
  int64_t commanded_ = 0;
  int64_t lost_ = 0;
  int64_t well_ = 0;  // electrical periods the rotor trails the field by
  // the step train, for the drive's damping
  double t_s_ = 0;
  double last_step_s_ = 0;
  double last_interval_s_ = 0;
  double train_rad_s_ = 0;
  int8_t last_dir_ = 1;
  bool has_stepped_ = false;
};

}  // namespace jointsim
}  // namespace wmra
