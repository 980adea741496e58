// The ideal arm of the motion sweep: what the stick asks for, in double precision and
// independent of the firmware's code. The stick's shaping (joystick.h's pipeline: dead zone,
// square to disc, response curve, rate limit) from the config's numbers; the hand's twist by
// mode (core/stick_twist.h's table, as docs/arm-guide.md gives it); and a resolved-rate arm that follows that twist exactly, through the Eigen
// reference's geometric Jacobian (modified DH matrices), integrated every millisecond. The
// sweep asks it which tests are eligible (clear of the slow bands, the soft-limit zones, the
// joints' speed limits and the DC motors' loaded speeds) and how far the hand should go.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "config/control_config.h"
#include "config/modes_config.h"
#include "config/motion_config.h"
#include "eigen_reference.h"
#include "kinematics/arm_model.h"
#include "plant/arm_plant_config.h"
#include "plant/arm_statics.h"

namespace wmra {
namespace sweep {

using Joints = std::array<double, 6>;

// One stick axis or the pair after shaping, as joystick.h does it from raw deflections in [-1, 1]
class StickShaper {
 public:
  // the deflection held from now on; returns the shaped output after dt_s
  std::array<double, 2> step(double x, double y, double dt_s) {
    const std::array<double, 2> target = shape(x, y);
    const double rise = dt_s * 1000.0 / config::kStickRise_ms, fall = dt_s * 1000.0 / config::kStickFall_ms;
    for (int i = 0; i < 2; ++i) {
      double& o = out_[i];
      const double t = target[i];
      // away from zero at the rise rate, towards it at the fall rate (through zero: fall, then rise)
      if (o * t < 0) {
        o = o > 0 ? std::max(0.0, o - fall) : std::min(0.0, o + fall);
      } else if (std::fabs(t) > std::fabs(o)) {
        o = t > o ? std::min(t, o + rise) : std::max(t, o - rise);
      } else {
        o = t > o ? std::min(t, o + fall) : std::max(t, o - fall);
      }
    }
    return out_;
  }
  // x, y: the stick's deflections as the simulator takes them, fractions of its whole travel;
  // full deflection (1) is reached a little before the travel's end (kStickFullDeflection_counts)
  static std::array<double, 2> shape(double x, double y) {
    const double dz = config::kStickDeadZone_permille / 1000.0, k = config::kStickExpo_permille / 1000.0;
    const double full = (double)config::kStickTravel_counts / config::kStickFullDeflection_counts;
    const auto dead = [dz](double v) { return std::fabs(v) <= dz ? 0.0 : std::copysign((std::fabs(v) - dz) / (1 - dz), v); };
    const double sx = dead(std::clamp(x * full, -1.0, 1.0)), sy = dead(std::clamp(y * full, -1.0, 1.0));
    const double r_square = std::max(std::fabs(sx), std::fabs(sy)), r_len = std::hypot(sx, sy);
    if (r_len == 0) return {0, 0};
    const double r = r_square;  // the square onto the disc: radius max(|x|, |y|) along the same direction
    const double curved = (1 - k) * r + k * r * r * r;
    return {sx / r_len * curved, sy / r_len * curved};
  }

