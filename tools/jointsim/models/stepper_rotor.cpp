#include "stepper_rotor.h"

#include <cmath>
#include <limits>

namespace wmra {
namespace jointsim {

namespace {
constexpr double kTwoPi = 6.28318530717958647692;
constexpr double kSlipEdge = 1.2 * 3.14159265358979323846;  // past the neighbouring well's edge
}  // namespace

StepperRotor::StepperRotor(const StepperRotorParams& p)
    : p_(p),
      step_rad_(kTwoPi / (p.rotor_teeth * p.steps_per_electrical_period)),
      stiffness_nm_per_rad_(p.holding_torque_nm * p.rotor_teeth) {}

void StepperRotor::step(int direction) {
  const int8_t dir = direction > 0 ? 1 : -1;
  commanded_ += dir;
  // the step train's rate: one step over the time since the step before (none before, or a
  // reversal: unknown, taken as 0)
  const double interval = t_s_ - last_step_s_;
  train_rad_s_ = (has_stepped_ && dir == last_dir_ && interval > 0) ? dir * step_rad_ / interval : 0.0;
  last_interval_s_ = interval;
  last_step_s_ = t_s_;
  last_dir_ = dir;
  has_stepped_ = true;
}

double StepperRotor::pull_out_torque_nm() const {
  const double w = std::fabs(s_.speed_rad_s);
  return w <= p_.corner_speed_rad_s ? p_.holding_torque_nm : p_.holding_torque_nm * p_.corner_speed_rad_s / w;
}

void StepperRotor::advance(double dt) {
  if (dt <= 0) return;
  t_s_ += dt;
  const double field = commanded_rad();
  // no step for longer than the last interval: the train is slowing down (or has stopped)
  const double since = t_s_ - last_step_s_;
  const double train = (train_rad_s_ != 0 && since > last_interval_s_) ? last_dir_ * step_rad_ / since : train_rad_s_;

  const double pull_out = pull_out_torque_nm();
  const double damping = 2.0 * p_.damping_ratio * std::sqrt(stiffness_nm_per_rad_ * p_.inertia_kgm2);
  double drive = pull_out * std::sin(p_.rotor_teeth * (field - s_.angle_rad)) + damping * (train - s_.speed_rad_s);
  if (drive > pull_out) drive = pull_out;
  if (drive < -pull_out) drive = -pull_out;
  const double detent = -p_.detent_torque_nm * std::sin(4.0 * p_.rotor_teeth * s_.angle_rad);

  constexpr double kInf = std::numeric_limits<double>::infinity();
  const plant::DriveFriction friction{0.0, 0.0, p_.viscous_nm_per_rad_s};
  plant::drive_step(s_, p_.inertia_kgm2, friction, drive + detent, 0.0, false, -kInf, kInf, dt);

  // which well the rotor sits in: a lag beyond the edge means one electrical period lost
  const double lag = p_.rotor_teeth * (field - s_.angle_rad) - kTwoPi * well_;
  if (lag > kSlipEdge || lag < -kSlipEdge) {
    const int64_t periods = (int64_t)std::floor((lag + 3.14159265358979323846) / kTwoPi);
    well_ += periods;
    lost_ += (periods < 0 ? -periods : periods) * p_.steps_per_electrical_period;
  }
}

}  // namespace jointsim
}  // namespace wmra
