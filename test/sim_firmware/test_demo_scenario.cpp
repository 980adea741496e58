// scripts/demo's session, scenarios/demo.txt, run as armsim runs it (run.h, with its files):
// it shows what it says it shows. The telemetry goes through start-up (homing, the ready
// pose) to running, every mode of the cycle is reached and the stick moves the arm in each
// (in the gripper mode the firmware reads it), the safety button stops the arm with every output off, and after the
// re-arm it runs and moves again; no step lost, no reset, and its report.html renders.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sys/wait.h>

#include "armsim/firmware_telemetry.h"
#include "armsim/run.h"
#include "config/modes_config.h"
#include "core/supervisor.h"
#include "plant/arm_plant_config.h"

namespace {

using namespace wmra;
using armsim::TrajectoryRow;
using core::ArmState;

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kScenario = std::string(SCENARIOS_DIR) + "/demo.txt";
const std::string kOut = std::string(DEMO_OUT) + "/demo";

// the stick in a mode moved the arm: the hand 20 mm, the wrist 0.2 rad (full stick for a
// second is about 150 mm, 0.8 rad)
constexpr double kMoved_mm = 20, kTurned_rad = 0.2;
// the firmware read a full stick (shaped, in [-1000, 1000])
constexpr int kFullStick_permille = 900;
// stopped: the worm-geared DC joints hold (0.1 mrad); a stepper whose DRV8825 is disabled lets
// its rotor fall into the nearest detent, at most one full step at the joint
double stopped_travel_allowed_rad(int j) {
  const bool stepper = j == 0 || j == 4 || j == 5;
  return stepper ? 2 * M_PI / plant::kFullStepsPerRev / plant::kGearRatio[j] : 1e-4;
}

double distance_mm(const TrajectoryRow& a, const TrajectoryRow& b) {
  return 1000 * std::sqrt((a.p[0] - b.p[0]) * (a.p[0] - b.p[0]) + (a.p[1] - b.p[1]) * (a.p[1] - b.p[1]) +
                          (a.p[2] - b.p[2]) * (a.p[2] - b.p[2]));
}

double turned_rad(const TrajectoryRow& a, const TrajectoryRow& b) {
  double trace = 0;
  for (int i = 0; i < 9; ++i) trace += a.r[i] * b.r[i];
  return std::acos(std::max(-1.0, std::min(1.0, (trace - 1) / 2)));
}

// one stretch of rows in one state and mode: how far things got from its first row
struct Stretch {
  ArmState state;
  int mode;
  TrajectoryRow first;
  double hand_mm = 0, wrist_rad = 0;
  bool outputs_always_off = true;
  std::array<double, 6> q_min = first.q, q_max = first.q;
};

struct DemoRun {
  armsim::Scenario scenario;
  armsim::FirmwareTelemetry telemetry;
  armsim::RunResult result;
  std::vector<Stretch> stretches;
};

void run_demo(DemoRun* r) {
  r->scenario = armsim::load_scenario(kScenario);
  armsim::RunOptions options;
  options.elf = kFirmware;
  options.out_dir = kOut;
  options.title = "demo.txt";
  options.telemetry = &r->telemetry;
  r->result = armsim::run_scenario(r->scenario, options, [r](const sim::ArmSimulator& sim, const TrajectoryRow& row) {
    if (row.state < 0) return;
    std::vector<Stretch>& s = r->stretches;
    if (s.empty() || (int)s.back().state != row.state || s.back().mode != row.mode)
      s.push_back(Stretch{(ArmState)row.state, row.mode, row, 0, 0, true});
    Stretch& now = s.back();
    now.hand_mm = std::max(now.hand_mm, distance_mm(row, now.first));
    now.wrist_rad = std::max(now.wrist_rad, turned_rad(row, now.first));
    now.outputs_always_off &= sim.outputs_off();
    for (int j = 0; j < 6; ++j) {
      now.q_min[j] = std::min(now.q_min[j], row.q[j]);
      now.q_max[j] = std::max(now.q_max[j], row.q[j]);
    }
  });
}

void check_states(const DemoRun& d) {
  std::vector<ArmState> states;
  for (const Stretch& s : d.stretches)
    if (states.empty() || states.back() != s.state) states.push_back(s.state);
  const std::vector<ArmState> expected = {ArmState::wait_neutral, ArmState::homing,       ArmState::to_ready,
                                          ArmState::running,      ArmState::stopped,      ArmState::wait_neutral,
                                          ArmState::running};
  std::string seen;
  for (ArmState s : states) seen += std::string(core::to_string(s)) + " ";
  std::printf("demo: states %s\n", seen.c_str());
  EXPECT_EQ(states, expected) << seen;
  EXPECT_EQ(d.result.trajectory.back().state, (int)ArmState::running);
  EXPECT_TRUE(d.result.measurements.resets.empty());
  EXPECT_EQ(d.telemetry.boots().size(), 1u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(d.result.measurements.steps[k].lost, 0) << "stepper " << k;
}

void check_modes(const DemoRun& d) {
  // the most each mode moved in running, over its stretches
  std::map<int, Stretch> best;
  for (const Stretch& s : d.stretches) {
    if (s.state != ArmState::running) continue;
    Stretch& b = best.emplace(s.mode, s).first->second;
    b.hand_mm = std::max(b.hand_mm, s.hand_mm);
    b.wrist_rad = std::max(b.wrist_rad, s.wrist_rad);
  }
  for (config::Mode m : config::kModeCycle) {
    const auto it = best.find((int)m);
    ASSERT_NE(it, best.end()) << "mode " << (int)m << " never reported while running";
    const Stretch& b = it->second;
    std::printf("demo: mode %d: hand %.1f mm, wrist %.3f rad\n", (int)m, b.hand_mm, b.wrist_rad);
    switch (m) {
      case config::Mode::xy:
      case config::Mode::xz: EXPECT_GE(b.hand_mm, kMoved_mm) << "mode " << (int)m; break;
      case config::Mode::r1:
      case config::Mode::r2: EXPECT_GE(b.wrist_rad, kTurned_rad) << "mode " << (int)m; break;
      // the simulator does not measure the firmware's servo pulse (Timer1 toggling its
      // compare pin in normal mode): the telemetry shows the stick read at full both ways
      case config::Mode::gripper: {
        int stick_min = 0, stick_max = 0;
        for (const protocol::StateMsg& f : d.telemetry.states()) {
          if (f.mode != (uint8_t)m || f.state != (uint8_t)ArmState::running) continue;
          stick_min = std::min<int>(stick_min, f.stick_permille[1]);
          stick_max = std::max<int>(stick_max, f.stick_permille[1]);
        }
        EXPECT_GE(stick_max, kFullStick_permille);
        EXPECT_LE(stick_min, -kFullStick_permille);
        break;
      }
    }
  }
}

void check_safety_stop(const DemoRun& d) {
  const std::vector<sim::EstopReaction>& estop = d.result.measurements.estop;
  ASSERT_EQ(estop.size(), 1u) << "the scenario presses the safety button once";
  ASSERT_GE(estop[0].outputs_off_s, 0) << "outputs never went off";
  const double reaction_ms = 1000 * (estop[0].outputs_off_s - estop[0].pressed_s);
  bool stopped_seen = false, moved_after = false;
  for (const Stretch& s : d.stretches) {
    if (s.state == ArmState::stopped) {
      stopped_seen = true;
      std::printf("demo: safety button, outputs off in %.3f ms; stopped from %.2f s, hand moved %.2f mm\n", reaction_ms,
                  s.first.t_s, s.hand_mm);
      EXPECT_TRUE(s.outputs_always_off);
      for (int j = 0; j < 6; ++j) EXPECT_LE(s.q_max[j] - s.q_min[j], stopped_travel_allowed_rad(j)) << "joint " << j + 1;
    } else if (stopped_seen && s.state == ArmState::running) {
      moved_after |= s.hand_mm >= kMoved_mm;
    }
  }
  EXPECT_LE(reaction_ms, 1.0);  // SPEC 9, S5
  EXPECT_TRUE(stopped_seen);
  EXPECT_TRUE(moved_after) << "the stick moves the hand after the re-arm";
}

void check_report() {
  const std::string page = kOut + "/report.html";
  FILE* p = popen((std::string(CHECK_REPORT) + " " + page + " 2>&1").c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string output;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) output += buf;
  const int status = pclose(p);
  std::printf("%s", output.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
}

}  // namespace

// one run (36 s simulated, about 10 s here), every check on it
TEST(DemoScenario, ShowsWhatItClaims) {
  DemoRun d;
  run_demo(&d);
  ASSERT_TRUE(d.result.completed);
  {
    SCOPED_TRACE("start-up, stop, re-arm");
    check_states(d);
  }
  {
    SCOPED_TRACE("every mode");
    check_modes(d);
  }
  {
    SCOPED_TRACE("the safety button");
    check_safety_stop(d);
  }
  {
    SCOPED_TRACE("report.html");
    check_report();
  }
}
