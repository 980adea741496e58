// Number policies: each kinematics template is written once, as the formula, and
// instantiated with one of these.
//   Floating<double>  host reference and the armkin default
//   Floating<float>   the same closed forms in float on the AVR (benchmark baseline)
//   Fixed             the firmware's integer instantiation (fixed_point.h, fixed_trig.h)
// A policy names the kinds of number the formulas use (Angle, Unit for sines and rotation
// entries, Length for link constants, Real for positions and velocities, Recip for
// reciprocals) and the few operations that differ between them.
#pragma once

#include <math.h>

#include "kinematics/fixed_trig.h"

namespace wmra {
namespace kin {

template <class Unit>
struct SinCosOf {
  Unit s;
  Unit c;
};

inline float sin_of(float a) { return sinf(a); }
inline float cos_of(float a) { return cosf(a); }
inline float atan2_of(float y, float x) { return atan2f(y, x); }
inline float sqrt_of(float a) { return sqrtf(a); }
inline float fmod_of(float a, float b) { return fmodf(a, b); }
inline double sin_of(double a) { return ::sin(a); }
inline double cos_of(double a) { return ::cos(a); }
inline double atan2_of(double y, double x) { return ::atan2(y, x); }
inline double sqrt_of(double a) { return ::sqrt(a); }
inline double fmod_of(double a, double b) { return ::fmod(a, b); }

template <class T>
struct Floating {
  using Angle = T;
  using Unit = T;
  using Length = T;
  using Real = T;
  using Recip = T;
  using SinCos = SinCosOf<T>;
  struct Band {
    T eps;
  };

  static constexpr Unit unit(Ratio x) { return (T)wmra::to_double(x); }
  static constexpr Length length(Ratio metres) { return (T)wmra::to_double(metres); }
  static constexpr Real real(Ratio x) { return (T)wmra::to_double(x); }
  static constexpr Recip recip_constant(Ratio c) { return (T)(1.0 / wmra::to_double(c)); }
  static constexpr Band band(Ratio eps) { return Band{(T)wmra::to_double(eps)}; }
  static constexpr Angle angle_deg(Ratio degrees) { return (T)(wmra::to_double(degrees) * (fx::kPi / 180)); }
  static constexpr Angle half_turn() { return (T)fx::kPi; }
  static constexpr Angle full_turn() { return (T)(2 * fx::kPi); }

  static SinCos sincos(Angle a) { return SinCos{sin_of(a), cos_of(a)}; }
  static Unit sin(Angle a) { return sin_of(a); }
  static Angle atan2(T y, T x) { return atan2_of(y, x); }
  // the angle in (-pi, pi]
  static Angle wrap(Angle a) {
    a = fmod_of(a, full_turn());
    return a <= -half_turn() ? a + full_turn() : a > half_turn() ? a - full_turn() : a;
  }
  static Unit hypot(Unit a, Unit b) { return sqrt_of(a * a + b * b); }
  static Unit sqrt_one_minus_square(Unit c) { return c * c < 1 ? sqrt_of(1 - c * c) : 0; }
  static Unit to_unit(Real r) { return r; }
  static Real to_real(Unit u) { return u; }
  static T abs(T x) { return x < 0 ? -x : x; }
  // a x + b y (Fixed sums the two products before its one rounding)
  static T dot(T a, T x, T b, T y) { return a * x + b * y; }
  // 1/x outside the band, x/eps^2 inside it (see fx::damped_reciprocal)
  static Recip damped_reciprocal(Unit x, Band b) { return abs(x) >= b.eps ? (T)1 / x : x / (b.eps * b.eps); }
  static bool inside(Unit x, Band b) { return abs(x) < b.eps; }
  static bool is_zero(Real x) { return x == 0; }
};

struct Fixed {
  using Angle = fx::Angle;
  using Unit = fx::Unit;
  using Length = fx::Length;
  using Real = fx::Real;
  using Recip = fx::Recip;
  using SinCos = fx::SinCos;
  using Band = fx::DampedBand;

  static constexpr Unit unit(Ratio x) { return fx::unit(x); }
  static constexpr Length length(Ratio metres) { return fx::length(metres); }
  static constexpr Real real(Ratio x) { return fx::real(x); }
  static constexpr Recip recip_constant(Ratio c) { return fx::recip_constant(c); }
  // 1/eps^2 from the eps that the comparison uses, so the damped branch meets 1/x at the edge
  static constexpr Band band(Ratio eps) { return fx::damped_band(fx::unit(eps)); }

  static constexpr Angle angle_deg(Ratio degrees) { return fx::angle_deg(degrees); }
  static constexpr Angle half_turn() { return Angle{fx::kAngleTurn / 2}; }
  static constexpr Angle full_turn() { return Angle{fx::kAngleTurn}; }

  static SinCos sincos(Angle a) { return fx::sincos(a); }
  static Unit sin(Angle a) { return fx::sin(a); }
  static Angle atan2(Unit y, Unit x) { return fx::atan2(y.raw, x.raw); }
  static Angle atan2(Real y, Real x) { return fx::atan2(y.raw, x.raw); }
  static Angle atan2(fx::Span y, fx::Span x) { return fx::atan2(y.raw, x.raw); }
  static Angle wrap(Angle a) { return fx::wrap(a); }
  static Angle abs(Angle a) { return Angle{a.raw < 0 ? -a.raw : a.raw}; }
  static Unit hypot(Unit a, Unit b) { return fx::hypot(a, b); }
  static Unit sqrt_one_minus_square(Unit c) { return fx::sqrt_one_minus_square(c); }
  static Unit to_unit(Real r) { return fx::to_unit(r); }
  static Unit to_unit(fx::Span s) { return fx::to_unit(s); }  // a link chain's sum, rounded
  static Real to_real(Unit u) { return fx::to_real(u); }
  static Real dot(Unit a, Real x, Unit b, Real y) { return fx::dot(a, x, b, y); }  // one fused product
  static Recip damped_reciprocal(Unit x, Band b) { return fx::damped_reciprocal(x, b); }
  static bool inside(Unit x, Band b) { return (x.raw < 0 ? -x.raw : x.raw) < b.eps.raw; }
  static bool is_zero(Real x) { return x.raw == 0; }
};

}  // namespace kin
}  // namespace wmra
