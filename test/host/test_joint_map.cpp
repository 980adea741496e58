// firmware/core/joint_map.h: the stepper joints' angle <-> step conversions over each joint's
// range, against exact arithmetic.
#include <gtest/gtest.h>

#include <cmath>

#include "config/joints_config.h"
#include "core/joint_map.h"
#include "advance_vectors.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;

constexpr int kStepperJoint[3] = {0, 4, 5};  // J1, J5, J6 (config::kStepsPerJointTurn order)

// A reference taken from the step count (entering running, after homing or a joint move) must
// ask for no step: steps(angle(n)) == n for every step count within the joint's limits.
TEST(StepperMap, StepsOfTheAngleOfAStepCountIsThatCount) {
  for (int i = 0; i < 3; ++i) {
    const uint32_t per_turn = config::kStepsPerJointTurn[i];
    const core::StepperMap map = core::StepperMap::make(per_turn);
    const int j = kStepperJoint[i];
    const int32_t lo = (int32_t)std::floor(arm::q_min_rad(j) / (2 * arm::kPi) * per_turn);
    const int32_t hi = (int32_t)std::ceil(arm::q_max_rad(j) / (2 * arm::kPi) * per_turn);
    int32_t wrong = 0, first_wrong = 0;
    int32_t inexact = 0;  // angles further from the exact one than a count and Scale's 2^-14
    for (int32_t n = lo; n <= hi; ++n) {
      const fx::Angle a = map.angle(n);
      const double exact = (double)n * fx::kAngleTurn / per_turn;
      if (std::fabs(a.raw - exact) > 1 + std::fabs(exact) / 16384) ++inexact;
      if (map.steps(a) != n && wrong++ == 0) first_wrong = n;
    }
    EXPECT_EQ(wrong, 0) << "J" << j + 1 << ", first at " << first_wrong << " steps";
    EXPECT_EQ(inexact, 0) << "J" << j + 1;
  }
}

// steps() is the nearest step to any angle, not the one below it
TEST(StepperMap, StepsOfAnAngleIsTheNearestStep) {
  for (int i = 0; i < 3; ++i) {
    const uint32_t per_turn = config::kStepsPerJointTurn[i];
    const core::StepperMap map = core::StepperMap::make(per_turn);
    const int j = kStepperJoint[i];
    const int32_t lo = (int32_t)(arm::q_min_rad(j) / (2 * arm::kPi) * fx::kAngleTurn);
    const int32_t hi = (int32_t)(arm::q_max_rad(j) / (2 * arm::kPi) * fx::kAngleTurn);
    // excess: beyond half a step, one angle count (half_step is whole counts) and Scale's 2^-14
    double worst_steps = 0, worst_excess = 0;
    for (int32_t a = lo; a <= hi; a += 7) {
      const double exact = (double)a * per_turn / fx::kAngleTurn;
      const double error = std::fabs(map.steps(fx::Angle{a}) - exact);
      worst_steps = std::max(worst_steps, error);
      worst_excess = std::max(worst_excess, error - 0.5 - (double)per_turn / fx::kAngleTurn - std::fabs(exact) / 16384);
    }
    EXPECT_LE(worst_excess, 0) << "J" << j + 1 << ", worst " << worst_steps << " steps";
    EXPECT_GE(worst_steps, 0.45) << "J" << j + 1 << ": a stride of 7 counts meets half-step points";
  }
}

}  // namespace

namespace {

// apply(s, x) is one 32x16 product and a shift, written for the AVR as bytes (joint_map.h):
// against the plain formula in 64-bit arithmetic, floor((x m - lo8(x) lo8(m)) 2^(e - 15)), with a
// left shift wrapping in 32 bits as the single shift it replaces did, over random operands and
// every exponent the firmware's scales can have. Counter-based, seeded: deterministic.
TEST(Scale, ApplyIsTheProductShiftedOnce) {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&state]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(state >> 32);
  };
  int wrong = 0;
  for (int n = 0; n < 200000; ++n) {
    const int32_t x = (int32_t)next() >> (n % 24);
    const core::Scale s{(int16_t)(16384 + (next() & 16383)), (int8_t)(n % 33 - 24)};  // e in [-24, 8]
    const int64_t product = (int64_t)x * s.m - (int64_t)(x & 0xFF) * (s.m & 0xFF);
    const int32_t want = s.e >= 0 ? (int32_t)((uint32_t)(int32_t)(product >> 15) << s.e) : (int32_t)(product >> (15 - s.e));
    if (core::apply(s, x) != want && wrong++ < 5) ADD_FAILURE() << "x " << x << " m " << s.m << " e " << (int)s.e;
  }
  EXPECT_EQ(wrong, 0);
}

