// Resolved-rate motion: the joint velocities that move the hand along the commanded twist,
// scaled down, all by one factor, wherever a joint or the arm's geometry asks for it.
//
//   1. qd = J^-1(q) twist, the closed form of inverse_jacobian.h (damped inside the
//      singular bands, so qd stays bounded there); the twist's w about the wrist axes
//      (kin::TwistWrist: what the rotation modes give, kin::twist_wrist turns a base-frame one).
//   2. Singularity slow-down. For each factor of det J (c5, s3, R5) inside its slow band and
//      moving towards zero (sign(f) df/dt < 0, faster than |f| / 32 s: moving_towards_zero),
//      the motion may go at most the fraction
//      (|f| - damp) / (slow - damp) of its speed: 1 at the edge of the slow band, 0 at the
//      edge of the damped band. Motion that takes f away from zero is not slowed, so the arm
//      can always be driven back out, and it stops before the damped band, where the
//      inverse is no longer exact. df/dt comes from qd itself:
//        d c5/dt = -s5 qd5,   d s3/dt = c3 qd3,
//        d R5/dt = -(s2 a2 qd2 + s23 a3 (qd2 + qd3) + s234 a4 (qd2 + qd3 + qd4)).
//      The elbow (s3) also brakes in time: |d s3/dt| at most the rate from which it still
//      stops before the damped band (singular_approach_rate), from |sin q3| < 0.43 on,
//      before the slow band. The fraction alone lets J^-1's speeds, which grow as 1 / f, run
//      the elbow into the band faster than it can stop, and it crossed to the other branch. (c5 = 0 lies at J5's limits, +-90 deg: J5's soft
//      limit brakes it before its band, step 3.)
//   3. Soft joint limits. A joint moving towards a limit may go at its speed limit times
//      (distance to its soft stop) / zone, 0 at the stop, which lies a margin inside the switch;
//      and at most sqrt(2 (3/4) a d), the speed it can still brake from within the distance d
//      at 3/4 of its acceleration limit a (joint_acceleration.h applies a, with the rest to
//      spare): J1, at 0.5 rad/s^2, needs 37 deg to stop from its 0.8 rad/s.
//   4. Joint speed limits. Every |s qd_j| <= allowed_j.
// One common factor s satisfies all of them, so the hand keeps its direction;
// s only shrinks, and a joint that needs a division (1/|qd_j| from a table reciprocal) is
// only one that s does not already satisfy.
#pragma once

#include "config/motion_config.h"
#include "core/joint_map.h"
#include "kinematics/inverse_jacobian.h"
#include "kinematics/inverse_kinematics.h"

