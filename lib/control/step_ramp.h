// Step-interval ramp generator for timer-driven stepping: given a signed target speed (or a
// target position) and an acceleration limit, the interval in timer ticks to the next step
// edge, one call per step, counting every step it schedules.
//
// Why this form. Seed 2 (eq. 4.14-4.16, after AVR446) gets each interval from the last by
// solving a quadratic, k_{i+1} = [-w_i + sqrt(w_i^2 + 4 w' a_s)] / (2 t0 w'): a square root
// and a division per step (~1,100 cycles here), and its model (4.15) takes a step's mean
// speed a_s/(k t0) for its end speed. From rest that gives a first interval of 1/sqrt(w')
// where constant acceleration needs sqrt(2/w') (the first step at twice the limit); after
// that it accelerates at 2 k_{i+1} / (k_i + k_{i+1}) of the limit, and used backwards for
// braking it would exceed the limit by the same ratio. (Its first-order term is right: the
// per-step change -w' k^3 t0^2 is the same as here; test_step_ramp checks both facts.)
// Here the profile is the exact one. At constant acceleration a from rest, step n is at
// t_n = sqrt(2n/a), so
//     tau(n) = sqrt(2/a) (sqrt(n+1) - sqrt(n))                                       (1)
// and speed is a function of the "level" n, the number of constant-acceleration steps between
// rest and the present speed. Speeding up emits tau(L) and raises L; slowing down emits
// tau(L-1) and lowers L; so braking from level L to rest takes exactly L steps. That is the
// stopping distance, as an integer: positioning is exact, and a reversal always passes through
// rest (level 0). Measured as the change of mean step speed 1/tau between two steps over the
// time between their midpoints, (1) gives exactly a for every step, the first from rest and
// the last to rest included.
//
// Cost. tau(n) for n <= 256 is a table of sqrt(n+1) - sqrt(n) (UQ32, 1 KB of flash) times
// sqrt(2/a). Above it, nodes tau(j) = F / sqrt(a (2j+1)) (the expansion of (1), relative error
// below 1/(32 j^2)) come from a reciprocal-square-root table every K = 2^(floor(log2 j) - 6)
// levels (at most 2^15), with exact integer interpolation between them (a Bresenham remainder,
// so the value at a level never depends on the path to it). Inside a block the interpolation
// is off (1) by at most +-0.75 K/n = +-1.2 % in acceleration, so the ramp runs at 31/32 of the
// configured limit. Per step: a cruise step is compares and adds; a ramp step adds one
// interpolation step; every K levels a new node costs one table reciprocal square root
// (no division). set_speed converts a speed to an interval with one table reciprocal (no
// division). Measured cycle counts: README.
//
// Units. The timer runs at kTickHz (the firmware's Timer5 at prescaler 8: 2 MHz). Intervals
// are Q16.16 ticks inside and whole ticks out, the fractions carried from one interval to the
// next, so edge times stay within one tick of the exact sum. Every interval fits the 16-bit
// compare register: speeds below kTickHz/65534 steps/s count as a stop, and an acceleration
// whose first interval sqrt(2/a) would be longer than 65534 ticks is refused by configure().
//
// Concurrency. next() runs in the step ISR. set_speed, move_to, stop and halt run in the main
// loop with that ISR masked; they compute first and store last, so the masked part is short.
#pragma once

#include <stdint.h>

#include "control/control_math.h"
#include "kinematics/reciprocal.h"

