// The joint drives: a DC joint (BTS7960 bridge, Mabuchi 578VA with its worm, the joint gear) and
// a stepper joint (DRV8825 at 1/32 microstep driving a hybrid stepper through the joint gear).
// Both are integrated on their motor side with drive_step (drive.h); angles here are joint
// angles in rad unless a name says motor.
#pragma once

#include <cstdint>
#include <limits>

#include "arm_plant_config.h"
#include "drive.h"

namespace wmra {
namespace plant {

// BTS7960: two half bridges; PWM on one input drives, the other input at 0 holds its side low.
// Averaged over a PWM period the motor sees 12 V x (duty_left - duty_right); both at 0 shorts
// the motor through the low sides (it brakes).
inline double bts7960_voltage(double duty_left, double duty_right, double supply_v = kBatteryV) {
  auto clamp01 = [](double d) { return d < 0 ? 0.0 : d > 1 ? 1.0 : d; };
  return supply_v * (clamp01(duty_left) - clamp01(duty_right));
}

class DcJoint {
 public:
  DcJoint(double gear_ratio, double q_min_rad, double q_max_rad, bool self_locking);

  void set_angle(double q_rad);
  void set_voltage(double v) { voltage_v_ = v; }
  // one step with the arm's inertia and the gravity torque about this joint (at the joint)
  void step(double dt, double link_inertia_kgm2, double load_torque_nm);

  double q() const { return s_.angle_rad / gear_; }
  double qd() const { return s_.speed_rad_s / gear_; }
  double voltage() const { return voltage_v_; }
  // torque of the motor-and-worm assembly at its output shaft, and the motor current
  double motor_torque_nm() const;
  double current_a() const;
  bool against_stop() const { return against_stop_; }

 private:
  double gear_;
  double stop_low_, stop_high_;  // at the assembly output
  bool self_locking_;
  DriveState s_;
  double voltage_v_ = 0;
  bool against_stop_ = false;
};

class StepperJoint {
 public:
  StepperJoint(const StepperMotorData& motor, double gear_ratio, double q_min_rad, double q_max_rad, bool hard_stops,
               bool self_locking);

  void set_angle(double q_rad);  // power-up: the rotor rests where the indexer points
  void set_enabled(bool on) { enabled_ = on; }
  // one microstep from the driver's indexer, +1 or -1
  void microstep(int direction);
  // An outside torque (a knock on the hand) turns the rotor through whole electrical periods (4
  // full steps each, signed): the drive holds it in the new well, and its steps are lost.
  void slip(int periods) { s_.angle_rad += periods * 2.0 * kPi / kRotorPolePairs; }
  void step(double dt, double link_inertia_kgm2, double load_torque_nm);

  double q() const { return s_.angle_rad / gear_; }
  double qd() const { return s_.speed_rad_s / gear_; }
  bool enabled() const { return enabled_; }
  // the angle the indexer commands, at the joint
  double q_commanded() const { return commanded_motor_rad() / gear_; }
  int64_t microsteps_commanded() const { return commanded_; }
  // microsteps lost: each slip of the rotor by one electrical period loses 4 full steps
  int64_t microsteps_lost() const { return lost_; }
  // signed: where the rotor's well is against the indexer, in microsteps (+ = rotor ahead)
  int64_t microsteps_slipped() const { return -well_ * kMicrostepsPerElectricalPeriod; }
  double available_torque_nm() const;  // pull-out torque at the present speed
  double corner_speed_rad_s() const { return corner_; }
  double rotor_inertia_kgm2() const { return motor_.rotor_inertia_kgm2; }
  bool against_stop() const { return against_stop_; }

  static double microstep_motor_rad() { return 2.0 * kPi / (kFullStepsPerRev * kMicrosteps); }

 private:
  double commanded_motor_rad() const { return origin_motor_rad_ + commanded_ * microstep_motor_rad(); }
  StepperMotorData motor_;
  double gear_;
  double corner_;
  double stop_low_, stop_high_;
  bool self_locking_;
  DriveState s_;
  double origin_motor_rad_ = 0;  // rotor angle at power-up (a detent, and indexer position 0)
  int64_t commanded_ = 0;
  int64_t lost_ = 0;
  int64_t well_ = 0;  // electrical periods the rotor trails the indexer by
  double last_commanded_rad_ = 0;
  double field_speed_rad_s_ = 0;
  static constexpr double kFieldSpeedTauS = 2e-3;
  bool enabled_ = false;
  bool against_stop_ = false;
};

}  // namespace plant
}  // namespace wmra
