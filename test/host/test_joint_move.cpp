// A joint-space move (firmware/core/joint_move.h) run tick by tick as the firmware runs it (the
// references advanced by the speeds it gives, JointReferences): it arrives on its target from any
// start, each joint within 1 mrad of where the lead's share of the way puts it (a straight line in
// joint space), the
// lead's speed within its cap and its change within the acceleration, and a move taken over
// slows to rest without passing its target.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/joint_map.h"
#include "core/joint_move.h"
#include "core/resolved_rate.h"

namespace {

using namespace wmra;

core::JointMoveLimits limits() {
  core::JointMoveLimits k{};
  const double speed[6] = {0.4, 0.5, 0.5, 0.8, 0.75, 0.75}, accel[6] = {0.5, 3, 3, 3, 3.5, 3.5};
  const double reach_m[6] = {1.077, 1.063, 0.713, 0.363, 0.198, 0};
  for (int j = 0; j < 6; ++j) {
    k.speed_rad_s[j] = fx::Real{(int32_t)(speed[j] * core::kRealPerRad)};
    k.accel_rad_s2[j] = fx::Real{(int32_t)(accel[j] * core::kRealPerRad)};
    k.reach[j] = fx::Unit{(int16_t)(reach_m[j] / core::kReachScale_m * 32768)};
  }
  k.hand_m_s = fx::Real{(int32_t)(0.15 / core::kReachScale_m * core::kRealPerRad)};
  k.wrist_rad_s = fx::Real{(int32_t)(0.8 * core::kRealPerRad)};
  return k;
}

core::DriveSpeeds free_drives() {
  core::DriveSpeeds d{};
  for (int j = 0; j < 6; ++j) d.positive_rad_s[j] = d.negative_rad_s[j] = fx::Real{(int32_t)(2.0 * core::kRealPerRad)};
  return d;
}

struct MoveRun {
  int ticks = 0;
  double worst_off_line = 0;  // Angle counts: the farthest a joint is from where the lead's share of the way puts it
  double fastest_lead = 0, largest_change = 0;  // rad/s, rad/s per tick
  bool arrived = false;
};

MoveRun run_move(const int32_t* from, const int32_t* to, int brake_at_tick = -1) {
  const core::JointMoveLimits k = limits();
  core::JointMove move;
  move.begin(from, to);
  core::JointReferences refs{};
  for (int j = 0; j < 6; ++j) refs.set((uint8_t)j, fx::Angle{from[j]});
  while (!move.prepare(k)) {
  }
  MoveRun r;
  double v_before = 0;
  for (r.ticks = 0; r.ticks < 60000; ++r.ticks) {
    if (r.ticks % 4 == 0) move.set_speed_cap(k, free_drives(), fx::Unit{(int16_t)fx::kUnitOne}, fx::Unit{(int16_t)fx::kUnitOne});
    if (r.ticks == brake_at_tick) move.brake();
    int32_t now[6];
    for (int j = 0; j < 6; ++j) now[j] = refs.q.q[j].raw;
    if (move.tick(now, refs.qd_rad_s)) {
      r.arrived = true;
      break;
    }
    if (move.braking() && move.lead_speed().raw == 0) break;
    const double v = move.lead_speed().raw / core::kRealPerRad;
    r.fastest_lead = std::max(r.fastest_lead, v);
    r.largest_change = std::max(r.largest_change, std::fabs(v - v_before));
    v_before = v;
    refs.advance_all(false);
    // each joint where the lead's share of its way puts it on the line (Angle counts off it)
    const int lead = move.lead();
    const double share = (double)(refs.q.q[lead].raw - from[lead]) / (to[lead] - from[lead]);
    for (int j = 0; j < 6; ++j)
      r.worst_off_line = std::max(r.worst_off_line, std::fabs(refs.q.q[j].raw - from[j] - share * (to[j] - from[j])));
  }
  // on arrival the firmware sets the references onto the target: they must be within a step of it
  if (r.arrived) {
    for (int j = 0; j < 6; ++j) {
      const int32_t left = to[j] - refs.q.q[j].raw;
      EXPECT_LE(std::abs(left), 400) << "joint " << j + 1 << " far from its target at the line's end";
    }
  }
  return r;
}

TEST(JointMove, EveryMoveArrivesAlongItsLineWithinItsLimits) {
  std::mt19937 rng(5);
  const double lo_deg[6] = {-90, -45, -135, -160, -90, -360}, hi_deg[6] = {90, 135, 160, 160, 90, 360};
  double worst_line = 0, fastest = 0;
  for (int n = 0; n < 300; ++n) {
    int32_t from[6], to[6];
    for (int j = 0; j < 6; ++j) {
      std::uniform_real_distribution<double> in(lo_deg[j], hi_deg[j]);
      from[j] = (int32_t)(in(rng) / 360.0 * fx::kAngleTurn);
      to[j] = n % 7 == 0 && j % 2 ? from[j] : (int32_t)(in(rng) / 360.0 * fx::kAngleTurn);  // some joints stay
    }
    const MoveRun r = run_move(from, to);
    ASSERT_TRUE(r.arrived) << "move " << n << " after " << r.ticks << " ticks";
    EXPECT_LE(r.worst_off_line, 42.0) << "move " << n;
    EXPECT_LE(r.largest_change, 3.5 / 1000 * 1.01) << "move " << n;
    worst_line = std::max(worst_line, r.worst_off_line);
    fastest = std::max(fastest, r.fastest_lead);
  }
  std::printf("300 moves: every joint within %.1f Angle counts of the line, the lead at most %.3f rad/s\n", worst_line,
              fastest);
}

// the sign: a lead joint that moves the negative way (J1 from 70 to 40 deg)
TEST(JointMove, ALeadMovingNegativeGoesToItsTarget) {
  const int32_t from[6] = {(int32_t)(70 / 360.0 * fx::kAngleTurn), 0, 0, 0, 0, 0};
  const int32_t to[6] = {(int32_t)(40 / 360.0 * fx::kAngleTurn), (int32_t)(5 / 360.0 * fx::kAngleTurn), 0, 0, 0, 0};
  const MoveRun r = run_move(from, to);
  EXPECT_TRUE(r.arrived);
  EXPECT_LE(r.worst_off_line, 42.0);
}

// the hand's bound: a move of J2 alone (the hand 1.063 m out at most) at most 0.15 m/s / 1.063 m
TEST(JointMove, TheHandIsBoundedByTheStickSpeed) {
  const int32_t from[6] = {0, 0, 0, 0, 0, 0};
  const int32_t to[6] = {0, (int32_t)(90 / 360.0 * fx::kAngleTurn), 0, 0, 0, 0};
  const MoveRun r = run_move(from, to);
  EXPECT_TRUE(r.arrived);
  EXPECT_LE(r.fastest_lead, 0.15 / 1.063 * 1.01);
  EXPECT_GE(r.fastest_lead, 0.15 / 1.063 * 0.9);
}

// taken over: it slows to rest along its line, short of its target
TEST(JointMove, ATakenOverMoveSlowsToRestOnItsLine) {
  const int32_t from[6] = {0, 0, 0, 0, 0, 0};
  const int32_t to[6] = {(int32_t)(60 / 360.0 * fx::kAngleTurn), 0, 0, (int32_t)(30 / 360.0 * fx::kAngleTurn), 0, 0};
  const MoveRun r = run_move(from, to, 2000);
  EXPECT_FALSE(r.arrived);
  EXPECT_LT(r.ticks, 60000) << "came to rest";
  EXPECT_LE(r.worst_off_line, 42.0);
}

}  // namespace