namespace wmra {
namespace control {

enum class RampStatus : uint8_t {
  ok = 0,
  accel_not_positive,      // a <= 0
  accel_too_low,           // the first interval sqrt(2/a) exceeds 65534 ticks
  accel_too_high,          // the interval scale F/sqrt(a) is below half a tick
  min_interval_invalid,    // outside [1, 65534] ticks
  max_interval_invalid,    // below the shortest interval or above 65534 ticks
  speed_range_too_wide,    // more than 2^22 ramp levels between rest and the top speed
};

struct StepRampConfig {
  int32_t accel_steps_s2;       // acceleration limit
  uint16_t min_interval_ticks;  // shortest interval the driver and motor allow (top speed)
  // Longest interval: slower speed commands are a stop. An interval, once scheduled, cannot be
  // cut short, so this bounds how long a speed command can wait behind a slow step (a position
  // loop that creeps at a few steps/s would otherwise hold off a new command for up to 262 ms).
  uint16_t max_interval_ticks = 65534;
};

// Everything the ramp needs from the configuration, computed once (constexpr: the firmware
// can static_assert on .status).
struct StepRampConstants {
  RampStatus status;
  uint32_t first_interval_q16;  // tau(0) = F sqrt(2/a_eff), Q16.16 ticks
  uint16_t node_mantissa;       // F / sqrt(a_eff) in Q16.16 ticks = mantissa << node_exponent
  uint8_t node_exponent;
  uint32_t min_interval_q16;
  uint32_t max_interval_q16;
};

namespace ramp_detail {

// sqrt(n+1) - sqrt(n) for n = 0..256 in UQ32 (entry 0, exactly 1, saturates);
// test_step_ramp checks every entry
inline const uint32_t* level_table() {
  static const uint32_t table[257] WMRA_FLASH = {
    4294967295u, 1779033704u, 1365100574u, 1150833018u, 1013904243u, 916639502u,
    842937017u, 784586646u, 736899888u, 696977243u, 662915876u, 633408139u,
    607521665u, 584571297u, 564040701u, 545532374u, 528734636u, 513399180u,
    499325409u, 486349261u, 474335071u, 463169552u, 452757257u, 443017125u,
    433879806u, 425285573u, 417182668u, 409525988u, 402276021u, 395397987u,
    388861133u, 382638150u, 376704697u, 371038996u, 365621496u, 360434587u,
    355462361u, 350690405u, 346105625u, 341696096u, 337450929u, 333360162u,
    329414654u, 325606008u, 321926490u, 318368963u, 314926833u, 311593993u,
    308364778u, 305233928u, 302196548u, 299248077u, 296384261u, 293601126u,
    290894951u, 288262255u, 285699772u, 283204434u, 280773359u, 278403837u,
    276093312u, 273839376u, 271639756u, 269492305u, 267394993u, 265345898u,
    263343202u, 261385179u, 259470191u, 257596687u, 255763189u, 253968293u,
    252210663u, 250489028u, 248802176u, 247148951u, 245528249u, 243939020u,
    242380256u, 240850997u, 239350324u, 237877357u, 236431254u, 235011208u,
    233616446u, 232246226u, 230899837u, 229576596u, 228275847u, 226996961u,
    225739331u, 224502375u, 223285533u, 222088266u, 220910054u, 219750397u,
    218608813u, 217484838u, 216378023u, 215287937u, 214214162u, 213156294u,
    212113947u, 211086742u, 210074318u, 209076324u, 208092419u, 207122275u,
    206165575u, 205222010u, 204291284u, 203373107u, 202467200u, 201573292u,
    200691120u, 199820431u, 198960976u, 198112517u, 197274821u, 196447661u,
    195630821u, 194824085u, 194027249u, 193240110u, 192462475u, 191694152u,
    190934958u, 190184714u, 189443245u, 188710381u, 187985957u, 187269812u,
    186561790u, 185861738u, 185169508u, 184484956u, 183807940u, 183138324u,
    182475972u, 181820756u, 181172547u, 180531223u, 179896661u, 179268743u,
    178647356u, 178032385u, 177423722u, 176821259u, 176224892u, 175634519u,
    175050040u, 174471358u, 173898376u, 173331004u, 172769148u, 172212722u,
    171661637u, 171115809u, 170575154u, 170039592u, 169509044u, 168983431u,
    168462677u, 167946708u, 167435451u, 166928835u, 166426790u, 165929247u,
    165436141u, 164947405u, 164462975u, 163982788u, 163506782u, 163034898u,
    162567076u, 162103259u, 161643389u, 161187410u, 160735269u, 160286911u,
    159842285u, 159401338u, 158964021u, 158530283u, 158100076u, 157673353u,
    157250066u, 156830171u, 156413621u, 156000373u, 155590383u, 155183609u,
    154780008u, 154379540u, 153982165u, 153587843u, 153196534u, 152808201u,
    152422807u, 152040314u, 151660686u, 151283887u, 150909883u, 150538639u,
    150170122u, 149804298u, 149441134u, 149080599u, 148722661u, 148367289u,
    148014452u, 147664121u, 147316265u, 146970856u, 146627865u, 146287265u,
    145949027u, 145613125u, 145279531u, 144948219u, 144619164u, 144292340u,
    143967722u, 143645284u, 143325004u, 143006856u, 142690818u, 142376865u,
    142064976u, 141755128u, 141447298u, 141141465u, 140837607u, 140535704u,
    140235733u, 139937675u, 139641510u, 139347217u, 139054777u, 138764170u,
    138475378u, 138188382u, 137903162u, 137619702u, 137337982u, 137057985u,
    136779694u, 136503091u, 136228159u, 135954882u, 135683243u, 135413226u,
    135144815u, 134877993u, 134612745u, 134349057u, 134086911u,
  };
  return table;
}

constexpr uint32_t kNoStep = 0xFFFFFFFFu;  // "infinitely long" interval: rest, or stop wanted

}  // namespace ramp_detail

// Constants for a tick rate F, an acceleration a and a minimum interval; status says why not.
constexpr StepRampConstants step_ramp_constants(uint32_t tick_hz, StepRampConfig c) {
  StepRampConstants k{RampStatus::ok, 0, 0, 0, 0, 0};
  if (c.accel_steps_s2 <= 0) {
    k.status = RampStatus::accel_not_positive;
    return k;
  }
  if (c.min_interval_ticks < 1 || c.min_interval_ticks > 65534) {
    k.status = RampStatus::min_interval_invalid;
    return k;
  }
  if (c.max_interval_ticks < c.min_interval_ticks || c.max_interval_ticks > 65534) {
    k.status = RampStatus::max_interval_invalid;
    return k;
  }
  // a_eff = 31 a / 32. tau(0) = F sqrt(2/a_eff) = F sqrt(2^38 / (31 a)) / 2^16 ticks;
  // the node scale F / sqrt(a_eff) = F sqrt(2^37 / (31 a)) / 2^16 ticks.
  const uint64_t a31 = 31ull * (uint64_t)c.accel_steps_s2;
  const uint64_t first = ((uint64_t)tick_hz * isqrt64((1ull << 62) / a31) + 2048u) >> 12;
  const uint64_t scale = ((uint64_t)tick_hz * isqrt64((1ull << 61) / a31) + 2048u) >> 12;
  if (first > 65534ull * 65536ull) {
    k.status = RampStatus::accel_too_low;
    return k;
  }
  if (scale < 32768u) {
    k.status = RampStatus::accel_too_high;
    return k;
  }
  // levels between rest and the top speed: about (scale / min)^2 / 2; at most 2^22 keeps
  // the interpolation blocks within 2^15 levels
  const uint64_t ratio_q16 = scale / c.min_interval_ticks;  // (scale / min) in Q16
  if (ratio_q16 >= (2896ull << 16)) {
    k.status = RampStatus::speed_range_too_wide;
    return k;
  }
  uint8_t e = 0;
  uint64_t m = scale;
  while (m >= 65536u) {
    m = (m + 1) >> 1;
    ++e;
  }
  k.first_interval_q16 = (uint32_t)first;
  k.node_mantissa = (uint16_t)m;
  k.node_exponent = e;
  k.min_interval_q16 = (uint32_t)c.min_interval_ticks << 16;
  k.max_interval_q16 = ((uint32_t)c.max_interval_ticks << 16) | 0xFFFFu;  // its fraction included
  return k;
}

template <uint32_t kTickHz>
class StepRamp {
  static_assert(kTickHz >= 1000u && kTickHz <= 16000000u, "timer tick rate out of range");

