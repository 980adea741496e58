// One DC joint of the arm with its armature circuit: the virtual arm's DC joint (sim/plant
// DcJoint: Mabuchi 578VA and its self-locking worm, friction, the joint gear, hard stops, on
// plant::drive_step) with the armature inductance added, so that the current lags the bridge
// voltage by L/R:
//   V = R i + L di/dt + k_e omega,   T = k_t i       (at the worm's output shaft)
// R, k_t and k_e come from the datasheet line the plant uses (joint_data.h); with L = 0 this is
// the plant's DcJoint exactly (test_jointsim checks it). Angles are joint angles (rad) unless a
// name says otherwise; the current is integrated exactly over a step with omega held.
#pragma once

#include "models/joint_data.h"
#include "plant/drive.h"

namespace wmra {
namespace jointsim {

class DcJointRl {
 public:
  // joint: the plant's index, 1..3 for J2..J4
  explicit DcJointRl(int joint, double inductance_h = kDcArmatureInductanceH,
                     bool self_locking = plant::kDcSelfLocking);

  void set_angle(double q_rad);  // at rest, no current
  void set_voltage(double v) { voltage_v_ = v; }
  // one step with the arm's inertia and the gravity torque about this joint (at the joint)
  void step(double dt, double link_inertia_kgm2, double load_torque_nm);

  double q() const { return s_.angle_rad / gear_; }
  double qd() const { return s_.speed_rad_s / gear_; }
  double current_a() const { return current_a_; }
  double motor_torque_nm() const { return kDcTorqueConstantNmPerA * current_a_; }  // at the worm's output
  double voltage() const { return voltage_v_; }
  double gear_ratio() const { return gear_; }
  bool against_stop() const { return against_stop_; }

 private:
  double gear_;
  double inductance_h_;
  bool self_locking_;
  double stop_low_, stop_high_;  // at the worm's output
  plant::DriveState s_;
  double voltage_v_ = 0;
  double current_a_ = 0;
  bool against_stop_ = false;
};

}  // namespace jointsim
}  // namespace wmra