 private:
  std::array<double, 2> out_{0, 0};
};

// The hand's twist for a shaped stick: v of the frame-6 origin in the base frame (m/s) and w in
// the base frame (rad/s); the rotation modes turn about the wrist axes x5, y5, z5 and keep the
// origin still.
struct Twist {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
};

inline Twist mode_twist(config::Mode mode, std::array<double, 2> s, const Joints& q) {
  const double hand = (double)config::kMaxHandSpeed_m_s.num / config::kMaxHandSpeed_m_s.den;
  const double wrist = (double)config::kMaxWristSpeed_rad_s.num / config::kMaxWristSpeed_rad_s.den;
  const double sx = config::kStickXSign * s[0], sy = config::kStickYSign * s[1];
  Twist t;
  const Eigen::Matrix3d r5 = ref::frames(q)[4].block<3, 3>(0, 0);
  switch (mode) {
    case config::Mode::xy: t.v = Eigen::Vector3d(sx, sy, 0) * hand; break;
    case config::Mode::xz: t.v = Eigen::Vector3d(sx, 0, sy) * hand; break;
    case config::Mode::r1: t.w = r5 * Eigen::Vector3d(0, sx, sy) * wrist; break;
    case config::Mode::r2: t.w = r5 * Eigen::Vector3d(sy, sx, 0) * wrist; break;
    case config::Mode::gripper: break;
  }
  return t;
}

// Why an ideal run is not eligible (0: it is)
enum Ineligible : unsigned {
  kSlowBand = 1,   // |cos q5|, |sin q3| or R5 inside the firmware's slow bands
  kSoftZone = 2,   // a joint within the soft-limit margin and zone of its limit
  kSpeedLimit = 4,  // a joint asked to turn faster than its speed limit
  // a factor inside its slow band taken towards zero within the first kApproachWindow_s of the
  // hold: the motion the firmware rightly slows to a stop (SPEC 5), so the arm staying put is
  // not "stuck"
  kTowardsSingular = 8,
  // a DC joint asked to turn faster than its motor turns it at full supply against the load's
  // gravity (the plant's torque model: what no controller can do)
  kDriveTorque = 16
};
constexpr double kApproachWindow_s = 1.0;

inline double r5_m(const Joints& q) {
  return arm::a1_m + std::cos(q[1]) * arm::a2_m + std::cos(q[1] + q[2]) * arm::a3_m + std::cos(q[1] + q[2] + q[3]) * arm::a4_m;
}

// the singular factors |cos q5|, |sin q3|, R5 (m) as fractions of their slow bands (< 1: inside)
inline std::array<double, 3> band_fractions(const Joints& q) {
  const auto ratio = [](Ratio r) { return (double)r.num / r.den; };
  const arm::SingularBands& b = arm::kSingularBands;
  return {std::fabs(std::cos(q[4])) / ratio(b.slow_c5), std::fabs(std::sin(q[2])) / ratio(b.slow_s3), r5_m(q) / ratio(b.slow_r5_m)};
}
// a factor inside its slow band that the step qd dt takes towards zero
inline bool approaches_singular(const Joints& q, const Eigen::Matrix<double, 6, 1>& qd, double dt_s) {
  Joints next = q;
  for (int j = 0; j < 6; ++j) next[j] += qd[j] * dt_s;
  const std::array<double, 3> now = band_fractions(q), then = band_fractions(next);
  for (int i = 0; i < 3; ++i)
    if (now[i] < 1 && then[i] < now[i]) return true;
  return false;
}

// The fastest a DC joint turns its way (sign of qd_rad_s) at full supply in the plant, at steady
// speed: the assembly's torque-speed line against its Coulomb and viscous friction and the
// gravity that opposes the motion (a self-locking worm takes a load that helps it).
inline double dc_loaded_speed_rad_s(int joint, double qd_rad_s, double gravity_nm) {
  const double gear = plant::kGearRatio[joint];
  const double opposing_nm = std::max(0.0, -std::copysign(1.0, qd_rad_s) * gravity_nm / gear);
  const double assembly_rad_s = (plant::kDcStallTorqueNm - plant::kDcCoulombFrictionNm - opposing_nm) /
                                (plant::kDcStallTorqueNm / plant::kDcNoLoadSpeedRadS + plant::kDcViscousNmPerRadS);
  return std::max(0.0, assembly_rad_s / gear);
}

inline unsigned ineligible_at(const Joints& q, const Eigen::Matrix<double, 6, 1>& qd) {
  unsigned why = 0;
  const auto ratio = [](Ratio r) { return (double)r.num / r.den; };
  const arm::SingularBands& b = arm::kSingularBands;
  if (std::fabs(std::cos(q[4])) < ratio(b.slow_c5) || std::fabs(std::sin(q[2])) < ratio(b.slow_s3) || r5_m(q) < ratio(b.slow_r5_m))
    why |= kSlowBand;
  const double zone = arm::deg_to_rad(config::kSoftLimitMargin_deg + config::kSoftLimitZone_deg);
  for (int j = 0; j < 6; ++j) {
    if (q[j] < arm::q_min_rad(j) + zone || q[j] > arm::q_max_rad(j) - zone) why |= kSoftZone;
    if (std::fabs(qd[j]) > config::kJointSpeedLimit_crad_s[j] / 100.0) why |= kSpeedLimit;
  }
  const plant::JointLoads loads = plant::joint_loads(q, true, plant::PlantConfig{}.payload);
  for (int j = 1; j <= 3; ++j)
    if (std::fabs(qd[j]) > dc_loaded_speed_rad_s(j, qd[j], loads.gravity_nm[j])) why |= kDriveTorque;
  return why;
}

// The resolved-rate arm that follows the shaped stick exactly
class IdealArm {
 public:
  explicit IdealArm(const Joints& q) : q_(q) {}
  // one step of dt_s with the stick at (x, y) in `mode`
  void step(config::Mode mode, double x, double y, double dt_s) {
    const std::array<double, 2> s = stick_.step(x, y, dt_s);
    const Twist t = mode_twist(mode, s, q_);
    Eigen::Matrix<double, 6, 1> twist;
    twist << t.v, t.w;
    const Eigen::Matrix<double, 6, 1> qd = ref::geometric_jacobian(q_).partialPivLu().solve(twist);
    why_ |= ineligible_at(q_, qd);
    if (t_s_ < kApproachWindow_s && approaches_singular(q_, qd, dt_s)) why_ |= kTowardsSingular;
    for (int j = 0; j < 6; ++j) q_[j] += qd[j] * dt_s;
    t_s_ += dt_s;
  }
  const Joints& q() const { return q_; }
  unsigned ineligible() const { return why_; }

 private:
  Joints q_;
  StickShaper stick_;
  unsigned why_ = 0;
  double t_s_ = 0;
};

}  // namespace sweep
}  // namespace wmra