 public:
  struct Step {
    uint16_t interval_ticks;  // ticks from the previous step edge to this one; 0 = no step (idle)
    int8_t dir;               // +1 or -1; set the DIR pin before this edge
  };

  // Speeds below this are a stop (their interval would not fit 16 bits).
  static constexpr uint32_t kMinSpeedStepsPerS = (kTickHz + 65533u) / 65534u;

  StepRamp() { halt(); }

  // Sets the limits and halts; the position count is kept. On an error the ramp keeps its
  // previous limits (or, never configured, never moves).
  RampStatus configure(const StepRampConfig& config) {
    const StepRampConstants k = step_ramp_constants(kTickHz, config);
    if (k.status != RampStatus::ok) return k.status;
    k_ = k;
    configured_ = true;
    halt();
    return RampStatus::ok;
  }

  // Run at a signed speed (steps/s), within the acceleration limit; 0 brakes to rest.
  void set_speed(int32_t speed_steps_s) {
    const uint32_t want = interval_for_speed(magnitude_u32(speed_steps_s));
    const int8_t dir = speed_steps_s < 0 ? -1 : 1;
    want_q16_ = want;
    want_dir_ = dir;
    has_target_ = false;
    fast_steps_ = 0;
    ramp_fast_ = 0;
  }

  // Go to a position (steps) and stop there exactly, at most at max_speed_steps_s.
  void move_to(int32_t target_steps, uint32_t max_speed_steps_s) {
    const uint32_t want = interval_for_speed(max_speed_steps_s);
    target_ = clamp_i32(target_steps, -kPositionLimit, kPositionLimit);
    want_q16_ = want;
    has_target_ = want != ramp_detail::kNoStep;
    fast_steps_ = 0;
    ramp_fast_ = 0;
  }

