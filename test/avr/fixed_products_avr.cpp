// Checks the hand-written AVR arithmetic on the chip against int64 arithmetic and the plain-C
// formulas of the headers: prints one line per mismatch and "mismatches N" at the end.
#include "advance_vectors.h"
#include "kinematics/fixed_trig.h"
#include "kinematics_vectors.h"
#include "probe.h"

using namespace wmra;

namespace {
volatile int64_t wide;  // volatile keeps the reference on the generic int64 path
uint32_t mismatches = 0;

void check(const char* what, int32_t x, int32_t c, int32_t got, int32_t want) {
  if (got == want || ++mismatches > 20) return;
  probe::print(what);
  probe::put(' ');
  probe::print_hex((uint32_t)x, 8);
  probe::put(' ');
  probe::print_hex((uint32_t)c, 8);
  probe::put(' ');
  probe::print_hex((uint32_t)got, 8);
  probe::put(' ');
  probe::print_hex((uint32_t)want, 8);
  probe::put('\n');
}

// the product with the low bytes' product left out, as fixed_point.h defines it
int64_t without_low_bytes(int32_t x, int32_t c) {
  wide = (int64_t)x * c;
  return wide - (int64_t)(uint8_t)x * (uint8_t)c;
}

int16_t random_unit(vectors::Lcg& rng) {
  const int16_t u = (int16_t)(rng.next() >> 16);
  return u == -32768 ? -32767 : u;  // Units stop at +-32767
}

void check_products(vectors::Lcg& rng) {
  for (uint16_t n = 0; n < 4000; ++n) {
    const int32_t x = (int32_t)rng.next() >> (n & 15);
    const int32_t y = (int32_t)rng.next() >> ((n >> 4) & 15);
    const int16_t c = random_unit(rng), d = random_unit(rng);
    const uint16_t cu = (uint16_t)(rng.next() >> 16);
    check("q15", x, c, fx::mul_q15(x, c), (int32_t)(without_low_bytes(x, c) >> 15));
    check("q16", x, c, fx::mul_q16(x, c), (int32_t)(without_low_bytes(x, c) >> 16));
    const int32_t want_dot = (int32_t)((without_low_bytes(x, c) + without_low_bytes(y, d)) >> 15);
    check("dot", x, y, fx::dot_q15(c, x, d, y), want_dot);
    const fx::Recip k{cu, (uint8_t)(1 << (n & 7)), (n & 8) != 0};
    wide = (without_low_bytes(x, cu) >> 16) * k.scale;
    const int32_t limited = wide > fx::kRecipProductLimit    ? fx::kRecipProductLimit
                            : wide < -fx::kRecipProductLimit ? -fx::kRecipProductLimit
                                                             : (int32_t)wide;
    check("recip", x, cu, (fx::Real{x} * k).raw, k.negative ? -limited : limited);
    wide = (int64_t)(uint16_t)x * c;
    check("us", x, c, fx::mul_us((uint16_t)x, c), (int32_t)wide);
    wide = (int64_t)(uint16_t)x * cu;
    check("uu", x, cu, (int32_t)fx::mul_uu((uint16_t)x, cu), (int32_t)wide);
    // Recip * Recip: the high half of the mantissas' product, renormalised, the scales' product
    const fx::Recip j{(uint16_t)(rng.next() >> 16), (uint8_t)(1 << ((n >> 3) & 7)), (n & 1) != 0};
    uint32_t m = (uint32_t)k.mantissa * j.mantissa;
    uint16_t scale = (uint16_t)(k.scale * j.scale);
    if (!(m & 0x80000000u) && scale > 1) {
      m <<= 1;
      scale >>= 1;
    }
    const fx::Recip p = k * j;
    const bool saturated = scale > fx::kRecipMaxScale;
    check("rr", k.mantissa, j.mantissa, p.mantissa, saturated ? 65535 : (int32_t)(m >> 16));
    check("rr scale", k.scale, j.scale, p.scale, saturated ? fx::kRecipMaxScale : scale);
    check("rr sign", k.negative, j.negative, p.negative, k.negative != j.negative);
    // Span -> Unit, rounded, saturated at +-32767
    const int32_t span = (int32_t)rng.next() >> (n & 3);
    wide = ((int64_t)span + 32768) >> 16;
    const int32_t rounded = (int32_t)wide;
    const int32_t want_unit = rounded > 32767 ? 32767 : rounded < -32767 ? -32767 : rounded;
    check("to_unit", span, 0, fx::to_unit(fx::Span{span}).raw, want_unit);
  }
}

// the table lookups against the interpolation formulas they implement
void check_tables(vectors::Lcg& rng) {
  for (uint16_t n = 0; n < 4000; ++n) {
    const fx::Angle a{(int32_t)rng.next()};
    const uint8_t i = (uint8_t)(a.raw >> 8), f = (uint8_t)a.raw;
    const int16_t s0 = fx::interpolate_up(fx::sin_table(), i, f);
    const int16_t c0 = fx::interpolate_down(fx::sin_table(), i, f);
    const uint8_t quadrant = (uint8_t)(a.raw >> 16) & 3u;
    const int16_t s = quadrant == 0 ? s0 : quadrant == 1 ? c0 : quadrant == 2 ? -s0 : -c0;
    const int16_t c = quadrant == 0 ? c0 : quadrant == 1 ? -s0 : quadrant == 2 ? -c0 : s0;
    const fx::SinCos sc = fx::sincos(a);
    check("sin", a.raw, 0, sc.s.raw, s);
    check("cos", a.raw, 0, sc.c.raw, c);
    check("sin alone", a.raw, 0, fx::sin(a).raw, s);
  }
  for (uint16_t magnitude = 1; magnitude <= 32767; magnitude += (magnitude < 512 ? 1 : 5)) {
    uint16_t normalised = magnitude;
    uint8_t scale = 1;
    while (!(normalised & 0x8000u) && scale < fx::kRecipMaxScale) {
      normalised <<= 1;
      scale <<= 1;
    }
    const bool saturated = !(normalised & 0x8000u);
    const fx::Recip k = fx::reciprocal_of_magnitude(magnitude, true);
    check("1/x", magnitude, 0, k.mantissa, saturated ? 65535 : fx::half_reciprocal_uq16(normalised));
    check("1/x scale", magnitude, 0, k.scale, scale);
    check("1/x sign", magnitude, 0, k.negative, true);
  }
}

// saturating Unit sums, including the overflow and -32768 corners
void check_unit_sums() {
  const int16_t corners[] = {-32767, -32766, -16384, -1, 0, 1, 16384, 32766, 32767};
  for (int16_t a : corners) {
    for (int16_t b : corners) {
      int32_t sum = (int32_t)a + b, diff = (int32_t)a - b;
      sum = sum > 32767 ? 32767 : sum < -32767 ? -32767 : sum;
      diff = diff > 32767 ? 32767 : diff < -32767 ? -32767 : diff;
      check("+", a, b, (fx::Unit{a} + fx::Unit{b}).raw, sum);
      check("-", a, b, (fx::Unit{a} - fx::Unit{b}).raw, diff);
    }
  }
}
// JointReferences::advance_all's asm loop against the 64-bit step, of one tick and of two in
// turn, over full-range angles (which wrap) and fractions; the bytes around the references stay
// untouched
void check_advance(vectors::Lcg& rng) {
  struct Guarded {
    uint8_t before[4];
    core::JointReferences refs;
    uint8_t after[4];
  };
  static Guarded g;
  for (uint8_t i = 0; i < 4; ++i) g.before[i] = g.after[i] = (uint8_t)(0xA5 + i);
  uint32_t n = 0;
  for (uint16_t round = 0; round < 20000; ++round) {
    vectors::AdvancedJoint want[6];
    for (uint8_t j = 0; j < 6; ++j) {
      g.refs.q.q[j].raw = (int32_t)rng.next();
      g.refs.fraction[j] = (uint16_t)rng.next();
      g.refs.qd_rad_s[j].raw = vectors::advance_velocity(rng, n++);
      want[j] = vectors::reference_advance(g.refs.q.q[j].raw, g.refs.fraction[j], g.refs.qd_rad_s[j].raw, round % 2);
    }
    g.refs.advance_all(round % 2);
    for (uint8_t j = 0; j < 6; ++j) {
      check("advance q", g.refs.qd_rad_s[j].raw, j, g.refs.q.q[j].raw, want[j].q);
      check("advance fraction", g.refs.qd_rad_s[j].raw, j, g.refs.fraction[j], want[j].fraction);
    }
  }
  for (uint8_t i = 0; i < 4; ++i) {
    check("advance guard", i, 0, g.before[i], (uint8_t)(0xA5 + i));
    check("advance guard", i, 1, g.after[i], (uint8_t)(0xA5 + i));
  }
}
}  // namespace

int main() {
  vectors::Lcg rng{12345u};
  check_products(rng);
  check_tables(rng);
  check_unit_sums();
  check_advance(rng);
  probe::print("mismatches ");
  probe::print_uint(mismatches);
  probe::put('\n');
  probe::finish();
}
