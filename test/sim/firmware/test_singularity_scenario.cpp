// S7 (docs/design.md): stretching the arm through sin q3 = 0. The firmware ELF in the simulator, in XY
// from the ready pose (q1 = 70 deg, q3 = -70 deg): full stick about along the arm pushes the
// hand outwards until the elbow straightens, the stick stays there, then it is reversed.
// The plant's true joint angles, sampled every millisecond, show no joint over its speed limit
// (config/motion_config.h) and no jump; the telemetry names the singularity slow-down and no
// fault; reversed, the stick drives the hand back and the elbow out of the slow band.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "config/motion_config.h"
#include "core/faults.h"
#include "core/resolved_rate.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;
using test::kFirmware;
using test::distance_mm;
using test::Rig;

constexpr double kSampleS = 0.001;
// the plant may go this much over a joint's limit: the DC joints follow their references in
// stick-slip steps of a pot count or two, so a joint catching up moves a little faster than
// commanded
constexpr double kSpeedMargin = 0.05;
// joint speeds are measured over 10 ms (the trajectory's rows)
constexpr int kSpeedWindowSamples = 10;
// stick about along the arm at q1 = 70 deg (after the square-to-disc mapping), full deflection
constexpr double kStickOutX = 0.3, kStickOutY = 1.0;
constexpr double kOutS = 3.5, kHoldS = 0.5, kBackS = 2.0;
// driven back, the hand comes this much nearer to where it started: clearly a motion, not
// noise or a DC joint settling (those are a few millimetres)
constexpr double kBackMin_mm = 50;

double limit_rad_s(int j) { return config::kJointSpeedLimit_crad_s[j] / 100.0; }

struct Sample {
  double t_s;
  plant::Joints q;
};

// the fastest each joint moved over kSpeedWindowSamples, and the largest change between two
// consecutive samples, in [t0, t1]
struct JointMotion {
  double speed_rad_s[6] = {}, speed_at_s[6] = {}, step_rad[6] = {};
};

JointMotion joint_motion(const std::vector<Sample>& samples, double t0_s, double t1_s) {
  JointMotion m;
  for (size_t k = 1; k < samples.size(); ++k) {
    if (samples[k].t_s < t0_s || samples[k].t_s > t1_s) continue;
    for (int j = 0; j < 6; ++j) {
      m.step_rad[j] = std::max(m.step_rad[j], std::fabs(samples[k].q[j] - samples[k - 1].q[j]));
      if (k < (size_t)kSpeedWindowSamples) continue;
      const Sample& a = samples[k - kSpeedWindowSamples];
      const double v = std::fabs(samples[k].q[j] - a.q[j]) / (samples[k].t_s - a.t_s);
      if (v > m.speed_rad_s[j]) {
        m.speed_rad_s[j] = v;
        m.speed_at_s[j] = samples[k].t_s;
      }
    }
  }
  return m;
}

