// A joint-space move (to the ready pose, to a stored pose), governed like the stick.
//
// The move is a straight line in joint space from the references where it starts to the
// target: every joint's reference speed is its share of the line, ratio_j = delta_j / |delta_L|
// (L, the lead, is the joint that moves furthest), times the lead's speed v, so the joints keep
// to the line and arrive together. v rises and falls within every joint's acceleration limit
// (the lead's acceleration scaled by the smallest accel_j / (|ratio_j| accel_L)), brakes onto
// the target (v <= sqrt(2 a remaining)), and is at most the lead's speed limit scaled by
// speed_scale(): each joint within its speed limit and its drive's present speed (the DC joints'
// load, J1's stop), the hand within the stick's full speed times the speed scale and the wrist
// within its turn rate. The hand's speed per unit of the lead's is measured along the line (the
// forward kinematics of the references a few ticks apart, with an eighth to spare); until the
// first measurement it is bounded from above without kinematics: at most sum_j |qd_j| r_j, r_j
// the farthest the frame-6 origin can be from joint j's axis. The wrist's turn is at most
// sum_j |qd_j|. So a move never outruns the stick, whatever the pose.
#pragma once

#include <stdint.h>

#include "core/joint_map.h"
#include "core/resolved_rate.h"
#include "kinematics/arm_model.h"
#include "kinematics/fixed_point.h"
#include "kinematics/fixed_trig.h"

namespace wmra {
namespace core {

struct JointMoveLimits {
  fx::Real speed_rad_s[arm::kJoints];   // each joint's limit in a move
  fx::Real accel_rad_s2[arm::kJoints];  // each joint's acceleration limit
  fx::Unit reach[arm::kJoints];         // r_j over kReachScale_m: the hand's farthest from joint j's axis
  fx::Real hand_m_s;                    // the stick's full speed, over kReachScale_m (the sums' unit)
  fx::Real wrist_rad_s;
};
constexpr double kReachScale_m = 1.25;  // the reaches as Units: r_j / 1.25 m < 1

class JointMove {
 public:
  // From the references `from` to `to` (Angle counts). Ratios follow, one joint a prepare() call.
  void begin(const int32_t* from, const int32_t* to) {
    uint32_t longest = 0;
    for (uint8_t j = 0; j < arm::kJoints; ++j) {
      target_[j] = to[j];
      delta_[j] = to[j] - from[j];
      const uint32_t d = magnitude32(delta_[j]);
      if (d > longest) {
        longest = d;
        lead_ = j;
      }
    }
    prepared_ = 0;
    v_ = fx::Real{0};
    cap_ = fx::Real{0};
    braking_ = false;
  }
  // One joint's share of the line (a quotient: one a call, so that no tick takes them all);
  // true once every joint's is known. Then the lead's acceleration.
  bool prepare(const JointMoveLimits& k) {
    if (prepared_ > arm::kJoints) return true;
    if (prepared_ < arm::kJoints) {
      const uint8_t j = prepared_++;
      // over the lead's distance, |delta_L|: each share keeps its joint's direction, the lead's
      // is +-1
      int32_t lead = (int32_t)magnitude32(delta_[lead_]), d = delta_[j];
      while (lead >= 32768) {  // both below 2^15: the quotient in Q15 fits 32 bits
        lead >>= 1;
        d >>= 1;
      }
      const int32_t q15 = lead == 0 ? 0 : (d << 15) / lead;  // |d| <= |lead|: within +-2^15
      ratio_[j] = fx::Unit{(int16_t)(q15 > 32767 ? 32767 : q15 < -32767 ? -32767 : q15)};
      return false;
    }
    // the lead's acceleration, so that each joint's, |ratio_j| a_L, is within its limit
    fx::Unit s{(int16_t)fx::kUnitOne};
    const fx::Real a_lead = k.accel_rad_s2[lead_];
    for (uint8_t j = 0; j < arm::kJoints; ++j) s = limit_scale(s, ratio_[j] * a_lead, k.accel_rad_s2[j]);
    accel_ = scaled(s, a_lead);
    dv_ = fx::Real{accel_.raw / 1000};  // a control tick's change (1 kHz)
    prepared_ = arm::kJoints + 1;
    return true;
  }
  bool prepared() const { return prepared_ > arm::kJoints; }

