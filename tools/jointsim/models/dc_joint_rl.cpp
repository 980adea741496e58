#include "dc_joint_rl.h"

#include <cmath>

#include "kinematics/arm_model.h"

namespace wmra {
namespace jointsim {

DcJointRl::DcJointRl(int joint, double inductance_h, bool self_locking)
    : gear_(plant::kGearRatio[joint]),
      inductance_h_(inductance_h),
      self_locking_(self_locking),
      stop_low_((arm::q_min_rad(joint) - plant::kHardStopBeyondLimitRad) * gear_),
      stop_high_((arm::q_max_rad(joint) + plant::kHardStopBeyondLimitRad) * gear_) {}

void DcJointRl::set_angle(double q_rad) {
  s_.angle_rad = q_rad * gear_;
  s_.speed_rad_s = 0;
  current_a_ = 0;
}

void DcJointRl::step(double dt, double link_inertia_kgm2, double load_torque_nm) {
  const double steady_a = (voltage_v_ - kDcBackEmfVsPerRad * s_.speed_rad_s) / kDcArmatureResistanceOhm;
  current_a_ = inductance_h_ > 0
                   ? steady_a + (current_a_ - steady_a) * std::exp(-dt * kDcArmatureResistanceOhm / inductance_h_)
                   : steady_a;
  const plant::DriveFriction f{plant::kDcStaticFrictionNm, plant::kDcCoulombFrictionNm, plant::kDcViscousNmPerRadS};
  const double load_inertia = link_inertia_kgm2 / (gear_ * gear_);
  against_stop_ = plant::drive_step(s_, plant::kDcAssemblyInertiaKgm2 + load_inertia, f, motor_torque_nm(),
                                    load_torque_nm / gear_, self_locking_, stop_low_, stop_high_, dt, load_inertia);
}

}  // namespace jointsim
}  // namespace wmra