TEST(SingularityScenario, S7StretchingTheElbowStaysWithinJointSpeedsAndDrivesBack) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0) << "never running";
  ASSERT_EQ(rig.last().mode, (uint8_t)config::Mode::xy);
  const double t_out = t_running + 1.0;  // the steppers' rotors settle after the move to the ready pose
  rig.run_to(t_out);
  const size_t first_frame = rig.telemetry.states().size();
  const armsim::TrajectoryRow start = rig.pose();
  std::vector<Sample> samples;
  rig.sim.every(kSampleS, [&samples](const sim::ArmSimulator& s) { samples.push_back({s.time_s(), s.q()}); });

  rig.sim.set_joystick(kStickOutX, kStickOutY);
  rig.run_to(t_out + kOutS);
  const armsim::TrajectoryRow stretched = rig.pose();
  rig.run_to(t_out + kOutS + kHoldS);  // still pushing: it goes no further
  const double t_back = t_out + kOutS + kHoldS;
  const armsim::TrajectoryRow pushed = rig.pose();
  const size_t back_frame = rig.telemetry.states().size();
  rig.sim.set_joystick(-kStickOutX, -kStickOutY);
  rig.run_to(t_back + kBackS);
  rig.sim.set_joystick(0, 0);
  rig.run_to(t_back + kBackS + 0.5);
  const armsim::TrajectoryRow back = rig.pose();

  // the elbow straightened into the slow band and stopped short of sin q3 = 0
  double closest_s3 = 1;
  for (const Sample& s : samples) closest_s3 = std::min(closest_s3, std::fabs(std::sin(s.q[2])));
  const double back_s3 = std::fabs(std::sin(back.q[2]));
  const double back_mm = distance_mm(pushed.p, start.p) - distance_mm(back.p, start.p);
  std::printf("S7: hand out %.1f mm, then %.1f mm more while held; closest |sin q3| %.4f (slow band %.2f, damped %.2f); "
              "back %.1f mm nearer the start, |sin q3| %.3f\n",
              distance_mm(stretched.p, start.p), distance_mm(pushed.p, stretched.p), closest_s3,
              to_double(arm::kSingularBands.slow_s3), to_double(arm::kSingularBands.damp_s3), back_mm, back_s3);
  EXPECT_LT(closest_s3, to_double(arm::kSingularBands.slow_s3)) << "the elbow did not straighten into the slow band";
  // and braked in time: the references stop at the damped band's edge, the elbow's lag behind
  // them carries it a fifth of the band further at most, and it never passes through
  EXPECT_GT(closest_s3, 0.8 * to_double(arm::kSingularBands.damp_s3)) << "the elbow ran into the damped band";
  bool crossed = false;
  for (const Sample& s : samples) crossed |= (std::sin(s.q[2]) > 0) != (std::sin(samples.front().q[2]) > 0);
  EXPECT_FALSE(crossed) << "the elbow passed through the stretch";

  // no joint over its limit, no jump: over 10 ms, and from one millisecond to the next
  const JointMotion m = joint_motion(samples, t_out, t_back + kBackS + 0.5);
  for (int j = 0; j < 6; ++j) {
    const double limit = limit_rad_s(j) * (1 + kSpeedMargin);
    std::printf("S7: J%d fastest %.3f rad/s at %.2f s (limit %.2f), largest 1 ms step %.3f mrad\n", j + 1,
                m.speed_rad_s[j], m.speed_at_s[j], limit_rad_s(j), 1000 * m.step_rad[j]);
    EXPECT_LE(m.speed_rad_s[j], limit) << "J" << j + 1 << " at " << m.speed_at_s[j] << " s";
    EXPECT_LE(m.step_rad[j], limit * kSampleS) << "J" << j + 1 << " jumped";
  }

  // the firmware's view: running throughout, no fault (not even a loop overrun), the
  // singularity named, commanded joint speeds within the limits (1 mrad/s: the frame's rounding)
  bool singular_named = false;
  int16_t commanded_max_mrad_s[6] = {};
  for (size_t i = first_frame; i < rig.telemetry.states().size(); ++i) {
    const protocol::StateMsg& s = rig.telemetry.states()[i];
    EXPECT_EQ(s.state, (uint8_t)core::ArmState::running) << "at " << s.t_ms << " ms";
    EXPECT_EQ(s.faults, 0u) << "at " << s.t_ms << " ms";
    if (i < back_frame) singular_named |= (s.slowed_by & core::kSlowSingular) != 0;
    for (int j = 0; j < 6; ++j) {
      commanded_max_mrad_s[j] = std::max<int16_t>(commanded_max_mrad_s[j], (int16_t)std::abs(s.qd_mrad_s[j]));
      EXPECT_LE(std::abs(s.qd_mrad_s[j]), config::kJointSpeedLimit_crad_s[j] * 10 + 1)
          << "J" << j + 1 << " commanded at " << s.t_ms << " ms";
    }
  }
  std::printf("S7: commanded at most %d %d %d %d %d %d mrad/s\n", commanded_max_mrad_s[0], commanded_max_mrad_s[1],
              commanded_max_mrad_s[2], commanded_max_mrad_s[3], commanded_max_mrad_s[4], commanded_max_mrad_s[5]);
  EXPECT_TRUE(singular_named) << "telemetry never named the singularity slow-down";
  for (const sim::StepperCounts& c : rig.sim.measurements().steps) EXPECT_EQ(c.lost, 0);

  // driven back: the hand nearer its start, the elbow out of the slow band
  EXPECT_GE(back_mm, kBackMin_mm);
  EXPECT_GT(back_s3, to_double(arm::kSingularBands.slow_s3));
  EXPECT_EQ(rig.state(), core::ArmState::running);
}

