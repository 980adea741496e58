// The effort that holds the arm and its payload against gravity at the DC joints J2..J4, as a
// duty of each joint's drive (Q15), for the DC servos' feedforward.
//
// J2, J3 and J4 turn about parallel horizontal axes z2 = z3 = z4 = u x z (u: the horizontal unit
// vector of the arm's vertical plane, (c1, s1, 0)). A mass m at a point p loads joint j with
// tau = z_j . ((p - o_j) x (0, 0, -m g)) = -m g u.(p - o_j): only its reach along u beyond the
// joint's origin counts. Along u, frame i's x axis is c(q2..qi) and its y axis -s(q2..qi) (y2
// points up at q2 = 0, so a positive q2 lifts), and y5 = c5 x4 + s5 z4 adds c5 c234. With the
// link lengths and the centres of mass that is, per joint, a fixed sum over seven products of
// the pose's sines and cosines:
//   reach_j = A c2 + B s2 + C c23 + D s23 + E c234 + F s234 + G c5 c234     (kg m)
// The holding effort is g reach_j over the drive's stall torque at the joint (the back-EMF part
// of the effort is the velocity feedforward's). Checked on the host against the simulator's
// gravity, which is built from the full frames (test/host/test_gravity.cpp).
#pragma once

#include <stdint.h>

#include "config/gravity_config.h"
#include "config/stop_config.h"
#include "kinematics/arm_model.h"
#include "kinematics/fixed_point.h"