namespace wmra {
namespace core {

using kin::Fixed;

// why the motion was slowed (bits, for telemetry)
enum SlowReason : uint8_t {
  kSlowSingular = 1,
  kSlowSoftLimit = 2,
  kSlowJointSpeed = 4,
  kSlowDriveLoad = 8,
  kSlowTracking = 16,  // set by the caller: a DC joint lags its reference, the whole motion slows
  kSlowLimitSwitch = 32,  // a joint would move into its closed limit switch (stop_towards_switches)
};

// The fastest each joint's drive can turn it now, each way (rad/s): a DC joint that lifts its
// load has only the duty left beyond its holding effort for speed (firmware/core/gravity.h).
// Slowing every joint by the same factor when one of them would exceed it keeps the hand on
// its line; a joint that lags behind its reference instead puts the hand off the line, and
// when it catches up afterwards the hand jumps.
struct DriveSpeeds {
  fx::Real positive_rad_s[arm::kJoints];
  fx::Real negative_rad_s[arm::kJoints];
  uint16_t closed_switches;  // stop_towards_switches' (inputs.h's bits): which drives are a switch's creep
};

// A limit switch closed while the arm runs (closed already when the switches were armed at a
// re-arm: only a closing stops the arm, inputs.h): its joint's drive may not turn it further
// that way, only back off it. closed: inputs.h's bits, 2j the low end's switch, 2j+1 the high
// end's. Through the drives' speeds, the hand's motion stops where it needs that joint moving
// into its switch (to a creep: rate_scale's common factor keeps the others' share).
// The creep, not 0: J^-1's rounding leaves a joint the twist does not turn a few steps of
// 2^-23 rad/s either way (up to ~70 in test_resolved_rate), and a drive of 0 would stop every
// motion then. Pressed on into its switch for a minute, a joint creeps 6 mrad (J4's hard stop
// is 52 mrad beyond its switch).
constexpr fx::Real kCreepTowardsClosedSwitch_rad_s = fx::real(Ratio{1, 10000});
__attribute__((cold)) inline void stop_towards_switches(DriveSpeeds& drives, uint16_t closed) {
  drives.closed_switches = closed;
  for (uint8_t j = 0; j < arm::kJoints; ++j, closed = (uint16_t)(closed >> 2)) {
    if (closed & 1) drives.negative_rad_s[j] = kCreepTowardsClosedSwitch_rad_s;
    if (closed & 2) drives.positive_rad_s[j] = kCreepTowardsClosedSwitch_rad_s;
  }
}

// steps 2 to 4: the common factor and why
struct RateScale {
  fx::Unit scale;  // the common factor s to apply to J^-1 twist, in [0, 1]
  kin::SingularStatus status;
  uint8_t slowed_by;  // SlowReason bits
};

struct JointRates {
  fx::Real qd_rad_s[arm::kJoints];
  fx::Unit scale;  // the common factor s applied to J^-1 twist, in [0, 1]
  kin::SingularStatus status;
  uint8_t slowed_by;  // SlowReason bits
};

// the soft-limit zone, Angle counts: closer to a soft stop, the speed limit falls to 0 at the stop
constexpr int32_t kSoftLimitZoneCounts = fx::angle_deg(Ratio{config::kSoftLimitZone_deg, 1}).raw;

// one joint's limits, together: the loop over the joints then walks one table (a table per
// limit kept five pointers, which avr-gcc spilled to the stack)
struct JointMotionLimits {
  fx::Real speed_rad_s;
  fx::Angle soft_min;
  fx::Angle soft_max;
  int32_t brake_from;   // Angle counts: closer to a soft stop, braking limits the speed
  // closer than the larger of brake_from and the zone, near_stop_speed: as angles (a joint
  // moving up beyond near_max, or down below near_min), one comparison without the distance
  fx::Angle near_max;
  fx::Angle near_min;
  // the braking speed squared, (2^-10 rad/s)^2 per Angle count, Q8 rounded down (the braking
  // speed at most 3/4 a's): with brake_from < 2^16, v is one 16x16 product and a byte shift
  uint16_t brake_speed_sq_q8;
};
struct MotionLimits {
  JointMotionLimits joint[arm::kJoints];
};

// 2 (3/4) a in (2^-10 rad/s)^2 per Angle count, for a in rad/s^2 x 100
constexpr double brake_speed_sq_per_count(int16_t accel_crad_s2) {
  return 1.5 * accel_crad_s2 / 100.0 * 1048576.0 / kAngleCountsPerRad;
}
// v^2 / (2 (3/4) a): beyond it the joint brakes from its speed limit in time
constexpr int32_t brake_from_counts(int16_t speed_crad_s, int16_t accel_crad_s2) {
  return (int32_t)((speed_crad_s / 100.0) * (speed_crad_s / 100.0) / (1.5 * accel_crad_s2 / 100.0) * kAngleCountsPerRad) + 1;
}

constexpr int32_t near_from_counts(int32_t brake_from) { return brake_from > kSoftLimitZoneCounts ? brake_from : kSoftLimitZoneCounts; }

constexpr JointMotionLimits joint_motion_limits(uint8_t j) {
  using L = kin::JointLimits<Fixed>;
  return JointMotionLimits{
      fx::real(Ratio{config::kJointSpeedLimit_crad_s[j], 100}),
      fx::Angle{L::min[j].raw + fx::angle_deg(Ratio{config::kSoftLimitMargin_deg, 1}).raw},
      fx::Angle{L::max[j].raw - fx::angle_deg(Ratio{config::kSoftLimitMargin_deg, 1}).raw},
      brake_from_counts(config::kJointSpeedLimit_crad_s[j], config::kJointAccelLimit_crad_s2[j]),
      fx::Angle{L::max[j].raw - fx::angle_deg(Ratio{config::kSoftLimitMargin_deg, 1}).raw -
                near_from_counts(brake_from_counts(config::kJointSpeedLimit_crad_s[j], config::kJointAccelLimit_crad_s2[j]))},
      fx::Angle{L::min[j].raw + fx::angle_deg(Ratio{config::kSoftLimitMargin_deg, 1}).raw +
                near_from_counts(brake_from_counts(config::kJointSpeedLimit_crad_s[j], config::kJointAccelLimit_crad_s2[j]))},
      (uint16_t)(brake_speed_sq_per_count(config::kJointAccelLimit_crad_s2[j]) * 256.0)};
}
// the braking distance and the braking speed's factor in 16 bits for every joint (a scale,
// ~110 cycles with its shift by a run-time exponent, was what the configuration needed beyond)
constexpr bool braking_in_16_bits() {
  for (uint8_t j = 0; j < arm::kJoints; ++j) {
    if (brake_from_counts(config::kJointSpeedLimit_crad_s[j], config::kJointAccelLimit_crad_s2[j]) >= 65536) return false;
    if (brake_speed_sq_per_count(config::kJointAccelLimit_crad_s2[j]) * 256.0 >= 65536.0) return false;
  }
  return true;
}
static_assert(braking_in_16_bits(), "a joint's braking distance (speed^2 / 1.5 a) and 1.5 a per count x 256 fit 16 bits");

constexpr MotionLimits motion_limits() {
  return MotionLimits{{joint_motion_limits(0), joint_motion_limits(1), joint_motion_limits(2), joint_motion_limits(3),
                       joint_motion_limits(4), joint_motion_limits(5)}};
}

// clamp a Real to [0, 1] as a Unit
inline fx::Unit fraction(fx::Real r) {
  return r.raw <= 0 ? fx::Unit{0} : r.raw >= (fx::kUnitOne << 8) ? fx::Unit{(int16_t)fx::kUnitOne} : fx::to_unit(r);
}

inline fx::Unit smaller(fx::Unit a, fx::Unit b) { return a.raw < b.raw ? a : b; }

inline int16_t magnitude(fx::Unit u) { return u.raw < 0 ? (int16_t)-u.raw : u.raw; }

// f's rate takes it towards zero, faster than |f| / 32 s. A motion that leaves f unchanged (a
// pure wrist roll) still has a rate from J^-1's rounding, up to 3.4e-4 /s inside the elbow's
// slow band (RoundingOfAMotionThatLeavesTheElbowDoesNotStopIt); inside the damped band, where
// the slow-down's fraction is 0, any rate towards zero would stop the whole motion: the arm
// stuck. A rate below |f| / 32 s falls with f, so such a motion only creeps towards zero and
// never reaches it. |f| / 32 s in Q23 is the Q15 |f| shifted by 8 - 5.
inline bool moving_towards_zero(fx::Unit f, fx::Real rate) {
  if (rate.raw == 0 || (f.raw < 0) == (rate.raw < 0)) return false;
  return (rate.raw < 0 ? -rate.raw : rate.raw) > ((int32_t)magnitude(f) << 3);
}


// (|f| - damp) / (slow - damp) in [0, 1]
template <int32_t kDampRaw, int32_t kSlowRaw>
fx::Unit singular_fraction(fx::Unit f) {
  static constexpr fx::Real kInvWidth = fx::real(Ratio{32768, kSlowRaw - kDampRaw});
  return fraction(fx::Unit{(int16_t)(magnitude(f) - kDampRaw)} * kInvWidth);
}

// s x, where s = kUnitOne is 1 (what no limit asked for: most of the time) and x = 0 (most of
// a mode's twist: XY v.z and w, R1 v) needs no product (~70 cycles). As a product kUnitOne
// took 2^-15 of x off (0.003 %, below every tolerance the motion has).
inline fx::Real scaled(fx::Unit s, fx::Real x) { return s.raw == fx::kUnitOne || x.raw == 0 ? x : s * x; }

// the largest s in [0, 1] with scaled(s, |qd|) <= allowed, given the current s. The quotient
// is rounded down by two steps, more than the error of the table reciprocal and of the
// product, so the limit holds exactly rather than to within rounding. scaled(s, |qd|) never
// exceeds |qd| (s < 1, the product rounds down), so a speed within the limit needs no product.
// The quotient out of line: the joint loops that call limit_scale need it for a joint or two
// a pass at most, and keep their pointers in registers without it.
__attribute__((noinline)) inline fx::Unit slower_scale(fx::Real speed, fx::Real allowed) {
  const fx::Unit quotient = fraction(allowed * fx::reciprocal(speed));
  return fx::Unit{(int16_t)(quotient.raw > 2 ? quotient.raw - 2 : 0)};
}
inline fx::Unit limit_scale(fx::Unit s, fx::Real qd, fx::Real allowed) {
  const fx::Real speed{qd.raw < 0 ? -qd.raw : qd.raw};
  if (!(allowed < speed) || !(allowed < scaled(s, speed))) return s;
  return slower_scale(speed, allowed);
}

// (x + 8191) >> 13 modulo 2^32 (ceil(x / 2^13) below 2^32 - 8191) by whole bytes: the high
// half times 8 (a hardware product) and the low half's top three bits. A 32-bit shift by 13
// is a loop of 13 steps on the AVR (~95 cycles).
inline uint32_t ceil_shr13(uint32_t x) {
  fx::Word32 w;
  w.u = x + 8191u;
  return fx::mul_uu((uint16_t)w.h.hi, 8) + (uint16_t)(w.h.lo >> 13);
}

// Step 3 for a joint moving `distance` counts short of its soft stop, within the zone or the
// braking distance: its speed limit scaled down. Not inlined: the joint loop, which needs it
// for a few joints at most, keeps its registers.
// The braking speed's square root (~300 cycles) is taken only where it slows the joint. When
// the joint's speed at the current scale, moving = scaled(s, |qd|) (what
// limit_scale compares), is at most the braking speed, the zone's speed is returned instead:
// at least the braking speed, so at least moving. The caller's s and reason are the same as
// with the braking speed: limit_scale leaves s for any allowed >= moving, and a drive slower
// than moving is below both (kSlowDriveLoad either way).
__attribute__((noinline)) inline fx::Real near_stop_speed(const JointMotionLimits& limit, int32_t distance, fx::Unit s, fx::Real qd) {
  static constexpr fx::Real kInvZone = fx::real(Ratio{1, kSoftLimitZoneCounts});  // per angle count
  static_assert(kSoftLimitZoneCounts < 32768 && kInvZone.raw < 32768, "the soft-limit zone's fraction is a 16x16 product");
  fx::Real allowed = limit.speed_rad_s;
  if (distance < kSoftLimitZoneCounts) {
    // distance / zone as one 16x16 product (both fit 16 bits; at or past the stop, 0)
    allowed = distance <= 0 ? fx::Real{0}
                            : fraction(fx::Real{fx::mul_ss((int16_t)distance, (int16_t)kInvZone.raw)}) * allowed;
  }
  if (distance < limit.brake_from) {
    // brake = floor(sqrt(v)) 2^13 is below allowed exactly when v < ceil(allowed / 2^13)^2:
    // the square root (~300 cycles) only when it limits
    const uint32_t v = distance <= 0 ? 0 : fx::mul_uu((uint16_t)distance, limit.brake_speed_sq_q8) >> 8;
    const uint16_t allowed_q10 = (uint16_t)ceil_shr13((uint32_t)allowed.raw);
    if (v < fx::mul_uu(allowed_q10, allowed_q10)) {
      // floor(sqrt(v)) 2^13 >= moving exactly when v >= ceil(moving / 2^13)^2; a moving_q10
      // beyond 16 bits is faster than any braking speed (sqrt(v) < 2^16)
      const uint32_t moving_q10 = ceil_shr13((uint32_t)scaled(s, fx::Real{qd.raw < 0 ? -qd.raw : qd.raw}).raw);
      if (moving_q10 > 0xFFFFu || v < fx::mul_uu((uint16_t)moving_q10, (uint16_t)moving_q10)) {
        allowed = fx::Real{(int32_t)fx::isqrt32(v) << 13};
      }
    }
  }
  return allowed;
}

// The fastest a singular factor f may approach its damped band, d = |f| - damp away (Q15): it
// runs on at that rate for the lag tau (kSingularBrakeLag_ms) and then brakes at a' (3/4 of
// the deceleration the acceleration limits give it: elbow_braking_q12) to a stop at the band:
//   r tau + r^2 / (2 a') <= d,  so  r = sqrt((a' tau)^2 + 2 a' d) - a' tau.
// a' arrives as a_q12 (2^-12 /s^2); the rate is worked in 2^-10 /s, as near_stop_speed's.
constexpr uint16_t kSingularLagQ16 = (uint16_t)(config::kSingularBrakeLag_ms * 65536.0 / 4000.0);  // a_q12 -> a' tau in 2^-10 /s
static_assert(config::kSingularBrakeLag_ms < 4000, "a' tau as a 16-bit fraction of a_q12");
inline fx::Real singular_approach_rate(int16_t d_q15, uint16_t a_q12) {
  if (d_q15 <= 0) return fx::Real{0};
  const uint32_t two_a_d = fx::mul_uu(a_q12, (uint16_t)d_q15) >> 6;  // 2 a' d: 2^-26 -> (2^-10)^2
  const uint16_t lag_q10 = (uint16_t)(fx::mul_uu(a_q12, kSingularLagQ16) >> 16);
  const uint16_t r_q10 = (uint16_t)(fx::isqrt32(two_a_d + fx::mul_uu(lag_q10, lag_q10)) - lag_q10);
  return fx::Real{(int32_t)r_q10 << 13};
}
// The elbow's braking deceleration a' = 3/4 |c3| a, in 2^-12 /s^2, at least one step. a is J3's
// acceleration limit, or less where another joint's limit is smaller for its speed: the
// acceleration limit changes every joint's speed by one common factor (joint_acceleration.h),
// so the motion brakes at the pace of the joint with the least a_j / |qd_j|, and J3 then at
// a_j |qd3| / |qd_j| (J1, at 0.5 rad/s^2, turning at 0.3 rad/s with J3 at 0.7: 1.2 rad/s^2
// instead of 3). qd: J^-1's joint speeds (their ratios are what matter); a reciprocal only for
// a joint that lowers a. Where J3 hardly turns a' is small, but so is the elbow's rate: the
// floor keeps such a motion (the drift correction's, a J6 roll's) from reading as one that
// cannot brake at all.
inline uint16_t elbow_braking_q12(fx::Unit c3, const fx::Real* qd) {
  static constexpr double kQ12 = 0.75 * 4096 / 100.0;  // 3/4 of a limit given in rad/s^2 x 100, Q12
  static_assert(kQ12 * 2000 < 65536, "3/4 of any acceleration limit (<= 20 rad/s^2) in 16 bits, Q12");
  static constexpr uint16_t kA_q12[arm::kJoints] = {
      (uint16_t)(kQ12 * config::kJointAccelLimit_crad_s2[0]), (uint16_t)(kQ12 * config::kJointAccelLimit_crad_s2[1]),
      (uint16_t)(kQ12 * config::kJointAccelLimit_crad_s2[2]), (uint16_t)(kQ12 * config::kJointAccelLimit_crad_s2[3]),
      (uint16_t)(kQ12 * config::kJointAccelLimit_crad_s2[4]), (uint16_t)(kQ12 * config::kJointAccelLimit_crad_s2[5])};
  const uint32_t qd3 = (uint32_t)(qd[2].raw < 0 ? -qd[2].raw : qd[2].raw);
  uint16_t a = kA_q12[2];
  for (uint8_t j = 0; j < arm::kJoints; ++j) {
    const uint32_t qdj = (uint32_t)(qd[j].raw < 0 ? -qd[j].raw : qd[j].raw);
    // a_j |qd3| / |qd_j| < a  <=>  a_j |qd3| < a |qd_j| (both sides / 2^16)
    if (j == 2 || fx::mul_hi_u32xu16(qd3, kA_q12[j]) >= fx::mul_hi_u32xu16(qdj, a)) continue;
    const fx::Real ratio = fx::Real{(int32_t)qd3} * fx::reciprocal(fx::Real{(int32_t)qdj});  // < a / a_j <= 40
    a = (uint16_t)(fx::mul_hi_u32xu16((uint32_t)ratio.raw, kA_q12[j]) >> 7);  // Q23 x Q12 -> Q12
  }
  const uint16_t braking = (uint16_t)(fx::mul_uu((uint16_t)magnitude(c3), a) >> 15);
  return braking > 0 ? braking : 1;
}
// Where the elbow's braking may begin: |sin q3| below 0.43 (|c3| >= 0.9). From J3's top
// speed at its own limit it needs 0.35 (the lag, the braking and the damped band); where
// another joint's limit sets the pace (elbow_braking_q12) it needs more, and J3 then turns the
// slower for it.
constexpr int32_t kElbowBrakingFromRaw = fx::unit(Ratio{43, 100}).raw;
constexpr bool elbow_braking_from_j3_speed_fits() {
  constexpr double a = 0.75 * 0.9 * config::kJointAccelLimit_crad_s2[2] / 100.0;
  constexpr double v = config::kJointSpeedLimit_crad_s[2] / 100.0;
  return (arm::kSingularBands.damp_s3.num / (double)arm::kSingularBands.damp_s3.den + v * config::kSingularBrakeLag_ms / 1000.0 +
          v * v / (2 * a)) * 32768.0 < kElbowBrakingFromRaw;
}
static_assert(elbow_braking_from_j3_speed_fits(), "the elbow brakes from J3's top speed within |sin q3| < 0.43");

// Step 2 for J^-1 twist (inv): the singular slow-down's factor (1: none)
template <class Trig>
fx::Unit singular_scale(const kin::JointAngles<Fixed>& q, const Trig& t, const kin::JacobianInverse<Fixed>& inv) {
  static constexpr fx::Unit kA2 = fx::unit(arm::a2), kA3 = fx::unit(arm::a3), kA4 = fx::unit(arm::a4);
  static constexpr int32_t kDampC5 = fx::unit(arm::kSingularBands.damp_c5).raw;
  static constexpr int32_t kSlowC5 = fx::unit(arm::kSingularBands.slow_c5).raw;
  static constexpr int32_t kDampS3 = fx::unit(arm::kSingularBands.damp_s3).raw;
  static constexpr int32_t kSlowS3 = fx::unit(arm::kSingularBands.slow_s3).raw;
  static constexpr int32_t kDampR5 = fx::unit(arm::kSingularBands.damp_r5_m).raw;
  static constexpr int32_t kSlowR5 = fx::unit(arm::kSingularBands.slow_r5_m).raw;

  const fx::Real* qd = inv.qd_rad_s;
  const auto& f = inv.factors;
  // singular factors moving towards zero (each rate only inside its slow band: away from the
  // singularities, most of the time, it is not needed)
  fx::Unit singular{(int16_t)fx::kUnitOne};
  if (magnitude(f.c5) < kSlowC5 && moving_towards_zero(f.c5, -(t.s5 * qd[4]))) {
    singular = smaller(singular, singular_fraction<kDampC5, kSlowC5>(f.c5));
  }
  static_assert(kElbowBrakingFromRaw >= kSlowS3, "the elbow brakes from the slow band or before it");
  if (magnitude(f.s3) < kElbowBrakingFromRaw) {
    const fx::Unit c3 = fx::sincos(q.q[2]).c;
    const fx::Real rate = c3 * qd[2];
    if (moving_towards_zero(f.s3, rate)) {
      if (magnitude(f.s3) < kSlowS3) singular = smaller(singular, singular_fraction<kDampS3, kSlowS3>(f.s3));
      singular = limit_scale(singular, rate, singular_approach_rate((int16_t)(magnitude(f.s3) - kDampS3), elbow_braking_q12(c3, qd)));
    }
  }
  if (magnitude(f.r5) < kSlowR5) {
    const fx::Real qd23 = qd[1] + qd[2];
    const fx::Real r5_rate = -((t.s2 * kA2) * qd[1] + (t.s23 * kA3) * qd23 + (t.s234 * kA4) * (qd23 + qd[3]));
    if (moving_towards_zero(f.r5, r5_rate)) singular = smaller(singular, singular_fraction<kDampR5, kSlowR5>(f.r5));
  }
  return singular;
}

// Steps 3 and 4 for J^-1 twist (inv), given step 2's factor: the common factor s, which the
// caller applies (scaled(s, qd_j) for each joint: the firmware in its acceleration limit's pass
// over the joints, without a pass of its own)
inline RateScale joint_rate_scale(fx::Unit singular, const kin::JointAngles<Fixed>& q, const kin::JacobianInverse<Fixed>& inv,
                                  const MotionLimits& limits, const DriveSpeeds& drives) {
  const fx::Real* qd = inv.qd_rad_s;
  RateScale out;
  out.status = inv.status;
  out.slowed_by = singular.raw < fx::kUnitOne ? kSlowSingular : 0;
  fx::Unit s = singular;
  for (uint8_t j = 0; j < arm::kJoints; ++j) {
    const JointMotionLimits& limit = limits.joint[j];
    fx::Real allowed = limit.speed_rad_s;
    // (distance < near_from, the distance soft_max - q or q - soft_min, as q beyond near_max
    // or near_min: the same integers, without the subtraction where it is not needed)
    const int32_t a = q.q[j].raw;
    if (qd[j].raw > 0 ? a > limit.near_max.raw : qd[j].raw < 0 && a < limit.near_min.raw) {
      allowed = near_stop_speed(limit, qd[j].raw > 0 ? limit.soft_max.raw - a : a - limit.soft_min.raw, s, qd[j]);
    }
    uint8_t reason = allowed < limit.speed_rad_s ? kSlowSoftLimit : kSlowJointSpeed;
    const fx::Real drive = qd[j].raw >= 0 ? drives.positive_rad_s[j] : drives.negative_rad_s[j];
    if (drive < allowed) {
      allowed = drive;
      reason = kSlowDriveLoad;  // (or a closed switch's creep: named_switch_stop)
    }
    const fx::Unit before = s;
    s = limit_scale(s, qd[j], allowed);
    if (s.raw < before.raw) out.slowed_by |= reason;
  }

  out.scale = s;
  return out;
}

// Steps 2 to 4
template <class Trig>
RateScale rate_scale(const kin::JointAngles<Fixed>& q, const Trig& t, const kin::JacobianInverse<Fixed>& inv,
                     const MotionLimits& limits, const DriveSpeeds& drives) {
  return joint_rate_scale(singular_scale(q, t, inv), q, inv, limits, drives);
}

// rate_scale counts a closed switch's creep as a drive's speed (kSlowDriveLoad). A joint whose
// J^-1 speed runs into its closed switch faster than the creep is the one that binds (the
// factor falls to the creep's share): the switch is named instead. Out of rate_scale's joint
// loop (it cost that loop ~70 cycles a pass): called only while a switch is closed.
__attribute__((cold, noinline)) inline uint8_t named_switch_stop(uint8_t slowed_by, const kin::JacobianInverse<Fixed>& inv, uint16_t closed) {
  for (uint8_t j = 0; j < arm::kJoints; ++j, closed = (uint16_t)(closed >> 2)) {
    const int32_t qd = inv.qd_rad_s[j].raw;
    if (((closed & 2) && qd > kCreepTowardsClosedSwitch_rad_s.raw) || ((closed & 1) && -qd > kCreepTowardsClosedSwitch_rad_s.raw)) {
      return (uint8_t)((slowed_by & ~kSlowDriveLoad) | kSlowLimitSwitch);
    }
  }
  return slowed_by;
}

// drives at the joints' speed limits: they never slow a joint (allowed is at most the limit)
inline DriveSpeeds drives_at_speed_limits(const MotionLimits& limits) {
  DriveSpeeds d;
  for (uint8_t j = 0; j < arm::kJoints; ++j) d.positive_rad_s[j] = d.negative_rad_s[j] = limits.joint[j].speed_rad_s;
  d.closed_switches = 0;
  return d;
}

// Steps 1 to 4: the joint velocities, scaled (without drives: none slows a joint)
template <class Trig>
JointRates resolved_rate(const kin::JointAngles<Fixed>& q, const Trig& t, const kin::TwistWrist<Fixed>& twist,
                         const MotionLimits& limits, const DriveSpeeds* drives = nullptr) {
  const auto inv = kin::inverse_jacobian_wrist<Fixed>(t, twist);
  const RateScale r = rate_scale(q, t, inv, limits, drives ? *drives : drives_at_speed_limits(limits));
  JointRates out;
  out.slowed_by = drives && drives->closed_switches ? named_switch_stop(r.slowed_by, inv, drives->closed_switches) : r.slowed_by;
  for (uint8_t j = 0; j < arm::kJoints; ++j) out.qd_rad_s[j] = scaled(r.scale, inv.qd_rad_s[j]);
  out.scale = r.scale;
  out.status = r.status;
  return out;
}

}  // namespace core
}  // namespace wmra
