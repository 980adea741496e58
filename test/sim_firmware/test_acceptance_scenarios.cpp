// SPEC 9's acceptance scenarios S4, S6, S8 and S9: the firmware ELF against the virtual arm.
// What the firmware says comes from its telemetry; whether the arm moved, and whether a limit
// switch closed, from the plant (true joint angles, the switch contacts).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "config/modes_config.h"
#include "config/motion_config.h"
#include "core/faults.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;
using test::command;
using test::kFirmware;
using test::message;
using test::Rig;

constexpr double kDeg = arm::kPi / 180;

double distance_mm(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return 1000 * std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

bool has_fault(const protocol::StateMsg& s, uint8_t bit) { return (s.faults & core::fault_mask(bit)) != 0; }

// What the plant did while a test ran, sampled every millisecond: the joints' extremes, the
// limit switches (as the board sees them, and the contacts themselves: a joint at or past its
// limit), and whether any output was on.
struct PlantWatch {
  plant::Joints q_min, q_max;
  bool switch_closed = false;  // a limit switch of J1..J5 as the Mega reads it
  bool at_limit = false;       // a joint at or past its switch's angle
  bool driven = false;         // a bridge or a DRV8825 on
  void reset(const plant::Joints& q) {
    q_min = q_max = q;
    switch_closed = at_limit = driven = false;
  }
  void sample(const sim::ArmSimulator& sim) {
    const plant::Joints q = sim.q();
    for (int j = 0; j < 6; ++j) {
      q_min[j] = std::min(q_min[j], q[j]);
      q_max[j] = std::max(q_max[j], q[j]);
      at_limit |= q[j] >= arm::q_max_rad(j) || q[j] <= arm::q_min_rad(j);
    }
    for (int j = 0; j < 5; ++j) switch_closed |= sim.plant().limit_closed(j, false) || sim.plant().limit_closed(j, true);
    driven |= !sim.outputs_off();
  }
  double travel_rad(int j) const { return q_max[j] - q_min[j]; }
  double largest_travel_rad() const {
    double m = 0;
    for (int j = 0; j < 6; ++j) m = std::max(m, travel_rad(j));
    return m;
  }
};

// A rig in running with its plant watched, at rest with the stick neutral
struct Running {
  Rig rig;
  PlantWatch watch;
  double t_running_s;
  double t_rest_s = -1;  // when the arm came to rest in running, -1: it did not within 2 s
  explicit Running(const plant::Joints& initial_q = test::kNearHome) : rig(kFirmware, initial_q) {
    t_running_s = rig.run_until_state(core::ArmState::running, 12.0);
    if (t_running_s < 0) return;
    // the steppers' rotors settle behind the last steps of the move to the ready pose (J1: 5
    // mrad in 0.3 s); at rest, no joint moves 0.05 mrad in 0.2 s (a creep of 0.25 mrad/s would)
    for (double t = t_running_s; t < t_running_s + 2.0 && t_rest_s < 0; t += 0.2) {
      const plant::Joints q = rig.sim.q();
      rig.run_to(t + 0.2);
      double moved = 0;
      for (int j = 0; j < 6; ++j) moved = std::max(moved, std::fabs(rig.sim.q()[j] - q[j]));
      if (moved < 5e-5) t_rest_s = rig.sim.time_s();
    }
    watch.reset(rig.sim.q());
    rig.sim.every(0.001, [this](const sim::ArmSimulator& s) { watch.sample(s); });
  }
  bool ok() const { return t_running_s > 0 && t_rest_s > 0; }
  int64_t steps_commanded() const {
    int64_t n = 0;
    for (const sim::StepperCounts& c : rig.sim.measurements().steps) n += c.commanded;
    return n;
  }
};

// The hand twist (base frame, frame-6 origin) that turns joint j alone at rate_rad_s from the
// plant's pose, by central differences of the host's double FK, as a streamed velocity command.
protocol::VelocityCmd joint_twist(const plant::Joints& q, int j, double rate_rad_s) {
  constexpr double h = 1e-6;
  plant::Joints qp = q, qm = q;
  qp[j] += h;
  qm[j] -= h;
  const armsim::TrajectoryRow a = armsim::trajectory_row(0, qp, 0, 0), b = armsim::trajectory_row(0, qm, 0, 0),
                              c = armsim::trajectory_row(0, q, 0, 0);
  // W = dR/dq R^T is the skew matrix of the joint's axis
  double w[3][3] = {};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) w[r][k] += (a.r[3 * r + i] - b.r[3 * r + i]) / (2 * h) * c.r[3 * k + i];
  const double axis[3] = {w[2][1], w[0][2], w[1][0]};
  protocol::VelocityCmd cmd{};
  for (int i = 0; i < 3; ++i) {
    cmd.v_mm_s[i] = (int16_t)std::lround((a.p[i] - b.p[i]) / (2 * h) * rate_rad_s * 1000);
    cmd.w_mrad_s[i] = (int16_t)std::lround(axis[i] * rate_rad_s * 1000);
  }
  return cmd;
}

// S4: every short press moves to the next mode of config::kModeCycle, and the last one back to
// the first; the telemetry shows each mode in turn and no other. The stick is neutral, so
// nothing moves: no step, no drive out of its park, the gripper's pulse unchanged.
TEST(AcceptanceScenarios, S4ShortPressesCycleThroughEveryMode) {
  Running r;
  ASSERT_TRUE(r.ok()) << "running at " << r.t_running_s << " s, at rest at " << r.t_rest_s << " s";
  Rig& rig = r.rig;
  ASSERT_EQ(rig.last().mode, (uint8_t)config::kModeCycle[0]);
  const size_t first_frame = rig.telemetry.states().size();
  const int64_t steps_before = r.steps_commanded();
  const double gripper_before_us = rig.sim.gripper_pulse_us();
  const armsim::TrajectoryRow pose_before = rig.pose();
  double t = r.t_rest_s;
  for (uint8_t press = 1; press <= config::kModeCount; ++press) {
    rig.sim.set_button(true);
    rig.run_to(t += plant::kButtonPressS);
    rig.sim.set_button(false);
    rig.run_to(t += 0.5);
    EXPECT_EQ(rig.last().mode, (uint8_t)config::kModeCycle[press % config::kModeCount]) << "after press " << (int)press;
    EXPECT_EQ(rig.state(), core::ArmState::running);
  }
  // the modes the state frames reported, in order, each once
  std::vector<uint8_t> seen;
  for (size_t i = first_frame; i < rig.telemetry.states().size(); ++i) {
    const uint8_t m = rig.telemetry.states()[i].mode;
    if (seen.empty() || seen.back() != m) seen.push_back(m);
  }
  std::vector<uint8_t> cycle;
  for (uint8_t i = 0; i <= config::kModeCount; ++i) cycle.push_back((uint8_t)config::kModeCycle[i % config::kModeCount]);
  EXPECT_EQ(seen, cycle);
  // nothing moved
  const double hand_mm = distance_mm(rig.pose().p, pose_before.p);
  std::printf("S4: %.2f s of presses, hand moved %.3f mm, largest joint travel %.3f mrad\n", t - r.t_rest_s,
              hand_mm, 1000 * r.watch.largest_travel_rad());
  EXPECT_EQ(r.steps_commanded(), steps_before);
  EXPECT_EQ(rig.sim.gripper_pulse_us(), gripper_before_us);
  EXPECT_LE(hand_mm, 0.1);
  EXPECT_LE(r.watch.largest_travel_rad(), 1e-4);
}

}  // namespace
