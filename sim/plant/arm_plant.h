// The whole virtual arm, without any simulator: six joint drives, their drivers, the sensors,
// the operator's joystick and buttons. The simulator sets the actuator inputs from the
// firmware's pins, calls step() at a fixed period, and reads the sensors back.
// Joints are indexed 0..5 (J1..J6): steppers 0, 4, 5; DC joints 1, 2, 3.
#pragma once

#include <array>
#include <vector>

#include "arm_plant_config.h"
#include "arm_statics.h"
#include "drv8825.h"
#include "motors.h"
#include "sensors.h"

namespace wmra {
namespace plant {

using Joints = std::array<double, kJoints>;

constexpr bool is_stepper(int joint) { return joint == 0 || joint == 4 || joint == 5; }
constexpr bool is_dc(int joint) { return joint >= 1 && joint <= 3; }
constexpr int kStepperJoints[3] = {0, 4, 5};
constexpr int kDcJoints[3] = {1, 2, 3};

class ArmPlant {
 public:
  explicit ArmPlant(const PlantConfig& config = PlantConfig{});

  // power-up: the true joint angles, everything at rest, drivers off
  void power_up(const Joints& q);

  // --- actuators
  void set_bridge_duty(int joint, double duty_left, double duty_right);  // DC joint
  // the DRV8825 pins at time t_s (the plant's own clock); returns the microstep taken (+1/-1/0)
  int set_stepper_pins(int joint, bool en_high, bool dir_high, bool step_high, double t_s);

  // --- the operator
  void set_stick(double x, double y) { stick_.set(x, y); }
  void set_stick_unplugged(bool open) { stick_.set_unplugged(open); }
  void set_button(bool down) { button_.set(down, t_); }
  void set_estop(bool down) { estop_.set(down, t_); }
  void set_pot_fault(int joint, PotFault f) { pots_[joint - 1].set_fault(f); }
  void slip_stepper(int joint, int periods) { steppers_[stepper_slot(joint)].slip(periods); }  // StepperJoint::slip

  // --- time
  void step(double dt);
  double time_s() const { return t_; }

  // --- sensors as the board sees them
  double sample_pot_mv(int joint) { return pots_[joint - 1].sample_mv(); }  // DC joint, with noise
  double sample_stick_mv(int axis) { return stick_.sample_mv(axis); }     // 0 = X, 1 = Y
  bool limit_closed(int joint, bool high) const;  // J6: its zero switch (high ignored)
  bool button_closed() const { return !stick_.unplugged() && button_.closed_at(t_); }
  bool estop_pressed() const { return estop_.closed_at(t_); }

  // --- state
  Joints q() const;
  Joints qd() const;
  const DcJoint& dc(int joint) const { return dc_[joint - 1]; }
  const StepperJoint& stepper(int joint) const { return steppers_[stepper_slot(joint)]; }
  const Drv8825& driver(int joint) const { return drivers_[stepper_slot(joint)]; }
  const Potentiometer& pot(int joint) const { return pots_[joint - 1]; }
  const JoystickAxes& stick() const { return stick_; }
  const JointLoads& loads() const { return loads_; }
  const PlantConfig& config() const { return config_; }
  bool against_stop(int joint) const;

  static int stepper_slot(int joint) { return joint == 0 ? 0 : joint == 4 ? 1 : 2; }

 private:
  void update_loads();
  PlantConfig config_;
  std::vector<DcJoint> dc_;
  std::vector<StepperJoint> steppers_;
  Drv8825 drivers_[3];
  std::vector<Potentiometer> pots_;
  std::vector<LimitSwitch> low_, high_;  // per joint; J6's zero cam in low_[5]
  JoystickAxes stick_;
  BouncingContact button_, estop_;
  JointLoads loads_;
  double t_ = 0;
  double next_loads_s_ = 0;
};

}  // namespace plant
}  // namespace wmra
