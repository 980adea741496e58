// Checks the hand-written AVR arithmetic on the chip against int64 arithmetic and the plain-C
// formulas of the headers: prints one line per mismatch and "mismatches N" at the end.
#include <string.h>

#include "advance_vectors.h"
#include "core/dc_servo.h"
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
// --- DcServo::update's asm run (update_running: two ticks, not parked, the PID) against
// update_portable, its C, from the same state and inputs: the duty and every byte of the servo.
// Random configurations (half tiny, so that sums land on the limits' edges), restarts, bounds,
// readings walking and jumping (garbage ones over the whole int16 too), references near and far,
// still and moving feedforwards, holding efforts, ticks 2 and others (those and the parked runs
// are C on both sides and only move the state on). Then edge vectors built on the state: P +
// the trial integral on the conditional integration's bound and one off, the sum on the
// effort's limits and one off. A model of update_effort's terms (below) classifies each vector:
// every branch of the kernel counted, each required.
template <typename T>
T pid_field(const core::DcServo& s, uint8_t offset) {
  T v;
  memcpy(&v, (const uint8_t*)&s.pid() + offset, sizeof v);
  return v;
}
int16_t pid_towards(int16_t from, int16_t to, uint16_t step) {
  if (to >= from) return (uint16_t)(to - from) <= step ? to : (int16_t)(from + step);
  return (uint16_t)(from - to) <= step ? to : (int16_t)(from - step);
}
int32_t clamp32(int32_t x, int32_t lo, int32_t hi) { return x < lo ? lo : x > hi ? hi : x; }

// update_effort's sums for two ticks from the servo's state, the error e, reading m, the
// feedforward ff after the holding's substitution and the integral i before the sample
struct DcTerms {
  int32_t p, di, t, s, sum;
  int16_t hi, lo;
  bool integrates, p_clamped, di_clamped, d_clamped, kp_wide, dm_saturated;
};
DcTerms dc_terms(const core::DcServo& servo, int16_t e, int16_t m, int16_t ff, int32_t i) {
  const control::Pid::Layout l = control::Pid::layout();
  const control::PidConfig& c = servo.pid().config();
  DcTerms x{};
  int16_t dm;
  x.dm_saturated = __builtin_sub_overflow(m, pid_field<int16_t>(servo, l.m_prev), &dm) || dm == -32768;
  dm = (int16_t)(control::sub_saturated_i16(m, pid_field<int16_t>(servo, l.m_prev)) >> 1);
  const uint16_t ae = control::distance_u16(e, 0), adm = control::distance_u16(dm, 0);
  const int32_t limit = pid_field<int32_t>(servo, l.integral_limit);
  x.di = e == 0 ? 0 : (int32_t)e * c.gains.ki_q8;
  x.di_clamped = e != 0 && ae > pid_field<uint16_t>(servo, l.i_error_limit);
  if (x.di_clamped) x.di = clamp32(x.di, -limit, limit);
  x.di *= 2;
  const uint16_t kp_x16 = pid_field<uint16_t>(servo, l.kp_x16);
  x.p_clamped = e != 0 && ae > pid_field<uint16_t>(servo, l.p_error_limit);
  x.kp_wide = e != 0 && !x.p_clamped && kp_x16 == 0 && c.gains.kp_q4 != 0;
  x.p = e == 0 ? 0 : x.p_clamped ? (e < 0 ? -(1L << 30) : (1L << 30)) : x.kp_wide ? (int32_t)e * c.gains.kp_q4 * 16 : (int32_t)kp_x16 * e;
  x.d_clamped = dm != 0 && adm > pid_field<uint16_t>(servo, l.d_change_limit);
  const int32_t d = dm == 0 ? 0 : x.d_clamped ? (dm < 0 ? -(1L << 22) : (1L << 22)) : (int32_t)dm * c.gains.kd;
  x.t = ff - d;
  const uint16_t rate = pid_field<uint16_t>(servo, l.rate_twice);
  const int16_t effort = servo.pid().effort_q15();
  x.hi = pid_towards(effort, pid_field<int16_t>(servo, l.top), rate);
  x.lo = pid_towards(effort, pid_field<int16_t>(servo, l.bottom), rate);
  const int32_t trial = clamp32(i + x.di, -limit, limit);
  x.s = x.p + trial;
  x.integrates = x.di != 0 && (x.di > 0 ? x.s <= (x.hi - x.t) * 256 + 15 : x.s >= (x.lo - x.t) * 256);
  x.sum = x.p + (x.integrates ? trial : i);
  return x;
}

