// Resolved-rate motion from the stick or a stream (motion.h).
#include "app/motion.h"

#include "app/arm.h"
#include "app/dc_drives.h"
#include "app/tick_plan.h"
#include "app/velocity_request.h"
#include "config/derived.h"
#include "core/joint_acceleration.h"
#include "core/resolved_rate.h"
#include "core/stick_twist.h"
#include "drivers/bridges.h"
#include "drivers/steppers.h"
#include "drivers/system_tick.h"
#include "kinematics/inverse_jacobian.h"

namespace wmra {
const core::MotionLimits config::kMotionLimits = config::kLimits;

namespace app {
namespace motion {

namespace {

using namespace config;
using kin::Fixed;

// each joint reference's largest change of speed in a motion pass
constexpr fx::Real per_pass(uint8_t j) { return fx::Real{kMaxSpeedChangePerTick[j].raw * plan::kMotionPeriod_ticks}; }
// (J1's and J5's entries follow the pose: g_arm.j1_max_change_per_tick, j5_max_change_per_tick)
fx::Real g_max_speed_change_per_pass[6] = {per_pass(0), per_pass(1), per_pass(2), per_pass(3), per_pass(4), per_pass(5)};
// The drift correction's hand position goes with the holding effort (plan::kHolding): its time
// constant is 1 / kDriftGain_per_s, and the error it corrects (the integrated references'
// rounding) grows over seconds.
static_assert(plan::period(plan::kHolding) * kDriftGain_per_s <= 1000 / 20, "the correction updated 20 times per time constant");
static_assert(kHandPositionAge_ms >= 2 * plan::period(plan::kHolding), "the report takes the drift correction's position after an overrun too");

kin::Vec3<fx::Real> g_v_m_s;       // the hand's commanded velocity, as far as the joints' speeds have reached it
kin::Vec3<fx::Real> g_p_cmd;       // the hand's commanded position (the drift correction's goal)
kin::Vec3<fx::Real> g_drift_m_s;   // the drift correction, held between its updates
kin::Vec3<fx::Real> g_p_hand;      // the drift correction's hand position (FK of the references), for the report
uint32_t g_p_hand_ms = 0u - kHandPositionAge_ms;  // and tick::now_ms() when it was (none yet: too old)
kin::JacobianTrig<Fixed> g_pass_trig;  // the last motion pass's, or the holding update's own
kin::Vec3<fx::Real> g_kept_p_cmd;      // the commanded position the pass before the holding update started from
bool g_kept;                           // that pass ran, and the holding update has not yet read them
bool g_drift_from_kept;                // the holding update took them: the drift pairs with the kept position
int32_t g_gripper_us_q15;  // pulse width, us x 32768
bool g_gripper_driven;     // the servo has a pulse: the person has moved the gripper since power-up
bool g_streaming;          // the last iteration's motion followed a streamed velocity
bool g_stream_halted;      // the stream stopped arriving: the joints halted, the stick waits for rest
uint8_t g_stream_halt_ms;
// The drift correction held off (ms left) after it took part in a motion slowed for a singular factor
constexpr uint16_t kDriftHoldOff_ms = 500;
uint16_t g_drift_hold_off_ms;

// The stream's halt lets the DC joints come to rest before the stick drives again; ramping the
// references down along the stick's ramps instead lets the hand run on 28-34 mm past the last
// frame (the rule: at rest within 0.3 s of it, at most 25 mm from 0.15 m/s, 100 ms of that at
// full speed before the timeout).
constexpr uint8_t kStreamHalt_ms = 60;

// the drift correction's velocity for a position error (Q23 m): error x gain, within the
// largest correction (config/derived.h): one 16x16 product
fx::Real drift_correction(int32_t error) {
  if (error > kMaxCorrectedError) return fx::Real{kDriftGain_per_s > 0 ? kMaxCorrection : 0};
  if (error < -kMaxCorrectedError) return fx::Real{kDriftGain_per_s > 0 ? -kMaxCorrection : 0};
  const int32_t c = (int32_t)fx::mul_uu((uint16_t)(error < 0 ? -error : error), (uint16_t)kDriftGain_per_s);
  return fx::Real{error < 0 ? -c : c};
}

// The servo gets no pulse until the person first moves the stick in the gripper mode: the first
// pulse sends it to kGripperStart_us from wherever it is, which must never happen unasked
// (passing through the mode with the stick neutral moves nothing).
void gripper_tick(int16_t stick_y_q15, uint8_t ticks) {
  if (stick_y_q15 == 0 && !g_gripper_driven) return;
  g_gripper_driven = true;
  constexpr core::Scale kRate = core::scale_for(kGripperRate_us_per_s / (double)kLoopHz);
  constexpr int32_t kMin = (int32_t)kGripperMin_us << 15, kMax = (int32_t)kGripperMax_us << 15;
  g_gripper_us_q15 += core::apply(kRate, stick_y_q15) * ticks;  // us x 32768 per tick: y/32768 x rate x 32768
  if (g_gripper_us_q15 < kMin) g_gripper_us_q15 = kMin;
  if (g_gripper_us_q15 > kMax) g_gripper_us_q15 = kMax;
  tick::set_servo_pulse_us((uint16_t)(g_gripper_us_q15 >> 15));
}

// The commanded position over the ticks that passed at once: each step times ticks is the same
// sum as a tick at a time (a component at rest, most of a mode's, moves nothing).
void integrate_commanded(uint8_t ticks) {
  constexpr core::Scale kPerTick = core::scale_for(1.0 / kLoopHz);
  if (g_v_m_s.x.raw != 0) g_p_cmd.x.raw += core::ticks_times(core::apply(kPerTick, g_v_m_s.x.raw), ticks);
  if (g_v_m_s.y.raw != 0) g_p_cmd.y.raw += core::ticks_times(core::apply(kPerTick, g_v_m_s.y.raw), ticks);
  if (g_v_m_s.z.raw != 0) g_p_cmd.z.raw += core::ticks_times(core::apply(kPerTick, g_v_m_s.z.raw), ticks);
}

// the twist scaled by `factor` (the speed scale and the DC joints' lag together)
void scale_twist(kin::TwistWrist<Fixed>& twist, fx::Unit factor) {
  twist.v_m_s = {core::scaled(factor, twist.v_m_s.x), core::scaled(factor, twist.v_m_s.y), core::scaled(factor, twist.v_m_s.z)};
  twist.w5_rad_s = {core::scaled(factor, twist.w5_rad_s.x), core::scaled(factor, twist.w5_rad_s.y), core::scaled(factor, twist.w5_rad_s.z)};
}

}  // namespace

void start_gripper() { g_gripper_us_q15 = (int32_t)kGripperStart_us << 15; }

void start() {
  g_p_cmd = kin::hand_position<Fixed>(kin::jacobian_trig<Fixed>(g_arm.q.q));
  g_drift_m_s = {fx::Real{0}, fx::Real{0}, fx::Real{0}};  // what it is with the commanded position where the hand is
  g_v_m_s = {fx::Real{0}, fx::Real{0}, fx::Real{0}};
  g_drift_hold_off_ms = 0;
  for (uint8_t j = 0; j < 6; ++j) g_arm.q.qd_rad_s[j] = fx::Real{0};
  g_stream_halted = g_streaming = false;
}

// stick (or stream) -> twist -> scaled -> + drift correction -> J^-1 -> joint limits and drives
// -> acceleration limit -> references
void pass(const control::JoystickOutput& stick, const Requests& rq, uint8_t ticks, bool keep_for_holding) {
  const kin::JointAngles<Fixed>& q = g_arm.q.q;
  // no joint 6: the twist, the hand's position and J^-1 do not use it
  kin::fill_jacobian_trig<Fixed>(q, g_pass_trig);
  const kin::JacobianTrig<Fixed>& trig = g_pass_trig;

  const config::Mode mode = g_arm.supervisor.mode();
  // w about the wrist axes, where J^-1 takes it (a streamed velocity's is turned there)
  kin::TwistWrist<Fixed> twist = rq.velocity_fresh
                                   ? velocity_twist(rq, trig)
                                   : core::stick_twist(mode, core::Stick{fx::Unit{stick.x_q15}, fx::Unit{stick.y_q15}});
  if (!rq.velocity_fresh && mode == config::Mode::gripper) {
    gripper_tick(config::kStickYSign > 0 ? stick.y_q15 : (int16_t)-stick.y_q15, ticks);
  }
  const fx::Unit tracking = dc_drives::tracking_factor();
  const fx::Unit factor = g_arm.speed_scale.raw == fx::kUnitOne ? tracking : g_arm.speed_scale * tracking;
  if (factor.raw != fx::kUnitOne) scale_twist(twist, factor);

  // the drift correction goes into the twist; the commanded velocity, without it, is what the
  // commanded position integrates
  const kin::Vec3<fx::Real> v_cmd = twist.v_m_s;
  const bool with_drift = g_drift_hold_off_ms == 0;
  if (with_drift) twist.v_m_s = {v_cmd.x + g_drift_m_s.x, v_cmd.y + g_drift_m_s.y, v_cmd.z + g_drift_m_s.z};
  else g_drift_hold_off_ms = ticks < g_drift_hold_off_ms ? (uint16_t)(g_drift_hold_off_ms - ticks) : 0;

  kin::JacobianInverse<Fixed> inv = kin::inverse_jacobian_wrist<Fixed>(trig, twist);
  const fx::Unit singular = core::singular_scale(q, trig, inv);
  // The drift correction never takes the arm towards a singularity, nor blocks the person's
  // motion there (SPEC 5): a motion slowed for a singular factor goes on without it for
  // kDriftHoldOff_ms, judged on the person's twist alone, and then the correction is tried
  // again. (Judging both in the same pass needs a second J^-1, ~2,900 cycles: the longest
  // iteration then passes its tick.)
  if (with_drift && singular.raw < fx::kUnitOne) g_drift_hold_off_ms = kDriftHoldOff_ms;
  const core::RateScale rates = core::joint_rate_scale(singular, q, inv, kMotionLimits, g_arm.drives);
  const uint16_t closed = g_arm.drives.closed_switches;
  const uint8_t slowed_by = closed ? core::named_switch_stop(rates.slowed_by, inv, closed) : rates.slowed_by;
  g_arm.status.slowed_by = (uint8_t)(slowed_by | (tracking.raw < fx::kUnitOne ? core::kSlowTracking : 0));
  // J1 speeding up (or reversing) at most at the pose's bound: its lag behind its field then adds
  // to a stop's travel; slowing down, the rotor leads its field and a stop shortens its swing (at
  // the acceleration the pose's inertia allows)
  const int32_t j1_now = g_arm.q.qd_rad_s[0].raw, j1_wanted = core::scaled(rates.scale, inv.qd_rad_s[0]).raw;
  const bool j1_speeding_up = j1_now >= 0 ? (j1_wanted > j1_now || j1_wanted < 0) : (j1_wanted < j1_now || j1_wanted > 0);
  const fx::Real j1_change = j1_speeding_up ? g_arm.j1_max_change_per_tick : g_arm.j1_max_brake_per_tick;
  // J5 speeding up a lift of the wrist at most at what its motor's torque left beyond gravity
  // gives; slowing down a lowering at its limit (the soft limits' braking counts on it; a worm
  // that does not back-drive takes the load, and one that does needs a stronger motor anyway)
  const int32_t j5_wanted = core::scaled(rates.scale, inv.qd_rad_s[4]).raw, j5_now = g_arm.q.qd_rad_s[4].raw;
  const int32_t j5_lift_wanted = g_arm.j5_lift_way < 0 ? -j5_wanted : j5_wanted, j5_lift_now = g_arm.j5_lift_way < 0 ? -j5_now : j5_now;
  const bool j5_speeding_lift = g_arm.j5_lift_way != 0 && j5_lift_wanted > 0 && j5_lift_wanted > j5_lift_now;
  const fx::Real j5_change = j5_speeding_lift ? g_arm.j5_max_change_per_tick : kMaxSpeedChangePerTick[4];
  fx::Real max_change[6];
  if (ticks != plan::kMotionPeriod_ticks) {
    for (uint8_t j = 0; j < 6; ++j) max_change[j] = fx::Real{kMaxSpeedChangePerTick[j].raw * ticks};
    max_change[0] = fx::Real{j1_change.raw * ticks};
    max_change[4] = fx::Real{j5_change.raw * ticks};
  } else {
    g_max_speed_change_per_pass[0] = fx::Real{j1_change.raw * plan::kMotionPeriod_ticks};
    g_max_speed_change_per_pass[4] = fx::Real{j5_change.raw * plan::kMotionPeriod_ticks};
  }
  const fx::Unit k = core::limit_joint_acceleration(g_arm.q.qd_rad_s, inv.qd_rad_s, rates.scale,
                                                    ticks == plan::kMotionPeriod_ticks ? g_max_speed_change_per_pass : max_change);
  // the hand's commanded velocity as far as the joints' speeds have reached it
  if (k.raw == fx::kUnitOne && rates.scale.raw == fx::kUnitOne) {
    g_v_m_s = v_cmd;
  } else {
    g_v_m_s.x = g_v_m_s.x + core::scaled(k, core::scaled(rates.scale, v_cmd.x) - g_v_m_s.x);
    g_v_m_s.y = g_v_m_s.y + core::scaled(k, core::scaled(rates.scale, v_cmd.y) - g_v_m_s.y);
    g_v_m_s.z = g_v_m_s.z + core::scaled(k, core::scaled(rates.scale, v_cmd.z) - g_v_m_s.z);
  }
  if (keep_for_holding) {
    g_kept_p_cmd = g_p_cmd;
    g_kept = true;
  }
  integrate_commanded(ticks);
  g_arm.q.advance_ticks(ticks);
}

// While the stick drives, the motion pass a tick before kept its trig and commanded position (the
// references at that pass's start, two ticks old: the load's angle sums move a quarter of what
// they move between two updates, and the correction's hand position stays paired with its
// commanded one); a trig of its own makes the holding tick the loop's longest (~600 cycles more).
const kin::JacobianTrig<Fixed>& holding_trig(bool stick_drives) {
  g_drift_from_kept = stick_drives && g_kept;
  g_kept = false;
  if (!g_drift_from_kept) kin::fill_jacobian_trig<Fixed>(g_arm.q.q, g_pass_trig);
  return g_pass_trig;
}

const kin::JacobianTrig<Fixed>& last_trig() { return g_pass_trig; }

// Towards the integrated commanded position from the hand's position; both are of the same
// references, sampled together, so the held correction has no lag term of its own.
void update_drift(const kin::JacobianTrig<Fixed>& trig) {
  const kin::Vec3<fx::Real>& p_cmd = g_drift_from_kept ? g_kept_p_cmd : g_p_cmd;
  const kin::Vec3<fx::Real>& p = g_p_hand = kin::hand_position<Fixed>(trig);
  g_p_hand_ms = tick::now_ms();
  g_drift_m_s = {drift_correction((p_cmd.x - p.x).raw), drift_correction((p_cmd.y - p.y).raw), drift_correction((p_cmd.z - p.z).raw)};
}

bool streaming() { return g_streaming; }
void set_streaming(bool fresh) { g_streaming = fresh; }

// the bridges brake, the step trains end (or, above a start/stop rate, ramp down)
void halt_lost_stream() {
  bridges::all_off();
  steppers::halt_trains();
  for (uint8_t j = 0; j < 6; ++j) g_arm.q.qd_rad_s[j] = fx::Real{0};
  g_stream_halted = true;
  g_stream_halt_ms = 0;
}

bool stream_halted() { return g_stream_halted; }

bool stream_halt_over(uint8_t ticks) {
  g_stream_halt_ms = control::add_saturated_u8(g_stream_halt_ms, ticks);
  return g_stream_halt_ms >= kStreamHalt_ms;
}

bool recent_hand_position(kin::Vec3<fx::Real>& p_m) {
  const uint32_t now_ms = tick::now_ms();
  if (now_ms - g_p_hand_ms < kHandPositionAge_ms) {
    p_m = g_p_hand;
    return true;
  }
  g_p_hand_ms = now_ms - kHandPositionAge_ms;  // kept old: 2^32 ms on (49.7 days) it would read as fresh
  return false;
}

}  // namespace motion
}  // namespace app
}  // namespace wmra