  // Brake to rest at the acceleration limit.
  void stop() {
    want_q16_ = ramp_detail::kNoStep;
    has_target_ = false;
    fast_steps_ = 0;
    ramp_fast_ = 0;
  }

  // Forget the speed at once (the caller has cut the driver: e-stop, fault). No more steps.
  void halt() {
    want_q16_ = ramp_detail::kNoStep;
    want_dir_ = 1;
    has_target_ = false;
    level_ = 0;
    frac_ = 0;
    running_ = false;
    fast_steps_ = 0;
    ramp_fast_ = 0;
    lo_q16_ = k_.first_interval_q16;
    hi_q16_ = ramp_detail::kNoStep;
    walk_reset();
  }

  // Sets the position count (homing). Only at rest.
  bool set_position(int32_t steps) {
    if (level_ != 0 || running_) return false;
    position_ = clamp_i32(steps, -kPositionLimit, kPositionLimit);
    return true;
  }

  // The next step: called at each step edge (and once to start from rest); counts the step
  // it returns. {0, 0}: no step; the ramp is at rest and stays so until a new command.
  Step next() {
    if (fast_steps_ != 0) {  // steady: the same interval again (known safe for these steps)
      --fast_steps_;
      position_ += dir_;
      const uint32_t t = last_q16_ + frac_;
      frac_ = (uint16_t)t;
      return Step{fx::hi16(t), dir_};
    }
    if (ramp_fast_ > 0) return ramp_step_up();  // inside an interpolation block, known direction
    if (ramp_fast_ < 0) return ramp_step_down();
    return decide();
  }

  int32_t position_steps() const { return position_; }
  bool running() const { return running_; }
  // True when next() would give a step: the caller starts the timer if !running().
  bool wants_step() const {
    if (!configured_ || want_q16_ == ramp_detail::kNoStep) return level_ != 0;
    return !has_target_ || target_ != position_ || level_ != 0;
  }
  uint32_t level() const { return level_; }
  int8_t direction() const { return dir_; }
  uint32_t last_interval_q16() const { return last_q16_; }
  const StepRampConstants& constants() const { return k_; }

  // tau(level) in Q16.16 ticks, the profile (1) as this ramp evaluates it (tests, planning)
  uint32_t interval_at_level(uint32_t level) const {
    if (level <= 256) return table_interval(level);
    const Block b = block_for(level);
    return b.n0 - interpolated_drop(b, (uint16_t)(level - b.j0));
  }

  // F * 2^16 / speed, for speeds >= kMinSpeedStepsPerS, by a table reciprocal; kNoStep below
  static uint32_t interval_for_speed_unclamped(uint32_t speed) {
    if (speed < kMinSpeedStepsPerS) return ramp_detail::kNoStep;
    // speed = M 2^(e-16) with M in [2^15, 2^16); 2^31/M from the reciprocal table; then
    // F 2^16 / speed = F (2^31/M) 2^(1-e)
    uint8_t e = 32;
    uint32_t v = speed;
    while (!(v & 0x80000000u)) {
      v <<= 1;
      --e;
    }
    const uint16_t h = fx::half_reciprocal_uq16(fx::hi16(v));
    uint32_t p = mul_hi_u32xu16(kTickHz, h);  // F h / 2^16
    if (e <= 17) {
      for (uint8_t i = e; i < 17; ++i) p <<= 1;
    } else {
      for (uint8_t i = 17; i < e; ++i) p >>= 1;
    }
    return p;
  }