struct DcCounts {
  uint32_t runs, still, moving, parks, substituted, dropped, integrated, held, at_hi, at_lo, inside, p_clamped, di_clamped,
      d_clamped, kp_wide, e_saturated, dm_saturated, breakaway, zero_duty, round_edge, bound[10], hi_edge[3], lo_edge[3];
};

// one update each way from the same servo; the model's classes counted for a kernel run
void dc_compare(core::DcServo& servo, bool& was_still, int16_t r, int16_t m, int16_t ff, int16_t h, uint8_t ticks,
                const core::DcServoConfig& c, DcCounts& n) {
  const bool kernel = ticks == 2 && !servo.parked() && !c.use_relay;
  const int16_t zb = c.pid.zero_band_q15;
  const bool still = ff < zb && ff > -zb;
  const int16_t e = control::sub_saturated_i16(r, m);
  const bool substitute = still && e != 0 && (e > 0) == (h > 0);
  const bool drop = still && !was_still;
  const int32_t i = drop ? 0 : servo.pid().integral_q23();
  const bool had_integral = servo.pid().integral_q23() != 0;
  const DcTerms x = dc_terms(servo, e, m, substitute ? h : ff, i);
  core::DcServo twin = servo;
  const int16_t got = servo.update(r, m, ff, h, ticks);
  const int16_t want = twin.update_portable(r, m, ff, h, ticks);
  check("dc duty", r, m, got, want);
  check("dc state", ff, ((uint32_t)h << 16) | ticks, memcmp(&servo, &twin, sizeof servo), 0);
  was_still = still;
  if (!kernel) return;
  ++n.runs;
  if (twin.parked()) {
    ++n.parks;
    return;
  }
  n.still += still;
  n.moving += !still;
  n.substituted += substitute;
  n.dropped += drop && had_integral;
  n.integrated += x.integrates;
  n.held += x.di != 0 && !x.integrates;
  const int32_t u = ((x.sum + 128) >> 8) + x.t;
  n.at_hi += u > x.hi;
  n.at_lo += u < x.lo;
  n.inside += u >= x.lo && u <= x.hi;
  n.p_clamped += x.p_clamped;
  n.di_clamped += x.di_clamped;
  n.d_clamped += x.d_clamped;
  n.kp_wide += x.kp_wide;
  n.e_saturated += e != (int32_t)r - m;
  n.dm_saturated += x.dm_saturated;
  n.zero_duty += want == 0;
  n.round_edge += (x.sum & 255) == 127 || (x.sum & 255) == 128;
  if (!still) {
    const bool negative = ff < 0;
    const int16_t effort = twin.pid().effort_q15();
    n.breakaway += want != control::Pid::duty_moving(effort, negative, c.moving_friction_q15,
                                                     twin.pid().moving_slope_q15(c.moving_friction_q15));
  }
  // (s - the bound in [-2, 2], each side: 0..4 e > 0, 5..9 e < 0)
  const int32_t off = x.di > 0 ? x.s - ((x.hi - x.t) * 256 + 15) : x.s - (x.lo - x.t) * 256;
  if (x.di != 0 && off >= -2 && off <= 2) ++n.bound[off + 2 + (x.di < 0 ? 5 : 0)];
  if (u - x.hi >= -1 && u - x.hi <= 1) ++n.hi_edge[u - x.hi + 1];
  if (u - x.lo >= -1 && u - x.lo <= 1) ++n.lo_edge[u - x.lo + 1];
}