  // The largest lead speed the limits allow now: the joints' (drive: each joint's present
  // drive speed, its direction's), the hand's and the wrist's (times the speed scale) and a
  // factor of the DC joints' lag. A few times a second is enough: it moves with the pose.
  // hand_per_lead: the hand's speed per unit of the lead's (m/rad over kReachScale_m), measured
  // along the line from the forward kinematics (0: not yet, the bound above serves)
  void set_speed_cap(const JointMoveLimits& k, const DriveSpeeds& drive, fx::Unit speed_scale, fx::Unit lag,
                     fx::Unit hand_per_lead = fx::Unit{0}) {
    const fx::Real v_lead = k.speed_rad_s[lead_];
    fx::Unit s{(int16_t)fx::kUnitOne};
    fx::Real hand{0}, wrist{0};
    for (uint8_t j = 0; j < arm::kJoints; ++j) {
      const fx::Real qd = ratio_[j] * v_lead;
      const fx::Real d = qd.raw >= 0 ? drive.positive_rad_s[j] : drive.negative_rad_s[j];
      s = limit_scale(s, qd, d < k.speed_rad_s[j] ? d : k.speed_rad_s[j]);
      const fx::Real speed{qd.raw < 0 ? -qd.raw : qd.raw};
      hand = hand + k.reach[j] * speed;
      wrist = wrist + speed;
    }
    // measured, with a tenth for the pose's change until the next measurement
    if (hand_per_lead.raw > 0) hand = hand_per_lead * v_lead + ((hand_per_lead * v_lead).raw >> 3 > 0 ? fx::Real{(hand_per_lead * v_lead).raw >> 3} : fx::Real{0});
    s = limit_scale(s, hand, scaled(speed_scale, k.hand_m_s));
    s = limit_scale(s, wrist, scaled(speed_scale, k.wrist_rad_s));
    cap_ = scaled(lag, scaled(s, v_lead));
  }
  // The person took the move over: it slows to rest along its ramp.
  void brake() { braking_ = true; }
  bool braking() const { return braking_; }

  // One control tick: the lead's speed, from `remaining` Angle counts of its line left; the
  // joints' reference speeds into qd. True once the line is done (the references are then to
  // be set onto the target).
  bool tick(const int32_t* references, fx::Real* qd_rad_s) {
    const uint32_t remaining = magnitude32(target_[lead_] - references[lead_]);
    const fx::Real dv = dv_;
    fx::Real cap = braking_ ? fx::Real{0} : cap_;
    // braking onto the target: v <= sqrt(2 a d), in 2^-10 rad/s: (2 a d 2^20) = a_q23 d 2^21 /
    // (2^23 kAngleCountsPerRad), a_q23 >> 8 times d times 2^29 / kAngleCountsPerRad >> 16
    const uint32_t a_q15 = (uint32_t)accel_.raw >> 8;
    const uint32_t d = remaining > 0xFFFFu ? 0xFFFFu : remaining;
    const uint32_t product = fx::mul_uu((uint16_t)(a_q15 > 0xFFFF ? 0xFFFF : a_q15), (uint16_t)d);
    // / kCountsPerBrakeUnit as a product (a 32-bit division is ~600 cycles): (p >> 12) times
    // 2^20 / kCountsPerBrakeUnit (< 2^11), >> 8, within 32 bits, rounded down
    const uint32_t brake_q10_sq = ((product >> 12) * kBrakeFactor) >> 8;
    const fx::Real brake{(int32_t)fx::isqrt32(brake_q10_sq) << 13};
    if (brake < cap) cap = brake;
    // at least a creep until the line is done (the braking speed falls to 0 at the target)
    if (!braking_ && cap.raw < 2 * dv.raw) cap = fx::Real{2 * dv.raw};
    v_ = v_ < cap ? (cap - v_ < dv ? cap : v_ + dv) : (v_ - cap < dv ? cap : v_ - dv);
    if (braking_ && v_.raw <= dv.raw) v_ = fx::Real{0};
    for (uint8_t j = 0; j < arm::kJoints; ++j) qd_rad_s[j] = ratio_[j] * v_;
    // done when the next step would pass the target (the line's other joints within counts):
    // a tick's step, v (Q23 rad/s) kAngleCountsPerRad / 1000, by halves that fit 32 bits
    const uint32_t counts_s = fx::mul_uu((uint16_t)((uint32_t)v_.raw >> 8), (uint16_t)(kAngleCountsPerRad / 16)) >> 11;
    const uint32_t step_counts = (uint32_t)(fx::mul_uu((uint16_t)(counts_s > 0xFFFF ? 0xFFFF : counts_s), 66) >> 16) + 1;
    return !braking_ && remaining <= step_counts;
  }
  fx::Real lead_speed() const { return v_; }
  uint8_t lead() const { return lead_; }
  const int32_t* target() const { return target_; }

 private:
  static uint32_t magnitude32(int32_t x) { return x < 0 ? (uint32_t)-x : (uint32_t)x; }
  // the braking product's divisor: (2^-10 rad/s)^2 = a_q15 d / (kAngleCountsPerRad / 64), rounded
  // up (a braking speed from below)
  static constexpr uint32_t kCountsPerBrakeUnit = (uint32_t)(kAngleCountsPerRad / 64.0 + 1);
  static constexpr uint32_t kBrakeFactor = (1ul << 20) / kCountsPerBrakeUnit;
  static_assert(kBrakeFactor < 2048, "(p >> 12) kBrakeFactor within 32 bits");
  int32_t target_[arm::kJoints] = {};
  int32_t delta_[arm::kJoints] = {};
  fx::Unit ratio_[arm::kJoints] = {};
  uint8_t lead_ = 0;
  uint8_t prepared_ = 0;
  bool braking_ = false;
  fx::Real v_{0};
  fx::Real cap_{0};
  fx::Real accel_{0};
  fx::Real dv_{0};
};

}  // namespace core
}  // namespace wmra