 private:
  static constexpr int32_t kPositionLimit = (int32_t)1 << 30;

  // The full decision: speed up, hold or slow down, within the command, the acceleration limit
  // and the stopping distance. Not inlined, so that the short paths of next() stay short.
  __attribute__((noinline)) Step decide() {
    uint32_t want = want_q16_;
    int8_t want_dir = want_dir_;
    int32_t remaining = 0;
    if (has_target_) {
      remaining = target_ - position_;  // both within +-2^30
      if (remaining == 0) {
        want = ramp_detail::kNoStep;
      } else {
        want_dir = remaining > 0 ? 1 : -1;
      }
    }
    if (!configured_) want = ramp_detail::kNoStep;
    if (level_ == 0) {
      if (want == ramp_detail::kNoStep) {
        running_ = false;
        frac_ = 0;
        return Step{0, 0};
      }
      dir_ = want_dir;  // reversals only here, at rest
    } else if (want_dir != dir_) {
      want = ramp_detail::kNoStep;  // brake to rest first
    }
    int8_t action = 0;  // +1 speed up, -1 slow down, 0 hold
    if (level_ != 0 && hi_q16_ < want) {
      action = -1;  // even the next slower ramp step is faster than wanted
    } else if (lo_q16_ > want) {
      action = 1;
    }
    if (has_target_ && action >= 0) {
      // braking from level L takes L steps: keep (steps left after this one) >= new level
      const uint32_t left = (uint32_t)(dir_ > 0 ? remaining : -remaining);
      if (action > 0 && left < level_ + 2) action = 0;
      if (action == 0 && left < level_ + 1) action = -1;
    }
    if ((dir_ > 0 && position_ >= kPositionLimit) || (dir_ < 0 && position_ <= -kPositionLimit)) {
      halt();  // never wraps: the count saturates (30 hours at 20 kHz from zero)
      return Step{0, 0};
    }
    uint32_t interval;
    if (action > 0) {
      interval = lo_q16_;
      hi_q16_ = lo_q16_;
      ++level_;
      walk_up();
      lo_q16_ = walk_value_;
    } else if (action < 0) {
      interval = hi_q16_;
      lo_q16_ = hi_q16_;
      --level_;
      walk_down();
      hi_q16_ = level_ == 0 ? ramp_detail::kNoStep : walk_below();
    } else {
      interval = want < lo_q16_ ? lo_q16_ : want > hi_q16_ ? hi_q16_ : want;
      // the next steps repeat this one until a command, the braking point or the count limit
      const uint32_t to_limit = (uint32_t)(kPositionLimit - (dir_ > 0 ? position_ : -position_)) - 1;
      uint32_t steady = to_limit;
      if (has_target_) {
        const uint32_t left = (uint32_t)(dir_ > 0 ? remaining : -remaining);
        steady = left - 1 - level_;  // left >= level + 1 here
      }
      fast_steps_ = (uint16_t)(steady > 65535u ? 65535u : steady);
    }
    if (action != 0 && !has_target_ && walk_level_ >= 256) plan_ramp_steps(action, want);
    return emit(interval);
  }

  Step emit(uint32_t interval) {
    position_ += dir_;
    last_q16_ = interval;
    running_ = true;
    const uint32_t t = interval + frac_;  // < 65535 * 2^16 + 2^16
    frac_ = (uint16_t)t;
    return Step{fx::hi16(t), dir_};
  }