core::DcServoConfig dc_config(vectors::Lcg& rng, uint16_t n) {
  const bool tiny = n % 2 == 0;
  core::DcServoConfig c{};
  control::PidConfig& k = c.pid;
  do {
    if (tiny) {
      k.gains = control::PidGains{(int16_t)rng.in_range(0, 4), (int16_t)rng.in_range(0, 300), (int16_t)rng.in_range(0, 4)};
      k.out_max_q15 = (int16_t)rng.in_range(1, 12);
      k.rate_q15 = (int16_t)rng.in_range(1, 4);
    } else {
      k.gains = control::PidGains{(int16_t)rng.in_range(0, n % 8 == 1 ? 32767 : 6000), (int16_t)rng.in_range(0, n % 4 == 3 ? 32767 : 400),
                                  (int16_t)(n % 8 == 3 ? 0 : rng.in_range(0, 32767))};
      k.out_max_q15 = (int16_t)(n % 4 == 3 ? 32767 : rng.in_range(2, 32767));
      k.rate_q15 = (int16_t)rng.in_range(1, n % 3 == 0 ? 32767 : 2000);
    }
    k.min_duty_q15 = (int16_t)rng.in_range(0, k.out_max_q15 - 1);
    k.zero_band_q15 = (int16_t)rng.in_range(0, k.out_max_q15);
  } while (control::pid_check(k) != control::PidStatus::ok);
  c.use_relay = n % 16 == 15;
  c.park_units = (int16_t)(tiny ? rng.in_range(0, 40) : rng.in_range(0, 16383));
  c.park_ticks = (uint16_t)(n % 32 == 5 ? 0 : rng.in_range(1, 12));
  c.unpark_ticks = (uint16_t)rng.in_range(1, 6);
  const int16_t most = k.min_duty_q15 < k.out_max_q15 / 2 ? k.min_duty_q15 : (int16_t)(k.out_max_q15 / 2);
  c.moving_friction_q15 = (int16_t)rng.in_range(0, most);
  return c;
}

int16_t dc_spread(vectors::Lcg& rng, int16_t small) {
  const uint8_t k = (uint8_t)(rng.next() >> 24) % 100;
  if (k < 85) return (int16_t)rng.in_range(-small, small);
  if (k < 98) return (int16_t)rng.in_range(-16384, 16383);
  return (int16_t)(rng.next() >> 16);
}

