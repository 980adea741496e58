// The DC joints J2, J3, J4: pots, servos, holding effort and speed governor (dc_drives.h).
#include "app/dc_drives.h"

#include "app/arm.h"
#include "app/flash_config.h"
#include "config/derived.h"
#include "core/dc_servo.h"
#include "core/gravity.h"
#include "drivers/bridges.h"

namespace wmra {
namespace app {
namespace dc_drives {

namespace {

using namespace config;
using kin::Fixed;

// A DC joint's state that its servo's run reads, together: run_servo reaches every field from
// one address (a table per field costs an address sum each, ~100 cycles a run).
struct DcJoint {
  int16_t units;               // measured, ADC counts x 16 (< 16,368)
  int16_t reference_units;     // the reference in pot units, as the last servo run drove it
  int16_t lag_fault_units;     // capped at 32767: a reference less a reading is at most 32,752
  int16_t holding_q15;         // the holding effort's duty at the reference pose (core::HoldingEffort)
  int16_t holding_effort_q15;  // the same as the servo's effort (through the dead-zone inverse)
  int16_t still_units;         // where it came to rest after a stop (mark_rest)
  uint8_t still_wait;          // the pot read at a rail: iterations until its rest is taken afresh
  int16_t standstill_units;    // kStandstillMove_mdeg in pot units (configure_pot)
  fx::Real qd_prev;            // the reference's speed of the last servo run (its acceleration)
  core::PotMap pot;
};

core::DcServo g_servo[3];
DcJoint g_dc[3];
int32_t g_lag_slow_units[3], g_lag_stop_units[3];
int16_t g_lag_inverse[3];  // 32767 / (stop - slow)
uint8_t g_servo_elapsed;   // control ticks since the servos last ran
uint8_t g_servo_ticks;     // and at this servo tick, the ticks its run spans
const core::DcServoConfig kServoConfigInFlash[3] PROGMEM = {kDcServoConfig[0], kDcServoConfig[1], kDcServoConfig[2]};

// |duty| <= 32767 in, the effort saturated to +-32767 out, in 16 bits: the dead-zone inverse's
// 1 / slope as 1 + (1 / slope - 1), one 16x16 product (a 32-bit division is ~600 cycles)
int16_t effort_for_duty(int16_t duty_q15) {
  const int16_t extra = (int16_t)fx::hi16((uint32_t)(fx::mul_ss(duty_q15, kInverseSlopeLess1_q16) + 32768));
  int16_t effort;
  if (__builtin_add_overflow(duty_q15, extra, &effort)) return duty_q15 < 0 ? (int16_t)-32767 : (int16_t)32767;
  return effort == -32768 ? (int16_t)-32767 : effort;
}

constexpr uint8_t kOverrunTicks = 8;  // past this many a run is one (the term is bounded below)
constexpr int16_t kOneOverTicks[kOverrunTicks + 1] = {0, 32767, 16384, 10923, 8192, 6554, 5461, 4681, 4096};

// The feedforward's duty for the reference's speed and its change: the speed over the drive's
// full-duty speed, the load's lifting effort, the inertia's share of the change (a self-locking
// worm's braking moves the rotor only).
int16_t feedforward_q15(uint8_t d, DcJoint& dc, fx::Real qd_raw, uint8_t ticks) {
  // a reference creeping slower than the standing speed (the drift correction's trickle) stands:
  // no effort of a motion, the servo parks and follows it a count at a time
  const fx::Real qd = qd_raw.raw < kDcStandingSpeed && qd_raw.raw > -kDcStandingSpeed ? fx::Real{0} : qd_raw;
  // the change per tick: a run spans `ticks` of them (its period, more after an overrun); past
  // two ticks a product by 1/ticks (a 32-bit division would lengthen the longest iterations)
  int32_t change = qd.raw - dc.qd_prev.raw;
  if (ticks == 2) change >>= 1;
  else if (ticks > 2) change = (fx::Unit{kOneOverTicks[ticks < kOverrunTicks ? ticks : kOverrunTicks]} * fx::Real{change}).raw;
  dc.qd_prev = qd;
  // one tick's change at most the acceleration limit's (a larger one: the reference started or
  // stopped standing), which fits 16 bits
  const int16_t accel = (int16_t)(change > kMaxDcChange ? kMaxDcChange : change < -kMaxDcChange ? -kMaxDcChange : change);
  if (qd.raw == 0 && accel == 0) return 0;  // it stands and stood: every term 0
  const bool slowing = (accel < 0) != (qd.raw < 0);  // the change opposes the speed
  const DcFeedforward& k = kDcFeedforward[d];
  int32_t duty = qd.raw == 0 ? 0 : ((k.per_speed * qd).raw >> 8) + core::lifting_effort_q15(dc.holding_q15, qd.raw);
  if (accel != 0) duty += fx::mul_ss(accel, slowing ? k.brake_q8 : k.accel_q8) >> 16;
  return effort_for_duty(control::saturate_i16(duty));
}

void run_servo(uint8_t d, DcJoint& dc, core::DcServo& servo) {
  const uint8_t ticks = g_servo_ticks;
  const int16_t reference = dc.pot.units(g_arm.q.q.q[kDcJoint[d]]);
  dc.reference_units = reference;
  const int16_t lag = (int16_t)(reference - dc.units);  // [-16384 - 16368, 16383]
  if (lag > dc.lag_fault_units || lag < -dc.lag_fault_units) raise_fault(core::kFaultBitTracking);
  const int16_t feedforward = feedforward_q15(d, dc, g_arm.q.qd_rad_s[kDcJoint[d]], ticks);
  bridges::set(d, servo.update(reference, dc.units, feedforward, dc.holding_effort_q15, ticks));
}

// A lag of `mrad` in pot units, from the calibration's pot units over Angle counts (integers,
// like PotMap::make; Q24 counts per mrad): floor(units mrad K / counts / 2^24) =
// floor(floor(a K / 2^24) / counts) with a = units mrad (floors compose), the product a K in
// 16-bit halves (a 64-bit one links libgcc's 64-bit multiply and division, ~700 B):
// a K = ah kh 2^32 + (ah kl + al kh) 2^16 + al kl, each term within 32 bits for a < 2^24
int32_t lag_units(uint16_t units, uint32_t counts, uint16_t mrad) {
  constexpr uint16_t kh = (uint16_t)(kAngleCountsPerMrad_q24 >> 16), kl = (uint16_t)kAngleCountsPerMrad_q24;
  const uint32_t a = fx::mul_uu(units, mrad);
  const uint16_t ah = (uint16_t)(a >> 16), al = (uint16_t)a;
  const uint32_t middle = fx::mul_uu(ah, kl) + fx::mul_uu(al, kh) + (fx::mul_uu(al, kl) >> 16);
  const uint32_t a_k_q24 = (fx::mul_uu(ah, kh) << 8) + (middle >> 8);  // floor(a K / 2^24)
  return (int32_t)(a_k_q24 / counts);
}

}  // namespace

void configure_pot(const Settings& settings, uint8_t d) {
  using L = kin::JointLimits<Fixed>;
  const uint8_t j = kDcJoint[d];
  const int32_t at_min = settings.pot_at_min_counts_x16[d], at_max = settings.pot_at_max_counts_x16[d];
  g_dc[d].pot = core::PotMap::make(L::min[j], L::max[j], at_min, at_max);
  const uint16_t units = (uint16_t)(at_max - at_min);  // within [600, 1023] counts x 16 (settings.cpp)
  const uint32_t counts = (uint32_t)(L::max[j].raw - L::min[j].raw);
  g_lag_slow_units[d] = lag_units(units, counts, kTrackingSlowFrom_mrad);
  g_lag_stop_units[d] = lag_units(units, counts, kTrackingStopAt_mrad);
  const int32_t fault_units = lag_units(units, counts, kTrackingFault_mrad);
  g_dc[d].lag_fault_units = (int16_t)(fault_units > 32767 ? 32767 : fault_units);
  g_lag_inverse[d] = (int16_t)(32767 / (g_lag_stop_units[d] - g_lag_slow_units[d]));
  g_dc[d].standstill_units = (int16_t)lag_units(units, counts, (uint16_t)(kStandstillMove_mdeg * 3.14159265 / 180 + 0.5));
}

void configure(const Settings& settings) {
  for (uint8_t d = 0; d < 3; ++d) {
    configure_pot(settings, d);
    g_servo[d].configure(from_flash(kServoConfigInFlash[d]));
  }
}

// The motion checks (stall, sign error) run with the servo, in its tick before it runs: the duty
// they judge changes only then, so each of their windows spans the one duty. The rail and jump
// checks every reading, every tick: a jump is a change within a tick (over a servo's period it
// would let a glitch twice as large through).
void read_and_check(const uint16_t* pot_counts, uint8_t ticks, bool servo_tick) {
  g_servo_elapsed = control::add_saturated_u8(g_servo_elapsed, ticks);
  g_servo_ticks = servo_tick ? g_servo_elapsed : 0;
  if (servo_tick) g_servo_elapsed = 0;
  for (uint8_t d = 0; d < 3; ++d) {
    g_dc[d].units = (int16_t)(pot_counts[d] * kPositionUnitsPerCount);
    const uint8_t flags = g_servo[d].check(g_dc[d].units, ticks, g_servo_ticks);
    if (flags) g_arm.faults |= core::dc_joint_faults(d, flags);
  }
}

void run_servos() {
  for (uint8_t d = 0; d < 3; ++d) run_servo(d, g_dc[d], g_servo[d]);
}

void hold() {
  bridges::all_off();
  for (uint8_t d = 0; d < 3; ++d) {
    g_servo[d].rest(g_dc[d].units);
    g_arm.q.set(kDcJoint[d], g_dc[d].pot.angle(g_dc[d].units));
  }
}

// (a stop at speed left the references' last speeds, whose change would be one tick's braking
// feedforward)
void start() {
  for (uint8_t d = 0; d < 3; ++d) {
    g_servo[d].rest(g_dc[d].units);
    g_arm.q.set(kDcJoint[d], g_dc[d].pot.angle(g_dc[d].units));
    g_dc[d].reference_units = g_dc[d].units;
    g_dc[d].qd_prev = fx::Real{0};
  }
}

void reset_checks() {
  for (uint8_t d = 0; d < 3; ++d) g_servo[d].reset_checks(g_dc[d].units);
}

// The references in pot units are each servo's last run's (a tick old at most: at a DC joint's
// top speed 1.6 mrad, against lags of 15 and 50 mrad; after start(), the measured units).
fx::Unit tracking_factor() {
  int32_t f = fx::kUnitOne;
  for (uint8_t d = 0; d < 3; ++d) {
    int32_t lag = g_dc[d].reference_units - g_dc[d].units;
    if (lag < 0) lag = -lag;
    if (lag <= g_lag_slow_units[d]) continue;
    const int32_t fd = lag >= g_lag_stop_units[d] ? 0 : (g_lag_stop_units[d] - lag) * g_lag_inverse[d];
    if (fd < f) f = fd;
  }
  return fx::Unit{(int16_t)(f > fx::kUnitOne ? fx::kUnitOne : f)};
}

void update_holding(const kin::JacobianTrig<Fixed>& trig) {
  const core::HoldingEffort holding = core::holding_effort(trig);
  for (uint8_t d = 0; d < 3; ++d) {
    const int16_t h = g_dc[d].holding_q15 = holding.duty_q15[d];
    g_dc[d].holding_effort_q15 = effort_for_duty(h);
  }
}

// The model plans with the duty beyond the stiction's (the dead-zone inverse's slope), and keeps
// the reserve's share of what is left after the holding effort for the PID. Each way, the
// servo's effort is bounded by the speed limit's and the load's lifting (the feedforward's model
// at the limit speed, without the acceleration's term).
void update_governor() {
  for (uint8_t d = 0; d < 3; ++d) {
    const int16_t h = g_dc[d].holding_q15;
    g_servo[d].set_effort_bounds(
        effort_for_duty(control::saturate_i16((int32_t)kLimitDuty_q15[d] + core::lifting_effort_q15(h, 1))),
        effort_for_duty(control::saturate_i16((int32_t)kLimitDuty_q15[d] - core::lifting_effort_q15(h, -1))));
    const int16_t up = (int16_t)(kUsableDuty_q15 - (h > 0 ? h : 0)), down = (int16_t)(kUsableDuty_q15 - (h < 0 ? -h : 0));
    g_arm.drives.positive_rad_s[kDcJoint[d]] = fx::Unit{up > 0 ? up : (int16_t)0} * kPlannedSpeed[d];
    g_arm.drives.negative_rad_s[kDcJoint[d]] = fx::Unit{down > 0 ? down : (int16_t)0} * kPlannedSpeed[d];
  }
}

void mark_rest() {
  for (uint8_t d = 0; d < 3; ++d) {
    g_dc[d].still_units = g_dc[d].units;
    g_dc[d].still_wait = 0;
  }
}

// A pot at a rail (open, shorted: its own fault) tells nothing of where its joint is, and its
// reading's return from the rail is no move: the joint's rest is taken afresh once the reading
// has been off the rail for kStandstillSettle_ms (the pot's input filter settles within it).
bool moved_from_rest() {
  static_assert(kStandstillSettle_ms < 256, "the settling count fits a byte");
  bool moved = false;
  for (uint8_t d = 0; d < 3; ++d) {
    DcJoint& dc = g_dc[d];
    if (dc.units <= kPotRailLow_units || dc.units >= kPotRailHigh_units) {
      dc.still_wait = (uint8_t)kStandstillSettle_ms;
      continue;
    }
    if (dc.still_wait != 0) {
      if (--dc.still_wait == 0) dc.still_units = dc.units;
      continue;
    }
    const int16_t delta = (int16_t)(dc.units - dc.still_units);
    if (delta > dc.standstill_units || delta < -dc.standstill_units) moved = true;
  }
  return moved;
}

int16_t units(uint8_t d) { return g_dc[d].units; }
fx::Angle angle(uint8_t d) { return g_dc[d].pot.angle(g_dc[d].units); }

}  // namespace dc_drives
}  // namespace app
}  // namespace wmra
