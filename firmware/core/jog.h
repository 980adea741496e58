// A jog (bring-up, SPEC 7): one joint turned at a requested speed while the requests keep coming,
// to check a motor's direction or a pot before the first homing. The speed it may have now: the
// request within kJogSpeed_mrad_s; none into a closed limit switch of the joint; where the
// joint's angle is known (a DC joint's pot, a homed stepper's count, J6's recorded angle) the soft
// limits' slow-down and the drives' speeds, as the stick's motion has them (joint_rate_scale).
// A stepper whose count is not yet its angle (before homing) within kJogUnhomedStepperSpeed_mrad_s,
// and none further than kJogUnhomedTravel_deg from where its count stood at power-up (origin).
#pragma once

#include <stdint.h>

#include "config/motion_config.h"
#include "core/joint_map.h"
#include "core/resolved_rate.h"

namespace wmra {
namespace core {


constexpr int32_t kJogUnhomedTravel = fx::angle_deg(Ratio{config::kJogUnhomedTravel_deg, 1}).raw;

// origin: the joint's angle where its count stood at power-up (used where !angle_known)
inline fx::Real jog_speed(uint8_t joint, int16_t requested_mrad_s, bool angle_known, const kin::JointAngles<kin::Fixed>& q,
                          const MotionLimits& limits, const DriveSpeeds& drives, uint16_t closed_switches,
                          fx::Angle origin = fx::Angle{0}) {
  const int16_t cap = angle_known ? config::kJogSpeed_mrad_s : config::kJogUnhomedStepperSpeed_mrad_s;
  const int16_t mrad_s = requested_mrad_s > cap ? cap : requested_mrad_s < -cap ? (int16_t)-cap : requested_mrad_s;
  // the joint's switches: bit 2j its low end's, 2j + 1 its high end's (J6 has none: its bits
  // 10 and 11 are its zero switch's and none)
  const uint16_t towards = joint < 5 ? (uint16_t)(1u << (2 * joint + (mrad_s > 0 ? 1 : 0))) : 0;
  if (mrad_s == 0 || (closed_switches & towards)) return fx::Real{0};
  const fx::Real speed{(int32_t)mrad_s * kRealPerMilli};
  if (!angle_known) {
    const int32_t from_origin = q.q[joint].raw - origin.raw;
    const bool away = mrad_s > 0 ? from_origin >= kJogUnhomedTravel : from_origin <= -kJogUnhomedTravel;
    return away ? fx::Real{0} : speed;
  }
  kin::JacobianInverse<kin::Fixed> only{};
  only.qd_rad_s[joint] = speed;
  return scaled(joint_rate_scale(fx::Unit{(int16_t)fx::kUnitOne}, q, only, limits, drives).scale, speed);
}

}  // namespace core
}  // namespace wmra