  // After a ramp step in an interpolation block at a constant speed command: the following
  // steps up to the block's edge are ramp steps in the same sense when the block's end (speeding
  // up) or start (slowing down) is still on the same side of the wanted interval. They then
  // take the short paths below (no decisions, no block change).
  void plan_ramp_steps(int8_t action, uint32_t want) {
    const uint32_t to_limit = (uint32_t)(kPositionLimit - (dir_ > 0 ? position_ : -position_)) - 1;
    uint32_t n = 0;
    if (action > 0) {
      if (block_.n0 - interpolated_drop(block_, block_.k) > want) n = (uint32_t)(block_.k - 1u - walk_off_);
    } else if (block_.n0 < want && walk_off_ >= 2) {
      n = walk_off_ - 1u;
    }
    if (n > to_limit) n = to_limit;
    ramp_fast_ = action > 0 ? (int16_t)n : (int16_t)-(int16_t)n;
  }
  Step ramp_step_up() {
    --ramp_fast_;
    const uint32_t interval = lo_q16_;
    hi_q16_ = interval;
    ++level_;
    ++walk_level_;
    ++walk_off_;
    walk_acc_ += block_.rem;
    uint32_t drop = block_.q;
    if (walk_acc_ >= block_.k) {
      walk_acc_ -= block_.k;
      ++drop;
    }
    walk_value_ -= drop;
    lo_q16_ = walk_value_;
    return emit(interval);
  }
  Step ramp_step_down() {
    ++ramp_fast_;
    const uint32_t interval = hi_q16_;
    lo_q16_ = interval;
    --level_;
    --walk_level_;
    --walk_off_;  // stays >= 1
    uint32_t rise = block_.q;
    if (walk_acc_ < block_.rem) {
      walk_acc_ += block_.k;
      ++rise;
    }
    walk_acc_ -= block_.rem;
    walk_value_ += rise;  // tau(level)
    hi_q16_ = walk_value_ + block_.q + (walk_acc_ < block_.rem ? 1u : 0u);  // tau(level - 1)
    return emit(interval);
  }

  uint32_t interval_for_speed(uint32_t speed) const {
    const uint32_t want = interval_for_speed_unclamped(speed);
    if (want > k_.max_interval_q16) return ramp_detail::kNoStep;
    return want < k_.min_interval_q16 ? k_.min_interval_q16 : want;
  }

  // --- the profile: table below 257 levels, interpolated nodes above

  uint32_t table_interval(uint32_t level) const {
    return mul_hi_u32xu32(k_.first_interval_q16, flash_read_u32(ramp_detail::level_table() + level));
  }

  // tau(j) = F / sqrt(a_eff (2j+1)) for j > 256, by a normalised table reciprocal square root.
  // Once per interpolation block: not inlined (at -O3 its copies made decide() 6.5 KB).
  __attribute__((noinline)) uint32_t node(uint32_t j) const {
    if (j <= 256) return table_interval(j);
    uint8_t s;
    const uint16_t r = rsqrt_normalised(2 * j + 1, s);  // 1/sqrt(2j+1) = r 2^(s-31)
    // tau = mantissa 2^exponent r 2^(s-31)
    return shift_right_rounded(fx::mul_uu(k_.node_mantissa, r), (uint8_t)(31 - k_.node_exponent - s));
  }

  struct Block {
    uint32_t j0;       // first level of the block
    uint32_t n0;       // tau(j0)
    uint32_t q;        // (tau(j0) - tau(j0 + K)) / K, whole part
    uint16_t rem;      // and remainder
    uint16_t k;        // K = 2^log2k
    uint8_t log2k;
  };

  static uint8_t block_log2k(uint32_t level) {  // floor(log2 level) - 6, level >= 256, at most 15
    uint8_t l = 2;
    for (uint32_t v = level >> 9; v != 0 && l < 15; v >>= 1) ++l;
    return l;
  }

  static Block block_of(uint32_t j0, uint8_t log2k, uint32_t n0, uint32_t n1) {
    const uint32_t d = n0 - n1;
    const uint16_t k = (uint16_t)(1u << log2k);
    return Block{j0, n0, d >> log2k, (uint16_t)(d & (k - 1u)), k, log2k};
  }
  Block block_from(uint32_t j0, uint8_t log2k, uint32_t n0) const {
    return block_of(j0, log2k, n0, node(j0 + ((uint32_t)1 << log2k)));
  }
  Block block_for(uint32_t level) const {
    const uint8_t l = block_log2k(level);
    const uint32_t j0 = level & ~(((uint32_t)1 << l) - 1);
    return block_from(j0, l, node(j0));
  }
  // the block that ends at j0 (> 256), whose end node tau(j0) is known
  Block block_ending_at(uint32_t j0, uint32_t n_end) const {
    const uint8_t l = block_log2k(j0 - 1);
    const uint32_t start = j0 - ((uint32_t)1 << l);
    return block_of(start, l, node(start), n_end);
  }
  // floor(off * (n0 - n1) / K)
  static uint32_t interpolated_drop(const Block& b, uint16_t off) {
    return (uint32_t)off * b.q + ((uint32_t)off * b.rem >> b.log2k);
  }

