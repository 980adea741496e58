#include "motors.h"

#include <cmath>

namespace wmra {
namespace plant {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

// --- DC joint

DcJoint::DcJoint(double gear_ratio, double q_min_rad, double q_max_rad, bool self_locking)
    : gear_(gear_ratio),
      stop_low_((q_min_rad - kHardStopBeyondLimitRad) * gear_ratio),
      stop_high_((q_max_rad + kHardStopBeyondLimitRad) * gear_ratio),
      self_locking_(self_locking) {}

void DcJoint::set_angle(double q_rad) {
  s_.angle_rad = q_rad * gear_;
  s_.speed_rad_s = 0;
}

// The assembly's torque-speed line through the datasheet's stall point and the no-load speed,
// scaled with the applied voltage (L ~ 0: first order, Torres, Eq. 2.11).
double DcJoint::motor_torque_nm() const {
  return kDcStallTorqueNm * (voltage_v_ / kDcNominalV - s_.speed_rad_s / kDcNoLoadSpeedRadS);
}
double DcJoint::current_a() const {
  return kDcStallCurrentA * (voltage_v_ / kDcNominalV - s_.speed_rad_s / kDcNoLoadSpeedRadS);
}

void DcJoint::step(double dt, double link_inertia_kgm2, double load_torque_nm) {
  const DriveFriction f{kDcStaticFrictionNm, kDcCoulombFrictionNm, kDcViscousNmPerRadS};
  const double load_inertia = link_inertia_kgm2 / (gear_ * gear_);
  against_stop_ = drive_step(s_, kDcAssemblyInertiaKgm2 + load_inertia, f, motor_torque_nm(), load_torque_nm / gear_,
                             self_locking_, stop_low_, stop_high_, dt, load_inertia);
}

// --- stepper joint

StepperJoint::StepperJoint(const StepperMotorData& motor, double gear_ratio, double q_min_rad, double q_max_rad,
                           bool hard_stops, bool self_locking)
    : motor_(motor),
      gear_(gear_ratio),
      corner_(plant::corner_speed_rad_s(motor)),
      stop_low_(hard_stops ? (q_min_rad - kHardStopBeyondLimitRad) * gear_ratio : -kInf),
      stop_high_(hard_stops ? (q_max_rad + kHardStopBeyondLimitRad) * gear_ratio : kInf),
      self_locking_(self_locking) {}

void StepperJoint::set_angle(double q_rad) {
  s_.angle_rad = q_rad * gear_;
  s_.speed_rad_s = 0;
  origin_motor_rad_ = s_.angle_rad;
  commanded_ = 0;
  lost_ = 0;
  well_ = 0;
  last_commanded_rad_ = origin_motor_rad_;
  field_speed_rad_s_ = 0;
}

void StepperJoint::microstep(int direction) { commanded_ += direction > 0 ? 1 : -1; }

double StepperJoint::available_torque_nm() const {
  const double w = std::fabs(s_.speed_rad_s);
  return w <= corner_ ? motor_.holding_torque_nm : motor_.holding_torque_nm * corner_ / w;
}

void StepperJoint::step(double dt, double link_inertia_kgm2, double load_torque_nm) {
  const double inertia = motor_.rotor_inertia_kgm2 + link_inertia_kgm2 / (gear_ * gear_);
  // speed of the indexer's field, smoothed over the microstep staircase
  const double commanded = commanded_motor_rad();
  field_speed_rad_s_ += ((commanded - last_commanded_rad_) / dt - field_speed_rad_s_) * (dt / kFieldSpeedTauS);
  last_commanded_rad_ = commanded;
  double torque = 0;
  if (enabled_) {
    // the current vector pulls the rotor towards it (sin of the electrical lag); the drive's
    // damping acts on the rotor's speed against the field; never beyond the pull-out torque
    const double e = kRotorPolePairs * (commanded - s_.angle_rad);
    const double stiffness = motor_.holding_torque_nm * kRotorPolePairs;
    const double damping = 2.0 * kStepperDampingRatio * std::sqrt(stiffness * inertia);
    const double limit = available_torque_nm();
    torque = limit * std::sin(e) + damping * (field_speed_rad_s_ - s_.speed_rad_s);
    torque = torque > limit ? limit : torque < -limit ? -limit : torque;
  }
  // detent torque: 200 wells per turn, one at the power-up position
  torque -= motor_.detent_torque_nm * std::sin(4.0 * kRotorPolePairs * (s_.angle_rad - origin_motor_rad_));
  const DriveFriction f{kStepperStaticFrictionNm, kStepperCoulombFrictionNm, 0.0};
  against_stop_ = drive_step(s_, inertia, f, torque, load_torque_nm / gear_, self_locking_, stop_low_, stop_high_, dt);

  // Slip: the rotor left its well (|e - 2 pi well| beyond pi, with some hysteresis) for the next
  // one: 4 full steps (128 microsteps) lost each time.
  const double e_after = kRotorPolePairs * (commanded - s_.angle_rad);
  constexpr double kTwoPi = 2.0 * kPi;
  constexpr double kEdge = 1.2 * kPi;
  while (e_after - kTwoPi * well_ > kEdge) {
    ++well_;
    lost_ += kMicrostepsPerElectricalPeriod;
  }
  while (e_after - kTwoPi * well_ < -kEdge) {
    --well_;
    lost_ += kMicrostepsPerElectricalPeriod;
  }
}

}  // namespace plant
}  // namespace wmra
