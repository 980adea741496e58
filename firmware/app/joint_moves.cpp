// Joint-space moves to a pose (joint_moves.h).
#include "app/joint_moves.h"

#include "app/arm.h"
#include "app/dc_drives.h"
#include "app/stepper_drives.h"
#include "config/derived.h"
#include "core/joint_move.h"
#include "core/ready_roll.h"
#include "drivers/steppers.h"

namespace wmra {
namespace app {
namespace joint_moves {

namespace {

using namespace config;
using kin::Fixed;

core::JointMove g_move;
int32_t g_ready_angle[6];
bool g_at_target;
bool g_line_done;              // the references are on the target: the joints settle onto it
kin::Vec3<fx::Real> g_move_p;  // the hand at the move's last measurement (hand_per_lead)
int32_t g_move_lead_at;        // and the lead joint's reference then
bool g_move_p_valid;
fx::Unit g_move_hand;          // the last measurement (0: none yet)

int32_t target_steps(uint8_t i) { return stepper_drives::steps_of(i, fx::Angle{g_move.target()[kStepperJoint[i]]}); }

// The hand's speed per unit of the lead joint's, from the hand's position (the references' FK)
// now and at the last measurement, once the lead has moved 32 counts (0.8 mrad) since:
// |dp| / dtheta_lead, as a Unit of m/rad over core::kReachScale_m (0: none yet).
fx::Unit hand_per_lead() {
  const core::JointReferences& r = g_arm.q;
  const kin::Vec3<fx::Real> p = kin::hand_position<Fixed>(kin::jacobian_trig<Fixed>(r.q));
  const int32_t lead_at = r.q.q[g_move.lead()].raw;
  if (g_move_p_valid) {
    const uint32_t dtheta = (uint32_t)(lead_at > g_move_lead_at ? lead_at - g_move_lead_at : g_move_lead_at - lead_at);
    // the components in Q19 m (within 16 bits: at most 7 mm in 4 ticks at the joints' limits)
    const int16_t dx = (int16_t)((p.x.raw - g_move_p.x.raw) >> 4), dy = (int16_t)((p.y.raw - g_move_p.y.raw) >> 4),
                  dz = (int16_t)((p.z.raw - g_move_p.z.raw) >> 4);
    const uint32_t dp_q19 = fx::isqrt32((uint32_t)fx::mul_ss(dx, dx) + (uint32_t)fx::mul_ss(dy, dy) + (uint32_t)fx::mul_ss(dz, dz));
    if (dtheta < 32) return g_move_hand;  // the baseline kept until the lead has moved enough
    // |dp| 2^-19 m / (dtheta / kAngleCountsPerRad rad) / 1.25 m x 2^15
    constexpr uint16_t kScale = (uint16_t)(core::kAngleCountsPerRad * 32768.0 / 524288.0 / core::kReachScale_m + 1);
    const uint32_t q15 = fx::mul_uu((uint16_t)(dp_q19 > 0xFFFF ? 0xFFFF : dp_q19), kScale) / dtheta;
    g_move_hand = fx::Unit{(int16_t)(q15 > 32767 ? 32767 : q15 == 0 ? 1 : q15)};
  }
  g_move_p = p;
  g_move_lead_at = lead_at;
  g_move_p_valid = true;
  return g_move_hand;
}

}  // namespace

// (worked out in the homing's last tick: the move's first tick is the heaviest of a start-up)
void plan_ready_pose() {
  for (uint8_t j = 0; j < 6; ++j) g_ready_angle[j] = g_arm.settings->pose_angle[0][j];
  constexpr int32_t kSlack = fx::angle_deg(Ratio{kSoftLimitMargin_deg + kHomeSwitch_deg[2], 1}).raw;
  g_ready_angle[5] = core::ready_roll(g_ready_angle[5], g_arm.q.q.q[5].raw, fx::kAngleTurn, kLimits.joint[5].soft_min.raw,
                                      kLimits.joint[5].soft_max.raw, kSlack);
}

void begin_ready() { begin(g_ready_angle); }

void begin(const int32_t* angles) {
  int32_t from[6];
  for (uint8_t j = 0; j < 6; ++j) {
    from[j] = g_arm.q.q.q[j].raw;
    g_arm.q.qd_rad_s[j] = fx::Real{0};
  }
  g_move.begin(from, angles);
  g_at_target = g_line_done = g_move_p_valid = false;
  g_move_hand = fx::Unit{0};
}

// The line's shares first (one a tick), then its speed cap in the plan's cap ticks (which carry
// neither the holding update nor the governor), the references along the line, the steppers
// tracking them. Arrived: the references on the target, every stepper at rest on it and every
// DC joint's pot within the tolerance of it (the pots' angles, a conversion each, only then).
void tick(bool cap_tick, bool ramp_tick) {
  core::JointReferences& r = g_arm.q;
  if (!g_move.prepared()) {
    stepper_drives::limit_speeds(false);  // J5 free to lift: the stick's lift limit would cap the move to a creep
    if (g_move.prepare(kMoveLimits)) g_move.set_speed_cap(kMoveLimits, g_arm.drives, g_arm.speed_scale, dc_drives::tracking_factor());
  } else if (!g_line_done) {
    if (cap_tick) g_move.set_speed_cap(kMoveLimits, g_arm.drives, g_arm.speed_scale, dc_drives::tracking_factor(), hand_per_lead());
    int32_t references[6];
    for (uint8_t j = 0; j < 6; ++j) references[j] = r.q.q[j].raw;
    if (g_move.tick(references, r.qd_rad_s)) {
      for (uint8_t j = 0; j < 6; ++j) {
        r.set(j, fx::Angle{g_move.target()[j]});
        r.qd_rad_s[j] = fx::Real{0};
      }
      for (uint8_t i = 0; i < 3; ++i) steppers::rate(i).move_to(target_steps(i), kSettleSpeed[i]);
      g_line_done = true;
    } else {
      r.advance_ticks(1);
    }
  }
  if (!g_line_done && ramp_tick) stepper_drives::track();
  bool at_target = g_line_done;
  for (uint8_t i = 0; at_target && i < 3; ++i) {
    if (steppers::rate(i).position_steps() != target_steps(i) || steppers::running(i)) at_target = false;
  }
  constexpr int32_t kTolerance = (int32_t)(kArrivedTolerance_mdeg / 1000.0 / 360.0 * fx::kAngleTurn);
  for (uint8_t d = 0; at_target && d < 3; ++d) {
    const int32_t error = dc_drives::angle(d).raw - g_move.target()[kDcJoint[d]];
    if (error > kTolerance || error < -kTolerance) at_target = false;
  }
  g_at_target = at_target;
}

bool arrived() { return g_at_target; }
void brake() { g_move.brake(); }
bool braked_to_rest() { return g_move.braking() && g_move.lead_speed().raw == 0; }

}  // namespace joint_moves
}  // namespace app
}  // namespace wmra