// scale_for_ratio in 32 bits (a long division for the mantissa) against its formula in 64-bit
// arithmetic, m = floor((n 2^16 + d) / (2 d)) once num / den is normalised to [0.5, 1), over
// random ratios of every size (num, den < 2^31), the calibrations' (units over Angle counts and
// back) and the mantissas that round up to 2^15 (the exponent's carry). Seeded: deterministic.
core::Scale scale_want(uint32_t num, uint32_t den) {
  int8_t e = 0;
  uint64_t n = num, d = den;
  while (n >= d) {
    d <<= 1;
    ++e;
  }
  while (2 * n < d) {
    n <<= 1;
    --e;
  }
  const uint64_t m = ((n << 16) + d) / (2 * d);
  return m >= 32768 ? core::Scale{16384, (int8_t)(e + 1)} : core::Scale{(int16_t)m, e};
}
TEST(Scale, ForRatioIsTheRoundedRatio) {
  vectors::Lcg rng{2113u};
  int wrong = 0, carries = 0;
  auto check = [&](uint32_t num, uint32_t den) {
    const core::Scale got = core::scale_for_ratio(num, den), want = scale_want(num, den);
    if (want.m == 16384 && got.m == 16384) ++carries;
    if ((got.m != want.m || got.e != want.e) && wrong++ < 5)
      ADD_FAILURE() << num << " / " << den << ": m " << got.m << " e " << (int)got.e << ", want " << want.m << " " << (int)want.e;
  };
  for (int n = 0; n < 400000; ++n) {
    const uint32_t num = (rng.next() & 0x7FFFFFFFu) >> (n % 31), den = (rng.next() & 0x7FFFFFFFu) >> ((n / 31) % 31);
    check(num | 1u, den | 1u);
  }
  for (uint32_t units = 1; units < 16384; ++units) {
    check(units, 233017u);
    check(233017u, units);
  }
  for (uint32_t den = 65537; den < 65537 + 4096; ++den) check(den - 1, den);  // m rounds up to 2^15
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(carries, 1000);
}

// the 64-bit formula of apply() (above)
int32_t applied(core::Scale s, int32_t x) {
  const int64_t product = (int64_t)x * s.m - (int64_t)(x & 0xFF) * (s.m & 0xFF);
  return s.e >= 0 ? (int32_t)((uint32_t)(int32_t)(product >> 15) << s.e) : (int32_t)(product >> (15 - s.e));
}
int16_t units_want(const core::PotMap& map, fx::Angle a) {
  const int32_t u = map.units_at_min + applied(map.units_per_angle, a.raw - map.q_min.raw);
  return (int16_t)(u > 16383 ? 16383 : u < -16384 ? -16384 : u);
}

// PotMap::units shifts by constants for the exponents of the plausible calibrations (-3, -4),
// by apply() for any other: the same as apply() for every exponent, over random angles and
// calibrations (a bad calibration must still convert right). Seeded: deterministic.
TEST(PotMap, UnitsIsApplyForEveryExponent) {
  vectors::Lcg rng{1511u};
  int wrong = 0;
  for (int n = 0; n < 400000; ++n) {
    const core::Scale s{(int16_t)(16384 + (rng.next() & 16383)), (int8_t)(n % 33 - 24)};  // e in [-24, 8]
    const core::PotMap map{fx::Angle{(int32_t)rng.next() >> 12}, (int32_t)(rng.next() & 16383), s, s};
    const fx::Angle a{(int32_t)rng.next() >> (n % 24)};
    if (map.units(a) != units_want(map, a) && wrong++ < 5) ADD_FAILURE() << "a " << a.raw << " m " << s.m << " e " << (int)s.e;
  }
  EXPECT_EQ(wrong, 0);
}

// The plausible calibrations (settings.cpp: spans of 600 to 1023 counts) of J2-J4 have the
// exponents units() shifts by constants, and convert as apply() over the joint's range.
TEST(PotMap, PlausibleCalibrationsTakeTheConstantShifts) {
  for (int j = 1; j <= 3; ++j) {
    const fx::Angle q_min = fx::angle_deg(Ratio{arm::q_min_deg[j], 1}), q_max = fx::angle_deg(Ratio{arm::q_max_deg[j], 1});
    for (int32_t span = 600 * 16; span <= 1023 * 16; span += 16) {
      const int32_t at_min = (1023 * 16 - span) / 2;
      const core::PotMap map = core::PotMap::make(q_min, q_max, at_min, at_min + span);
      const int8_t e = map.units_per_angle.e;
      ASSERT_TRUE(e == -3 || e == -4) << "J" << j + 1 << " span " << span << ": e " << (int)e;
      int wrong = 0;
      for (int32_t a = q_min.raw - 4096; a <= q_max.raw + 4096; a += 97)
        if (map.units(fx::Angle{a}) != units_want(map, fx::Angle{a})) ++wrong;
      ASSERT_EQ(wrong, 0) << "J" << j + 1 << " span " << span;
    }
  }
}

}  // namespace