void check_dc_servo(vectors::Lcg& rng) {
  DcCounts n{};
  for (uint16_t config = 0; config < 360; ++config) {
    const core::DcServoConfig c = dc_config(rng, config);
    const bool tiny = config % 2 == 0;
    const int16_t out_max = c.pid.out_max_q15, zb = c.pid.zero_band_q15;
    core::DcServo servo;
    servo.configure(c);
    int16_t m = (int16_t)rng.in_range(0, 16368);
    bool was_still = true;
    servo.rest(m);
    for (uint16_t step = 0; step < 200; ++step) {
      const uint8_t event = (uint8_t)(rng.next() >> 24);
      if (event < 3) servo.rest(m);
      else if (event < 12)
        servo.set_effort_bounds((int16_t)rng.in_range(-2, out_max + 2), (int16_t)rng.in_range(-2, out_max + 2));
      m = event < 250 ? (int16_t)clamp32(m + rng.in_range(-60, 60), 0, 16368)
                      : event < 253 ? (int16_t)rng.in_range(0, 16368) : (int16_t)(rng.next() >> 16);
      const int16_t r = (int16_t)(event % 64 == 7 ? (int16_t)(rng.next() >> 16) : m + dc_spread(rng, tiny ? 20 : 400));
      const uint8_t kind = (uint8_t)(rng.next() >> 24) % 8;
      const int16_t ff = kind < 3   ? (int16_t)rng.in_range(-zb - 2, zb + 2)
                         : kind < 6 ? (int16_t)rng.in_range(-out_max, out_max)
                                    : (int16_t)(rng.next() >> 16);
      const int16_t h = tiny ? (int16_t)rng.in_range(-out_max, out_max) : dc_spread(rng, 3000);
      const uint8_t pick = (uint8_t)(rng.next() >> 24);
      const uint8_t ticks = pick < 200 ? 2 : pick < 230 ? 1 : (uint8_t)rng.in_range(0, 9);
      dc_compare(servo, was_still, r, m, ff, h, ticks, c, n);
      if (!servo.parked() && !c.use_relay && step % 4 == 3) {
        // an edge vector on this state: a moving reference, the reading as the PID last saw it
        // (no D), the error scanned for a sum with the residue that puts it one off, on or one
        // past a bound, the feedforward solved for that bound
        const control::Pid::Layout l = control::Pid::layout();
        const int16_t mp = pid_field<int16_t>(servo, l.m_prev);
        const int32_t i = servo.pid().integral_q23();
        // which: 0, 1 the integration's bound (e > 0, < 0), 2, 3 the effort's hi, lo; delta: s
        // or the sum off it (s even: below)
        const uint8_t which = (uint8_t)((step / 4) % 4), third = (uint8_t)((step / 16) % 3);
        const int8_t delta = which == 0 ? (third == 0 ? -1 : 1) : which == 1 ? (int8_t)(2 * third - 2) : (int8_t)(third - 1);
        for (int16_t a = 1; a < 600; ++a) {
          const int16_t e = which == 1 ? (int16_t)-a : which == 0 ? a : (int16_t)(a - 1);
          if ((int32_t)mp + e > 32767 || (int32_t)mp + e < -32767) break;
          const DcTerms x = dc_terms(servo, e, mp, 0, i);
          int32_t ff;
          if (which == 0) {
            if (x.di <= 0 || ((x.s - 15 - delta) & 255) != 0) continue;
            ff = x.hi - ((x.s - 15 - delta) >> 8);
          } else if (which == 1) {
            if (x.di >= 0 || ((x.s - delta) & 255) != 0) continue;
            ff = x.lo - ((x.s - delta) >> 8);
          } else {
            if (x.di != 0) continue;  // held: the sum is P + the integral
            ff = (which == 2 ? x.hi : x.lo) + delta - ((x.sum + 128) >> 8);
          }
          if (ff > 32767 || ff < -32768 || (ff < zb && ff > -zb)) break;  // not a moving reference's
          dc_compare(servo, was_still, (int16_t)(mp + e), mp, (int16_t)ff, 0, 2, c, n);
          m = mp;
          break;
        }
      }
    }
  }
  // every branch of the kernel taken, many times
  const uint32_t r = n.runs;
  check("dc runs", r, 0, r > 40000, 1);
  check("dc still", r, 0, n.still > r / 20, 1);
  check("dc moving", r, 0, n.moving > r / 5, 1);
  check("dc parks", r, 0, n.parks > r / 500, 1);
  check("dc substituted", r, 0, n.substituted > r / 100, 1);
  check("dc integral dropped", r, 0, n.dropped > r / 1000, 1);
  check("dc integrated", r, 0, n.integrated > r / 20, 1);
  check("dc held", r, 0, n.held > r / 50, 1);
  check("dc at hi", r, 0, n.at_hi > r / 50, 1);
  check("dc at lo", r, 0, n.at_lo > r / 50, 1);
  check("dc inside", r, 0, n.inside > r / 20, 1);
  check("dc p clamped", r, 0, n.p_clamped > r / 1000, 1);
  check("dc di clamped", r, 0, n.di_clamped > r / 1000, 1);
  check("dc d clamped", r, 0, n.d_clamped > r / 1000, 1);
  check("dc kp wide", r, 0, n.kp_wide > r / 1000, 1);
  check("dc e saturated", r, 0, n.e_saturated > r / 5000, 1);
  check("dc dm saturated", r, 0, n.dm_saturated > r / 5000, 1);
  check("dc breakaway", r, 0, n.breakaway > r / 1000, 1);
  check("dc zero duty", r, 0, n.zero_duty > r / 50, 1);
  check("dc rounding edge", r, 0, n.round_edge > r / 1000, 1);
  // P and the integral are even (P 16 Kp e or +-2^30, the integral's steps 2 e Ki, its starts
  // and presets whole bytes), so s is: on the bound and beside it, the even ones (e > 0: the
  // bound is 256 (hi - t) + 15, s one below or above it; e < 0: 256 (lo - t), s on it or 2 off)
  for (uint8_t k = 1; k < 10; k += 2) check("dc integration bound", k, n.bound[k], n.bound[k] > 50, 1);
  for (uint8_t k = 0; k < 3; ++k) check("dc hi edge", k, n.hi_edge[k], n.hi_edge[k] > 100, 1);
  for (uint8_t k = 0; k < 3; ++k) check("dc lo edge", k, n.lo_edge[k], n.lo_edge[k] > 100, 1);
  probe::print("dc servo runs ");
  probe::print_uint(r);
  probe::put('\n');
}
}  // namespace

int main() {
  vectors::Lcg rng{12345u};
  check_products(rng);
  check_tables(rng);
  check_unit_sums();
  check_advance(rng);
  check_dc_servo(rng);
  probe::print("mismatches ");
  probe::print_uint(mismatches);
  probe::put('\n');
  probe::finish();
}