  // The walker holds tau(level) (walk_value_) and its interpolation state; one step up or
  // down is an add and a compare, a new block one node.
  void walk_reset() {
    walk_level_ = 0;
    walk_value_ = k_.first_interval_q16 ? table_interval(0) : 0;
    lo_q16_ = walk_value_;
  }
  void walk_enter(uint32_t level, const Block& b) {
    block_ = b;
    below_valid_ = false;
    const uint16_t off = (uint16_t)(level - b.j0);
    walk_acc_ = (uint16_t)(((uint32_t)off * b.rem) & (((uint32_t)1 << b.log2k) - 1));
    walk_value_ = b.n0 - interpolated_drop(b, off);
    walk_off_ = off;
  }
  void walk_up() {
    const uint32_t level = ++walk_level_;
    if (level <= 256) {
      walk_value_ = table_interval(level);
      if (level == 256) walk_enter(level, block_from(256, block_log2k(256), walk_value_));
      return;
    }
    const uint16_t k = block_.k;
    if (walk_off_ + 1u == k) {  // next block starts at the node this one ends on
      const uint32_t n1 = block_.n0 - interpolated_drop(block_, k);
      walk_enter(level, block_from(level, block_log2k(level), n1));
      return;
    }
    ++walk_off_;
    walk_acc_ += block_.rem;
    uint32_t drop = block_.q;
    if (walk_acc_ >= k) {
      walk_acc_ -= k;
      ++drop;
    }
    walk_value_ -= drop;
  }
  void walk_down() {
    const uint32_t level = --walk_level_;
    if (level < 256) {
      walk_value_ = table_interval(level);
      return;
    }
    if (walk_off_ == 0) {  // into the block below (walk_below usually found it already)
      if (!(below_valid_ && below_.j0 + below_.k == level + 1)) below_ = block_ending_at(level + 1, walk_value_);
      below_valid_ = false;
      walk_enter(level, below_);
      return;
    }
    --walk_off_;
    uint32_t rise = block_.q;
    if (walk_acc_ < block_.rem) {
      walk_acc_ += block_.k;
      ++rise;
    }
    walk_acc_ -= block_.rem;
    walk_value_ += rise;
  }
  // tau(walk_level_ - 1) without moving (at a block start it finds the block below and keeps it)
  uint32_t walk_below() {
    const uint32_t level = walk_level_ - 1;
    if (level < 256) return table_interval(level);
    if (walk_off_ == 0) {
      below_ = block_ending_at(walk_level_, walk_value_);
      below_valid_ = true;
      return below_.n0 - interpolated_drop(below_, (uint16_t)(below_.k - 1u));
    }
    return walk_value_ + block_.q + (walk_acc_ < block_.rem ? 1u : 0u);
  }

  StepRampConstants k_{RampStatus::ok, 0, 0, 0, 0, 0};
  bool configured_ = false;
  // command
  uint32_t want_q16_ = ramp_detail::kNoStep;
  int8_t want_dir_ = 1;
  bool has_target_ = false;
  int32_t target_ = 0;
  // state
  int32_t position_ = 0;
  uint32_t level_ = 0;
  int8_t dir_ = 1;
  bool running_ = false;
  uint32_t lo_q16_ = 0;  // tau(level): the next step when speeding up
  uint32_t hi_q16_ = ramp_detail::kNoStep;  // tau(level - 1): the next step when slowing down
  uint32_t last_q16_ = 0;
  uint16_t frac_ = 0;
  // walker at walk_level_ == level_
  uint32_t walk_level_ = 0;
  uint32_t walk_value_ = 0;
  uint16_t walk_off_ = 0;
  uint16_t walk_acc_ = 0;
  Block block_{0, 0, 0, 0, 1, 0};
  Block below_{0, 0, 0, 0, 1, 0};
  bool below_valid_ = false;
  uint16_t fast_steps_ = 0;  // steps known to repeat the last interval
  int16_t ramp_fast_ = 0;    // > 0: steps known to speed up, < 0: to slow down, inside the block
};

}  // namespace control
}  // namespace wmra
