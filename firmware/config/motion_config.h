// Motion limits of the arm: hand speeds, joint speeds and the soft joint limits.
// Every number carries its unit in its name; changing one is an edit here and a rebuild.
// Joint speeds are what the joint, its gear and the person next to it can take, well below
// what the drives can do (J1 2,037 steps/rad, J5 10,186, J6 1,019 at 1/32 microstep: at
// 20 kHz that is 9.8, 1.96 and 19.6 rad/s).
#pragma once

#include <stdint.h>

#include "kinematics/ratio.h"

namespace wmra {
namespace config {

// full stick deflection (docs/arm-guide.md, using the arm)
constexpr Ratio kMaxHandSpeed_m_s{15, 100};
constexpr Ratio kMaxWristSpeed_rad_s{80, 100};

// joint speed limits J1..J6, in hundredths of a rad/s
constexpr int16_t kJointSpeedLimit_crad_s[6] = {80, 100, 100, 160, 150, 150};

// acceleration limits of the joint references J1..J6, hundredths of a rad/s^2: the steppers'
// below their ramps' (joints_config.h), so that a ramp follows its reference with some to
// spare for corrections; the DC joints' well within what their motors do under load
constexpr int16_t kJointAccelLimit_crad_s2[6] = {50, 300, 300, 300, 350, 350};
// Soft joint limits: a joint stops this far inside its switch, and slows down linearly over
// the zone before that; motion away from the limit is never slowed.
constexpr int16_t kSoftLimitMargin_deg = 3;
constexpr int16_t kSoftLimitZone_deg = 12;
// How long a joint runs on at its speed after its reference starts to slow (the DC joints'
// lag behind their references, the steppers' position loop): the approach to a singular
// band brakes in time with it (core/resolved_rate.h). The DC elbow runs on 70-100 ms behind a
// braking reference; with less, the sweep's elbow ends inside the damped band (docs/motion.md).
constexpr int16_t kSingularBrakeLag_ms = 100;
// A jog (bring-up: one joint turned to check its motor's direction or its pot, SPEC 7) at most
// this fast; a stepper before homing (its count is not its angle: no soft limit, only its
// switches stop it) at most kJogUnhomedStepperSpeed_mrad_s
constexpr int16_t kJogSpeed_mrad_s = 100;
constexpr int16_t kJogUnhomedStepperSpeed_mrad_s = 50;
// and such a stepper at most this far from where its count stood at power-up (J6 has no switch:
// jogged on, it would wind its cables past its range; a J1 or J5 switch that does not work
// would let the joint run onto its hard stop): enough to see its direction
constexpr int16_t kJogUnhomedTravel_deg = 30;

static_assert(kJogSpeed_mrad_s > 0 && kJogSpeed_mrad_s <= 200 && kJogUnhomedStepperSpeed_mrad_s > 0 &&
                  kJogUnhomedStepperSpeed_mrad_s <= kJogSpeed_mrad_s,
              "kJogSpeed_mrad_s in (0, 200] mrad/s, kJogUnhomedStepperSpeed_mrad_s in (0, kJogSpeed_mrad_s]");
static_assert(kJogUnhomedTravel_deg >= 5 && kJogUnhomedTravel_deg <= 90, "kJogUnhomedTravel_deg in [5, 90] deg");
static_assert(kMaxHandSpeed_m_s.num > 0 && kMaxHandSpeed_m_s.num * 100 <= 30 * kMaxHandSpeed_m_s.den,
              "kMaxHandSpeed_m_s in (0, 0.3] m/s");
static_assert(kMaxWristSpeed_rad_s.num > 0 && kMaxWristSpeed_rad_s.num <= 2 * kMaxWristSpeed_rad_s.den,
              "kMaxWristSpeed_rad_s in (0, 2] rad/s");
constexpr bool joint_speeds_in_range() {
  for (int j = 0; j < 6; ++j)
    if (kJointSpeedLimit_crad_s[j] <= 0 || kJointSpeedLimit_crad_s[j] > 300) return false;
  return true;
}
static_assert(joint_speeds_in_range(), "kJointSpeedLimit_crad_s in (0, 300]: (0, 3] rad/s");
constexpr bool joint_accels_in_range() {
  for (int j = 0; j < 6; ++j)
    if (kJointAccelLimit_crad_s2[j] < 10 || kJointAccelLimit_crad_s2[j] > 2000) return false;
  return true;
}
static_assert(joint_accels_in_range(), "kJointAccelLimit_crad_s2 in [10, 2000]: [0.1, 20] rad/s^2");
static_assert(kSoftLimitMargin_deg >= 1 && kSoftLimitMargin_deg <= 10, "kSoftLimitMargin_deg in [1, 10] deg");
static_assert(kSoftLimitZone_deg >= 2 && kSoftLimitZone_deg <= 30, "kSoftLimitZone_deg in [2, 30] deg");
static_assert(kSingularBrakeLag_ms >= 0 && kSingularBrakeLag_ms <= 200, "kSingularBrakeLag_ms in [0, 200] ms");

}  // namespace config
}  // namespace wmra
