// Exact rational constants. avr-gcc's double is 32 bits, so a fixed-point constant computed
// from a double at compile time can differ by one step between the AVR and the host; the
// arm's numbers are therefore written as integer ratios (millimetres, degrees, hundredths)
// and converted to fixed point with integer arithmetic.
#pragma once

#include <stdint.h>

namespace wmra {

struct Ratio {
  int64_t num;
  int64_t den;  // > 0
};

constexpr double to_double(Ratio r) { return (double)r.num / (double)r.den; }
constexpr int64_t gcd(int64_t a, int64_t b) { return b == 0 ? (a < 0 ? -a : a) : gcd(b, a % b); }
// in lowest terms, so that sums and products of the arm's millimetre ratios stay far from overflow
constexpr Ratio reduced(Ratio r) { return Ratio{r.num / gcd(r.num, r.den), r.den / gcd(r.num, r.den)}; }
constexpr Ratio operator*(Ratio a, Ratio b) { return reduced(Ratio{a.num * b.num, a.den * b.den}); }
constexpr Ratio operator+(Ratio a, Ratio b) { return reduced(Ratio{a.num * b.den + b.num * a.den, a.den * b.den}); }

// round(n / d) to nearest, halves away from zero, d > 0
constexpr int64_t div_round(int64_t n, int64_t d) { return n >= 0 ? (n + d / 2) / d : -((-n + d / 2) / d); }

}  // namespace wmra