// Never stuck (SPEC 5): with the elbow stopped at the stretch and the stick released, the wrist
// still turns about y5 (R1's and R2's stick X: J6's axis), which leaves the elbow as it is, at
// the stick's speed; the drift correction's pull and J^-1's rounding do not block it. The elbow
// stays on its branch throughout.
TEST(SingularityScenario, AtTheStretchTheWristStillTurns) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0) << "never running";
  double t = t_running + 1.0;
  rig.run_to(t);
  const double s3_start = std::sin(rig.pose().q[2]);
  double closest_s3 = 1;
  bool crossed = false;
  rig.sim.every(kSampleS, [&](const sim::ArmSimulator& s) {
    closest_s3 = std::min(closest_s3, std::fabs(std::sin(s.q()[2])));
    crossed |= (std::sin(s.q()[2]) > 0) != (s3_start > 0);
  });
  rig.sim.set_joystick(kStickOutX, kStickOutY);
  rig.run_to(t += kOutS + kHoldS);
  rig.sim.set_joystick(0, 0);
  rig.run_to(t += 1.0);
  const double s3_stretched = std::fabs(std::sin(rig.pose().q[2]));
  ASSERT_LT(s3_stretched, to_double(arm::kSingularBands.slow_s3)) << "the elbow did not reach the stretch";
  for (config::Mode mode : {config::Mode::r1, config::Mode::r2}) {
    while (rig.last().mode != (uint8_t)mode) {  // short presses to the mode
      rig.sim.set_button(true);
      rig.run_to(t += plant::kButtonPressS);
      rig.sim.set_button(false);
      rig.run_to(t += 0.3);
    }
    for (double x : {1.0, -1.0}) {
      const double q6_before = rig.pose().q[5];
      const double t_turn = t;
      rig.sim.set_joystick(x, 0);
      rig.run_to(t += 1.5);
      rig.sim.set_joystick(0, 0);
      rig.run_to(t += 0.7);
      const double turned = (rig.pose().q[5] - q6_before) * x;
      // the ideal: the stick's ramps (0.3 s) and 0.8 rad/s for the rest of 1.5 s, ~1.08 rad
      std::printf("at the stretch (|sin q3| %.3f), %s stick X %+.0f: J6 turned %.3f rad in %.1f s (slowed_by %u)\n",
                  std::fabs(std::sin(rig.pose().q[2])), mode == config::Mode::r1 ? "R1" : "R2", x, turned, t - t_turn,
                  (unsigned)rig.last().slowed_by);
      EXPECT_GT(turned, 0.9) << (mode == config::Mode::r1 ? "R1" : "R2") << " stick X " << x;
    }
  }
  std::printf("closest |sin q3| %.4f\n", closest_s3);
  EXPECT_FALSE(crossed) << "the elbow passed through the stretch";
  EXPECT_GT(closest_s3, 0.8 * to_double(arm::kSingularBands.damp_s3));
  EXPECT_EQ(rig.state(), core::ArmState::running);
}

}  // namespace
