// Exhaustive and sweep tests of the fixed-point primitives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "kinematics/fixed_trig.h"

using namespace wmra::fx;

namespace {
double value(Recip k) { return (k.negative ? -1 : 1) * k.mantissa / 65536.0 * k.scale; }
}  // namespace

TEST(FixedTrig, SinCosOverEveryAngleOfTheCircle) {
  double worst = 0;
  for (int32_t raw = 0; raw < kAngleTurn; ++raw) {
    const double a = to_radians(Angle{raw});
    const SinCos sc = sincos(Angle{raw});
    worst = std::max({worst, std::abs(to_double(sc.s) - std::sin(a)), std::abs(to_double(sc.c) - std::cos(a))});
    ASSERT_EQ(sin(Angle{raw}).raw, sc.s.raw);
  }
  std::printf("sin/cos worst absolute error over %d angles: %.2e\n", kAngleTurn, worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(FixedTrig, SineTableEntriesAreRoundedSines) {
  const int16_t* t = sin_table();
  for (int i = 0; i < 258; ++i) {
    const double exact = std::sin(kPi / 2 * std::min(i, 256) / 256.0) * 32768.0;
    EXPECT_EQ(t[i], (int16_t)std::min(32767.0, std::floor(exact + 0.5))) << i;
  }
}

TEST(FixedReciprocal, TableEntriesAreRoundedHalfReciprocals) {
  const uint16_t* t = half_reciprocal_table();
  for (int i = 0; i <= 256; ++i) {
    const double exact = 65536.0 / (2 * (0.5 + i / 512.0));
    EXPECT_EQ(t[i], (uint16_t)std::min(65535.0, std::floor(exact + 0.5))) << i;
  }
}

TEST(FixedReciprocal, ProductOfReciprocals) {
  const Recip a = recip_constant(wmra::Ratio{350, 1000}), b = reciprocal(Unit{-12345});
  EXPECT_NEAR(value(a * b), 1 / 0.35 * (32768.0 / -12345), 1e-4 * std::abs(value(a * b)));
  const Recip big = recip_constant(wmra::Ratio{1, 64});
  EXPECT_NEAR(value(big * recip_constant(wmra::Ratio{2, 1})), 32.0, 1e-4);
  EXPECT_EQ(value(big * big), value(Recip{65535, kRecipMaxScale, false}));  // saturated
}

TEST(FixedReciprocal, ConstantsAreRounded) {
  for (const wmra::Ratio c : {wmra::Ratio{350, 1000}, wmra::Ratio{3, 1}, wmra::Ratio{1, 100}, wmra::Ratio{1, 1}}) {
    const Recip k = recip_constant(c);
    if (1.0 / wmra::to_double(c) >= 0.5) {
      EXPECT_GE(k.mantissa, 32768);  // smaller values keep scale 1
    }
    EXPECT_NEAR(value(k) * wmra::to_double(c), 1.0, 1.0 / 32768);
  }
  EXPECT_EQ(value(recip_constant(wmra::Ratio{1, 400})), value(Recip{65535, kRecipMaxScale, false}));
}

TEST(FixedTrig, AnglesWrapAcrossTurns) {
  for (int32_t raw : {-3 * kAngleTurn + 1234, -1, 5 * kAngleTurn - 77}) {
    const int32_t in_turn = ((raw % kAngleTurn) + kAngleTurn) % kAngleTurn;
    EXPECT_EQ(sincos(Angle{raw}).s.raw, sincos(Angle{in_turn}).s.raw);
    EXPECT_EQ(sincos(Angle{raw}).c.raw, sincos(Angle{in_turn}).c.raw);
  }
}

TEST(FixedTrig, Atan2OverTheCircleAndManyRadii) {
  double worst = 0;
  for (double radius : {1e-4, 0.01, 0.3, 1.0, 100.0}) {
    for (int k = 0; k < 36000; ++k) {
      const double a = -kPi + (2 * kPi) * k / 36000.0;
      const int32_t y = real(radius * std::sin(a)).raw, x = real(radius * std::cos(a)).raw;
      const double expected = std::atan2((double)y, (double)x);
      double err = std::abs(to_radians(atan2(y, x)) - expected);
      err = std::min(err, 2 * kPi - err);
      worst = std::max(worst, err);
    }
  }
  std::printf("atan2 worst error: %.2e rad\n", worst);
  EXPECT_LT(worst, 1e-4);
  EXPECT_EQ(atan2(0, 0).raw, 0);
}

TEST(FixedReciprocal, EveryUnitValue) {
  double worst = 0;
  for (int32_t raw = -32767; raw <= 32767; ++raw) {
    if (raw == 0) continue;
    const Recip k = reciprocal(Unit{(int16_t)raw});
    if (std::abs(raw) < 256) {  // |x| < 2^-7: saturated at the largest Recip
      EXPECT_EQ(value(k), (raw < 0 ? -1 : 1) * value(Recip{65535, kRecipMaxScale, false})) << raw;
      continue;
    }
    worst = std::max(worst, std::abs(value(k) / (32768.0 / raw) - 1));
  }
  std::printf("reciprocal worst relative error: %.2e\n", worst);
  EXPECT_LT(worst, 5e-5);
}

TEST(FixedReciprocal, DampedIsContinuousBoundedAndOdd) {
  const DampedBand band = damped_band(unit(wmra::Ratio{5, 100}));
  auto damped = [&](int16_t raw) { return value(damped_reciprocal(Unit{raw}, band)); };
  double previous = damped(-4000), max_step = 0, max_abs = 0;
  for (int raw = -3999; raw <= 4000; ++raw) {
    const double v = damped((int16_t)raw);
    max_step = std::max(max_step, std::abs(v - previous));
    max_abs = std::max(max_abs, std::abs(v));
    EXPECT_NEAR(v, -damped((int16_t)-raw), 1e-9);
    previous = v;
  }
  EXPECT_EQ(damped(0), 0.0);
  EXPECT_LT(max_abs, 1 / 0.05 * 1.001);
  // one Q15 step times the steepest slope 1/eps^2 = 400 is 0.0122, plus reciprocal rounding
  EXPECT_LT(max_step, 0.015);
}

// The Unit * Real products leave out the product of the low bytes (fixed_point.h): they are
// the floor of that difference, so at most two steps below the exact floor (four for dot).
TEST(FixedPoint, ProductsLeaveOutOnlyTheLowBytes) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> x(INT32_MIN / 2, INT32_MAX / 2);
  std::uniform_int_distribution<int> c(-32767, 32767);
  auto low = [](int32_t v, int32_t w) { return (double)(v & 0xFF) * (w & 0xFF); };
  for (int n = 0; n < 200000; ++n) {
    const int32_t a = x(rng), y = x(rng);
    const int16_t b = (int16_t)c(rng), d = (int16_t)c(rng);
    const double exact = std::floor((double)a * b / 32768.0);
    const int32_t p = mul_q15(a, b);
    ASSERT_EQ(p, (int32_t)std::floor(((double)a * b - low(a, b)) / 32768.0));
    ASSERT_EQ(mul_q15_const(a, b), p);  // the compile-time form
    ASSERT_LE(p, exact);
    ASSERT_GE(p, exact - 2);
    const int32_t s = dot_q15(b, a, d, y);
    ASSERT_EQ(s, (int32_t)std::floor(((double)a * b - low(a, b) + (double)y * d - low(y, d)) / 32768.0));
    ASSERT_GE(s, std::floor(((double)a * b + (double)y * d) / 32768.0) - 4);
    const Recip k{(uint16_t)(b + 32768), (uint8_t)(1 << (n & 7)), d < 0};
    const double q = std::floor(((double)a * k.mantissa - low(a, k.mantissa)) / 65536.0) * k.scale;
    const double limited = std::max<double>(-kRecipProductLimit, std::min<double>(kRecipProductLimit, q));
    ASSERT_EQ((Real{a} * k).raw, (int32_t)(k.negative ? -limited : limited));
  }
}

TEST(FixedPoint, UnitProductRoundsToNearest) {
  for (int a = -32767; a <= 32767; a += 7) {
    for (int b : {-32767, -20000, -255, -1, 0, 1, 255, 12345, 32767}) {
      const double exact = (double)a * b / 32768.0;
      EXPECT_LE(std::abs((Unit{(int16_t)a} * Unit{(int16_t)b}).raw - exact), 0.5 + 1e-9) << a << " " << b;
    }
  }
}

TEST(FixedMath, IntegerSquareRoot) {
  std::mt19937 rng(6);
  for (int n = 0; n < 100000; ++n) {
    const uint32_t v = rng();
    const uint32_t r = isqrt32(v);
    ASSERT_LE((uint64_t)r * r, v);
    ASSERT_GT((uint64_t)(r + 1) * (r + 1), v);
  }
  for (uint32_t v = 0; v < (1u << 18); ++v) {  // small values, and every square and its neighbours below 2^18
    const uint32_t r = isqrt32(v);
    ASSERT_LE((uint64_t)r * r, v);
    ASSERT_GT((uint64_t)(r + 1) * (r + 1), v);
  }
  for (uint32_t r = 1; r < 65536; ++r) {
    const uint32_t sq = r * r;
    ASSERT_EQ(isqrt32(sq), r);
    ASSERT_EQ(isqrt32(sq - 1), r - 1);
  }
  EXPECT_EQ(isqrt32(0), 0);
  EXPECT_EQ(isqrt32(0xFFFFFFFFu), 65535);
}

// 1/x of a positive Real (the resolved-rate speed limits divide by joint speeds this way):
// relative error within 1e-4 up to x = 2; above, a Recip holds 1/x < 0.5 as a mantissa
// below 2^15 with no negative scale, so the error is within one step of 2^-16 besides.
// Saturated at 128 below x = 2^-7.
TEST(FixedReciprocal, PositiveRealValues) {
  double worst = 0;
  for (double x = 1.0 / 128; x < 250; x *= 1.0007) {
    const Recip k = reciprocal(real(x));
    const double exact = 1 / to_double(real(x));
    const double error = std::abs(k.mantissa / 65536.0 * k.scale - exact);
    worst = std::max(worst, error / (1e-4 * exact + 1.0 / 65536));
  }
  std::printf("reciprocal of a Real over [2^-7, 250]: worst error %.2f of its bound\n", worst);
  EXPECT_LT(worst, 1.0);
  const Recip tiny = reciprocal(Real{1000});
  EXPECT_EQ(tiny.scale, kRecipMaxScale);
  EXPECT_EQ(tiny.mantissa, 65535);
}