namespace {

// JointReferences::advance_all, whose AVR asm test/avr/kinematics/fixed_products_avr.cpp checks against the
// same 64-bit reference: the portable twin over 10^7 seeded joint steps (every 8th velocity an
// extreme), of one tick and of two in turn, angles within +-2^30 (the twin's sum is a signed one).
TEST(JointReferences, AdvanceAllIsTheReferenceStep) {
  vectors::Lcg rng{20261122u};
  core::JointReferences refs{};
  int wrong = 0;
  uint32_t n = 0;
  for (int round = 0; round < 10000000 / 6 + 1; ++round) {
    vectors::AdvancedJoint want[6];
    for (uint8_t j = 0; j < 6; ++j) {
      refs.q.q[j].raw = (int32_t)rng.next() >> 2;
      refs.fraction[j] = (uint16_t)rng.next();
      refs.qd_rad_s[j].raw = vectors::advance_velocity(rng, n++);
      want[j] = vectors::reference_advance(refs.q.q[j].raw, refs.fraction[j], refs.qd_rad_s[j].raw, round % 2);
    }
    refs.advance_all(round % 2);
    for (uint8_t j = 0; j < 6; ++j) {
      if ((refs.q.q[j].raw != want[j].q || refs.fraction[j] != want[j].fraction) && wrong++ < 5) {
        ADD_FAILURE() << "joint " << (int)j << " qd " << refs.qd_rad_s[j].raw << ": " << refs.q.q[j].raw << " / "
                      << refs.fraction[j] << ", want " << want[j].q << " / " << want[j].fraction;
      }
    }
  }
  EXPECT_EQ(wrong, 0);
}

// A step of two ticks rounds once where two steps of one round twice: over n such steps the
// angle (Q16, fraction included) is the one-tick steps' to within n / 2^16 of a count, never
// behind them (floor(2x) >= 2 floor(x)).
TEST(JointReferences, TwoTickStepsFollowTheOneTickSteps) {
  vectors::Lcg rng{2611u};
  int wrong = 0;
  for (uint32_t n = 0; n < 200000; ++n) {
    const uint8_t pairs = (uint8_t)(1 + n % 8);
    core::JointReferences two{}, one{};
    two.q.q[0].raw = one.q.q[0].raw = (int32_t)rng.next() >> 2;
    two.fraction[0] = one.fraction[0] = (uint16_t)rng.next();
    two.qd_rad_s[0].raw = one.qd_rad_s[0].raw = vectors::advance_velocity(rng, n) >> 4;
    for (uint8_t i = 0; i < pairs; ++i) {
      two.advance_all(true);
      one.advance_all();
      one.advance_all();
    }
    const int64_t ahead_q16 = (((int64_t)two.q.q[0].raw << 16) + two.fraction[0]) - (((int64_t)one.q.q[0].raw << 16) + one.fraction[0]);
    if ((ahead_q16 < 0 || ahead_q16 > pairs) && wrong++ < 5) {
      ADD_FAILURE() << "qd " << one.qd_rad_s[0].raw << " over " << 2 * pairs << " ticks: " << ahead_q16 << " / 2^16 counts ahead";
    }
  }
  EXPECT_EQ(wrong, 0);
}

// motion_tick integrates the `ticks` since its last pass in steps of two ticks and an odd one:
// the same as all of those steps at once, floor((the steps' sum + fraction) / 2^16)
TEST(JointReferences, StepsAtATimeAreTheStepsAtOnce) {
  vectors::Lcg rng{77u};
  int wrong = 0;
  for (uint32_t n = 0; n < 200000; ++n) {
    core::JointReferences refs{};
    const uint8_t ticks = (uint8_t)(1 + n % 6);
    const int32_t qd = vectors::advance_velocity(rng, n) >> 4;
    const int32_t q0 = (int32_t)rng.next() >> 2;
    const uint16_t f0 = (uint16_t)rng.next();
    refs.q.q[0].raw = q0;
    refs.fraction[0] = f0;
    refs.qd_rad_s[0].raw = qd;
    refs.advance_ticks(ticks);
    const int64_t sum_q16 = (int64_t)core::apply(core::kRateToAngleQ16PerTwoTicks, qd) * (ticks / 2) +
                            core::apply(core::kRateToAngleQ16PerTick, qd) * (ticks % 2) + f0;
    if ((refs.q.q[0].raw != q0 + (int32_t)(sum_q16 >> 16) || refs.fraction[0] != (uint16_t)sum_q16) && wrong++ < 5) {
      ADD_FAILURE() << "qd " << qd << " ticks " << (int)ticks;
    }
  }
  EXPECT_EQ(wrong, 0);
}

}  // namespace