namespace wmra {
namespace core {

namespace gravity_detail {
constexpr double kG_m_s2 = 9.81;
constexpr double kg(int16_t grams) { return grams / 1000.0; }
constexpr double m(int16_t mm) { return mm / 1000.0; }
constexpr double mass_beyond(int link) {  // link 2, 3, 4, 5: that link's mass and everything after it
  return (link <= 2 ? kg(config::kLinkCentre[0].mass_g) : 0) + (link <= 3 ? kg(config::kLinkCentre[1].mass_g) : 0) +
         (link <= 4 ? kg(config::kLinkCentre[2].mass_g) : 0) + kg(config::kLink5Mass_g) + kg(config::kPayloadMass_g);
}
// the terms of link i (2, 3, 4) along u: its own centre of mass, and its length carrying the rest
constexpr double along_x(int link, double length_m) {
  return kg(config::kLinkCentre[link - 2].mass_g) * m(config::kLinkCentre[link - 2].x_mm) + mass_beyond(link + 1) * length_m;
}
constexpr double along_y(int link) {
  return -kg(config::kLinkCentre[link - 2].mass_g) * m(config::kLinkCentre[link - 2].y_mm);
}
constexpr double kWrist_kgm = kg(config::kLink5Mass_g) * m(config::kLink5CentreY_mm) +
                              kg(config::kPayloadMass_g) * (arm::d6_m + m(config::kPayloadOffset_mm));
// kg m of reach -> Q15 duty of DC joint d's drive
constexpr int16_t duty_q15(double reach_kgm, int d) {
  return (int16_t)(reach_kgm * kG_m_s2 / (config::kDcStallTorque_cNm / 100.0 * config::kDcGear_tenths[d] / 10.0) * 32768.0 +
                   (reach_kgm >= 0 ? 0.5 : -0.5));
}
struct Terms {
  int16_t c2, s2, c23, s23, c234, s234, c5c234;
};
// joint d (0: J2) carries the links from d + 2 on
constexpr Terms terms(int d) {
  return Terms{d == 0 ? duty_q15(along_x(2, arm::a2_m), d) : (int16_t)0, d == 0 ? duty_q15(along_y(2), d) : (int16_t)0,
               d <= 1 ? duty_q15(along_x(3, arm::a3_m), d) : (int16_t)0, d <= 1 ? duty_q15(along_y(3), d) : (int16_t)0,
               duty_q15(along_x(4, arm::a4_m), d), duty_q15(along_y(4), d), duty_q15(kWrist_kgm, d)};
}
constexpr Terms kTerms[3] = {terms(0), terms(1), terms(2)};
constexpr int32_t magnitude(int16_t x) { return x < 0 ? -x : x; }
constexpr int32_t largest_sum(const Terms& k) {  // |trig| <= 1: a bound on the sum
  return magnitude(k.c2) + magnitude(k.s2) + magnitude(k.c23) + magnitude(k.s23) + magnitude(k.c234) +
         magnitude(k.s234) + magnitude(k.c5c234);
}
static_assert(largest_sum(kTerms[0]) < 32767 && largest_sum(kTerms[1]) < 32767 && largest_sum(kTerms[2]) < 32767,
              "a DC drive cannot hold its joint's load with these masses at every pose: the effort would exceed full duty");

// J5's motor plans its lifts with this share of its holding torque through its 1:10 gear
// (config/stop_config.h's motor data): below its corner speed the pull-out torque is about the
// holding torque, less the microsteps' ripple and what the figures miss.
constexpr double kJ5LiftTorqueShare = 0.8;
constexpr double kJ5PlannedTorque_Nm = config::kStepperHoldingTorque_mNm[1] / 1000.0 * config::stepper_gear(1) * kJ5LiftTorqueShare;
// the wrist's largest gravity about J5 (kg m of reach times g) over that, Q14
constexpr int16_t kWristGravity_q14 = (int16_t)(kWrist_kgm * kG_m_s2 / kJ5PlannedTorque_Nm * 16384.0 + 0.5);
static_assert(kWrist_kgm * kG_m_s2 / kJ5PlannedTorque_Nm < 1.99, "the wrist's gravity within twice J5's planned torque (Q14)");
}  // namespace gravity_detail

// Gravity about J5's axis as a fraction of the torque its motor plans with (Q14: 16384 is all of
// it; + turns J5 positive). The wrist's masses (link 5, the payload) lie on y5 = z6, a reach L
// beyond the joint-5 origin; in the frame turned by q1, z5 = (s234, 0, -c234) and z6 = (c234 c5,
// -s5, s234 c5), so gravity (0, 0, -m g) turns J5 by z5 . (L z6 x (0, 0, -m g)) = m g L s5 s234:
// most with the wrist turned a quarter (s5 = +-1) on a horizontal link 4. Checked on the host
// against the simulator's gravity (test_gravity.cpp).
template <class Trig>
int16_t wrist_gravity_q14(const Trig& t) {
  return (int16_t)(fx::mul_ss(gravity_detail::kWristGravity_q14, (t.s5 * t.s234).raw) >> 15);
}

struct HoldingEffort {
  int16_t duty_q15[3];  // J2, J3, J4: + means the drive must push the joint positive to hold it
};

// Trig: kin::JacobianTrig<kin::Fixed> (c2, s2, c23, s23, c234, s234, c5 as fx::Unit).
template <class Trig>
HoldingEffort holding_effort(const Trig& t) {
  const int16_t c5c234 = (t.c5 * t.c234).raw;
  HoldingEffort h;
  for (uint8_t d = 0; d < 3; ++d) {
    const gravity_detail::Terms& k = gravity_detail::kTerms[d];
    const int32_t sum_q30 = fx::mul_ss(k.c2, t.c2.raw) + fx::mul_ss(k.s2, t.s2.raw) + fx::mul_ss(k.c23, t.c23.raw) +
                            fx::mul_ss(k.s23, t.s23.raw) + fx::mul_ss(k.c234, t.c234.raw) +
                            fx::mul_ss(k.s234, t.s234.raw) + fx::mul_ss(k.c5c234, c5c234);
    // (sum + 2^14) >> 15 by halves: a 32-bit shift by 15 is a loop of 15 steps on the AVR
    fx::Word32 w;
    w.s = sum_q30 + 16384;
    const int32_t duty = (int32_t)w.h.hi * 2 + (w.h.lo >> 15);
    h.duty_q15[d] = (int16_t)(duty > 32767 ? 32767 : duty < -32767 ? -32767 : duty);
  }
  return h;
}

// The part of the holding effort a reference moving at qd needs: all of it while it lifts the
// load; none while it lowers, if the worm does not back-drive (the gear takes the load); none at
// rest (the joint parks, the worm holds).
inline int16_t lifting_effort_q15(int16_t holding_q15, int32_t qd) {
  if (qd == 0) return 0;
  if (!config::kDcSelfLocking) return holding_q15;
  return (qd > 0) == (holding_q15 > 0) ? holding_q15 : (int16_t)0;
}

}  // namespace core
}  // namespace wmra
