// Checks the hand-written AVR multiply routines against int64 arithmetic on the chip:
// prints one line per mismatch and "mismatches N" at the end.
#include "kinematics/fixed_point.h"
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
}  // namespace

int main() {
  vectors::Lcg rng{12345u};
  uint32_t mismatches = 0;
  for (uint16_t n = 0; n < 4000; ++n) {
    const int32_t x = (int32_t)rng.next() >> (n & 15);
    const int16_t c = (int16_t)(rng.next() >> 16);
    const uint16_t cu = (uint16_t)(rng.next() >> 16);
    wide = (int64_t)x * c;
    const int32_t want_s = (int32_t)(wide >> 16);
    const int32_t got_s = fx::mul_hi_32x16(x, c);
    if (got_s != want_s && ++mismatches <= 20) report("s", x, c, got_s, want_s);
    wide = (int64_t)x * cu;
    const int32_t want_u = (int32_t)(wide >> 16);
    const int32_t got_u = fx::mul_hi_32xu16(x, cu);
    if (got_u != want_u && ++mismatches <= 20) report("u", x, cu, got_u, want_u);
    wide = (int64_t)(int16_t)x * c;
    if (fx::mul_ss((int16_t)x, c) != (int32_t)wide && ++mismatches <= 20) report("ss", x, c, fx::mul_ss((int16_t)x, c), (int32_t)wide);
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
