// Checks the hand-written AVR multiply routines against int64 arithmetic on the chip:
// prints one line per mismatch and "mismatches N" at the end.
#include "kinematics/reciprocal.h"
#include "kinematics_vectors.h"
#include "probe.h"

using namespace wmra;

namespace {
volatile int64_t wide;  // volatile keeps the reference on the generic int64 path

void report(const char* what, int32_t x, int32_t c, int32_t got, int32_t want) {
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
}  // namespace

int main() {
  vectors::Lcg rng{12345u};
  uint32_t mismatches = 0;
  for (uint16_t n = 0; n < 4000; ++n) {
    const int32_t x = (int32_t)rng.next() >> (n & 15);
    const int32_t y = (int32_t)rng.next() >> ((n >> 4) & 15);
    int16_t c = (int16_t)(rng.next() >> 16);
    int16_t d = (int16_t)(rng.next() >> 16);
    if (c == -32768) c = -32767;  // Units stop at +-32767
    if (d == -32768) d = -32767;
    const uint16_t cu = (uint16_t)(rng.next() >> 16);
    const int32_t want_q15 = (int32_t)(without_low_bytes(x, c) >> 15);
    const int32_t got_q15 = fx::mul_q15(x, c);
    if (got_q15 != want_q15 && ++mismatches <= 20) report("q15", x, c, got_q15, want_q15);
    const int32_t want_dot = (int32_t)((without_low_bytes(x, c) + without_low_bytes(y, d)) >> 15);
    const int32_t got_dot = fx::dot_q15(c, x, d, y);
    if (got_dot != want_dot && ++mismatches <= 20) report("dot", x, y, got_dot, want_dot);
    const fx::Recip k{cu, (uint8_t)(1 << (n & 7)), (n & 8) != 0};
    wide = (without_low_bytes(x, cu) >> 16) * k.scale;
    const int32_t limited = wide > fx::kRecipProductLimit ? fx::kRecipProductLimit
                            : wide < -fx::kRecipProductLimit ? -fx::kRecipProductLimit
                                                             : (int32_t)wide;
    const int32_t want_recip = k.negative ? -limited : limited;
    const int32_t got_recip = (fx::Real{x} * k).raw;
    if (got_recip != want_recip && ++mismatches <= 20) report("recip", x, cu, got_recip, want_recip);
    wide = (int64_t)(uint16_t)x * c;
    if (fx::mul_us((uint16_t)x, c) != (int32_t)wide && ++mismatches <= 20) report("us", x, c, fx::mul_us((uint16_t)x, c), (int32_t)wide);
    wide = (int64_t)(uint16_t)x * cu;
    if (fx::mul_uu((uint16_t)x, cu) != (uint32_t)wide && ++mismatches <= 20) report("uu", x, cu, (int32_t)fx::mul_uu((uint16_t)x, cu), (int32_t)wide);
  }
  // saturating Unit sums, including the overflow and -32768 corners
  const int16_t corners[] = {-32767, -32766, -16384, -1, 0, 1, 16384, 32766, 32767};
  for (int16_t a : corners) {
    for (int16_t b : corners) {
      int32_t sum = (int32_t)a + b, diff = (int32_t)a - b;
      sum = sum > 32767 ? 32767 : sum < -32767 ? -32767 : sum;
      diff = diff > 32767 ? 32767 : diff < -32767 ? -32767 : diff;
      if ((fx::Unit{a} + fx::Unit{b}).raw != sum && ++mismatches <= 20) report("+", a, b, (fx::Unit{a} + fx::Unit{b}).raw, sum);
      if ((fx::Unit{a} - fx::Unit{b}).raw != diff && ++mismatches <= 20) report("-", a, b, (fx::Unit{a} - fx::Unit{b}).raw, diff);
    }
  }
  probe::print("mismatches ");
  probe::print_uint(mismatches);
  probe::put('\n');
  probe::finish();
}
