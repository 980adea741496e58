// Seed 1's DC motor: G(s) = K_m / (s (tau s + 1)), drive voltage in, shaft angle out
// (seed1 4.3, 5.2), integrated exactly over each step with the voltage held (a ZOH):
//   theta(t+h)  = theta + tau (1 - e) omega + K_m u (h - tau (1 - e))      (4.23)
//   omega(t+h)  = e omega + K_m u (1 - e),   e = exp(-h / tau)           (4.24, corrected)
// so the sample rate of a controller and the plant's integration step do not change the answer.
// No friction: once the drive is off the motor coasts to theta + tau omega (seed1 4.3).
#pragma once

#include <cmath>

namespace wmra {
namespace jointsim {

class FirstOrderMotor {
 public:
  FirstOrderMotor(double gain_rad_per_v_s, double time_constant_s) : k_(gain_rad_per_v_s), tau_(time_constant_s) {}

  void set(double angle_rad, double speed_rad_s) {
    angle_rad_ = angle_rad;
    speed_rad_s_ = speed_rad_s;
  }
  void advance(double volts, double h) {
    const double e = std::exp(-h / tau_);
    const double drive = k_ * volts;  // the steady speed for this voltage
    angle_rad_ += tau_ * (1 - e) * speed_rad_s_ + drive * (h - tau_ * (1 - e));
    speed_rad_s_ = e * speed_rad_s_ + drive * (1 - e);
  }
  double angle_rad() const { return angle_rad_; }
  double speed_rad_s() const { return speed_rad_s_; }

 private:
  double k_, tau_;
  double angle_rad_ = 0, speed_rad_s_ = 0;
};

}  // namespace jointsim
}  // namespace wmra
