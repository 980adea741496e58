#include "arm_plant.h"

namespace wmra {
namespace plant {

namespace {
constexpr double kLoadsPeriodS = 1e-3;  // gravity and inertia change slowly: every millisecond

// noise stream ids (one per source, see noise.h)
enum Stream : uint64_t { kPotStream = 10, kStickX = 20, kStickY = 21, kButton = 30, kEstop = 31 };

const StepperMotorData& stepper_motor(int joint) { return joint == 0 ? kNema23Ht23_397 : kNema17_42HS48; }
}  // namespace

ArmPlant::ArmPlant(const PlantConfig& config)
    : config_(config),
      stick_(config.stick_centre_offset_mv, config.stick_noise_mv, NoiseStream(config.seed, kStickX),
             NoiseStream(config.seed, kStickY)),
      button_(config.button_bounce_s, NoiseStream(config.seed, kButton)),
      estop_(config.button_bounce_s, NoiseStream(config.seed, kEstop)) {
  for (int j : kDcJoints) {
    dc_.emplace_back(kGearRatio[j], arm::q_min_rad(j), arm::q_max_rad(j), config.dc_self_locking);
    pots_.emplace_back(arm::q_min_rad(j), arm::q_max_rad(j), config.pot_noise_mv, config.pot_filter_tau_s,
                       NoiseStream(config.seed, kPotStream + j));
  }
  for (int j : kStepperJoints) {
    steppers_.emplace_back(stepper_motor(j), kGearRatio[j], arm::q_min_rad(j), arm::q_max_rad(j), j != 5,
                           j == 4 ? config.j5_self_locking : false);
  }
  for (int j = 0; j < kJoints; ++j) {
    if (j == 5) {
      low_.emplace_back(LimitSwitch::Kind::zero, 0.0, config.limit_switch_tau_s);
      high_.emplace_back(LimitSwitch::Kind::zero, 0.0, config.limit_switch_tau_s);
    } else {
      low_.emplace_back(LimitSwitch::Kind::low, arm::q_min_rad(j), config.limit_switch_tau_s);
      high_.emplace_back(LimitSwitch::Kind::high, arm::q_max_rad(j), config.limit_switch_tau_s);
    }
  }
  power_up(Joints{});
}

void ArmPlant::power_up(const Joints& q) {
  t_ = 0;
  for (int j : kDcJoints) {
    dc_[j - 1].set_angle(q[j]);
    dc_[j - 1].set_voltage(0);
    pots_[j - 1].reset(q[j]);
  }
  for (int j : kStepperJoints) {
    steppers_[stepper_slot(j)].set_angle(q[j]);
    steppers_[stepper_slot(j)].set_enabled(false);
    drivers_[stepper_slot(j)] = Drv8825();
    drivers_[stepper_slot(j)].reset(true, false, false, t_);
  }
  for (int j = 0; j < kJoints; ++j) {
    low_[j].reset(q[j]);
    high_[j].reset(q[j]);
  }
  button_.reset(false);
  estop_.reset(false);
  update_loads();
}

void ArmPlant::set_bridge_duty(int joint, double duty_left, double duty_right) {
  dc_[joint - 1].set_voltage(bts7960_voltage(duty_left, duty_right));
}

int ArmPlant::set_stepper_pins(int joint, bool en_high, bool dir_high, bool step_high, double t_s) {
  const int slot = stepper_slot(joint);
  const int move = drivers_[slot].update(en_high, dir_high, step_high, t_s);
  steppers_[slot].set_enabled(drivers_[slot].enabled());
  if (move) steppers_[slot].microstep(move);
  return move;
}

void ArmPlant::update_loads() { loads_ = joint_loads(q(), config_.gravity, config_.payload); }

void ArmPlant::step(double dt) {
  if (t_ >= next_loads_s_) {
    update_loads();
    next_loads_s_ = t_ + kLoadsPeriodS;
  }
  for (int j : kDcJoints) dc_[j - 1].step(dt, loads_.inertia_kgm2[j], loads_.gravity_nm[j]);
  for (int j : kStepperJoints) steppers_[stepper_slot(j)].step(dt, loads_.inertia_kgm2[j], loads_.gravity_nm[j]);
  t_ += dt;
  const Joints angles = q();
  for (int j : kDcJoints) pots_[j - 1].step(angles[j], dt);
  for (int j = 0; j < kJoints; ++j) {
    low_[j].step(angles[j], dt);
    if (j != 5) high_[j].step(angles[j], dt);
  }
  button_.settle(t_);
  estop_.settle(t_);
}

bool ArmPlant::limit_closed(int joint, bool high) const {
  return (high && joint != 5) ? high_[joint].closed() : low_[joint].closed();
}

bool ArmPlant::against_stop(int joint) const {
  return is_dc(joint) ? dc_[joint - 1].against_stop() : steppers_[stepper_slot(joint)].against_stop();
}

Joints ArmPlant::q() const {
  Joints out;
  for (int j : kDcJoints) out[j] = dc_[j - 1].q();
  for (int j : kStepperJoints) out[j] = steppers_[stepper_slot(j)].q();
  return out;
}

Joints ArmPlant::qd() const {
  Joints out;
  for (int j : kDcJoints) out[j] = dc_[j - 1].qd();
  for (int j : kStepperJoints) out[j] = steppers_[stepper_slot(j)].qd();
  return out;
}

}  // namespace plant
}  // namespace wmra
