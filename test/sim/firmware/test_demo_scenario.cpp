// scripts/demo's session, scenarios/demo.txt, run as armsim runs it (run.h, with its files):
// it shows what it says it shows. The telemetry goes through start-up (the wait for the
// person's long press, homing, the ready pose) to running, every mode of the cycle is reached and the stick moves the arm in each
// (in the gripper mode the firmware reads it), the safety button stops the arm with every output off, and after the
// re-arm it runs and moves again; no fault, no step lost, no reset, and its report.html renders.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sys/wait.h>

#include "armsim/firmware_telemetry.h"
#include "armsim/run.h"
#include "config/control_config.h"
#include "config/modes_config.h"
#include "core/supervisor.h"
#include "plant/arm_plant_config.h"
#include "wmra_mega/board.h"

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
// one tick of the 1 kHz loop at 16 MHz: an iteration's cycles at most
constexpr uint64_t kTick_cycles = board::kCpuHz / config::kLoopHz;
// the firmware read a full stick (shaped, in [-1000, 1000])
constexpr int kFullStick_permille = 900;
// Timer1 counts at 2 MHz: the firmware's pulse widths are whole half-microseconds
constexpr double kPulseResolution_us = 0.5;
// the simulator sees a compare's edge after the instruction under way (up to 5 cycles late)
constexpr double kPulseJitter_us = 0.75;
// stopped: the worm-geared DC joints hold (0.1 mrad); a stepper whose DRV8825 is disabled lets
// its rotor fall into the nearest detent, at most one full step at the joint. Held from
// kCoastDown_s into the stretch: a DC joint that was moving when its bridge went off brakes on
// its shorted motor within a few mechanical time constants (J w0 / T_stall, about 50 ms at the
// worm: J4 stopped 40 ms after the press in the demo, 10 ms into the stopped stretch).
constexpr double kCoastDown_s = 0.2;
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
  bool bridges_always_off = true;        // braking, duty 0
  bool drivers_always_enabled = true;     // the steppers held
  std::array<double, 6> q_min = first.q, q_max = first.q;
  bool coasted = false;                    // kCoastDown_s into the stretch
  std::array<double, 6> rest_min = first.q, rest_max = first.q;  // the joints' range from then on
  double pulse_first_us = -1, pulse_min_us = 1e9, pulse_max_us = 0, pulse_last_us = 0;  // the gripper's D13
};

struct DemoRun {
  armsim::Scenario scenario;
  armsim::FirmwareTelemetry telemetry;
  armsim::RunResult result;
  std::vector<Stretch> stretches;
  // from power-up until the first long press is long (the start's ask): the joints' extremes
  double t_ask_s = -1;
  std::array<double, 6> waiting_q_min{}, waiting_q_max{};
  bool waiting_outputs_off = true;
};

void run_demo(DemoRun* r) {
  r->scenario = armsim::load_scenario(kScenario);
  for (const armsim::Event& e : r->scenario.events) {
    if (e.kind != armsim::Event::Kind::button_down) continue;
    r->t_ask_s = e.t_s + config::kButtonLongPress_ms / 1000.0;  // (from the first sample down: debounce_ms within it)
    break;
  }
  r->waiting_q_min = r->waiting_q_max = r->scenario.init_q;
  armsim::RunOptions options;
  options.elf = kFirmware;
  options.out_dir = kOut;
  options.title = "demo.txt";
  options.telemetry = &r->telemetry;
  r->result = armsim::run_scenario(r->scenario, options, [r](const sim::ArmSimulator& sim, const TrajectoryRow& row) {
    if (row.t_s < r->t_ask_s) {
      r->waiting_outputs_off &= sim.outputs_off();
      for (int j = 0; j < 6; ++j) {
        r->waiting_q_min[j] = std::min(r->waiting_q_min[j], row.q[j]);
        r->waiting_q_max[j] = std::max(r->waiting_q_max[j], row.q[j]);
      }
    }
    if (row.state < 0) return;
    std::vector<Stretch>& s = r->stretches;
    if (s.empty() || (int)s.back().state != row.state || s.back().mode != row.mode)
      s.push_back(Stretch{(ArmState)row.state, row.mode, row, 0, 0, true});
    Stretch& now = s.back();
    now.hand_mm = std::max(now.hand_mm, distance_mm(row, now.first));
    now.wrist_rad = std::max(now.wrist_rad, turned_rad(row, now.first));
    now.bridges_always_off &= sim.bridges_off();
    now.drivers_always_enabled &= sim.drivers_enabled();
    const double pulse_us = sim.gripper_pulse_us();
    if (now.pulse_first_us < 0) now.pulse_first_us = pulse_us;
    now.pulse_min_us = std::min(now.pulse_min_us, pulse_us);
    now.pulse_max_us = std::max(now.pulse_max_us, pulse_us);
    now.pulse_last_us = pulse_us;
    for (int j = 0; j < 6; ++j) {
      now.q_min[j] = std::min(now.q_min[j], row.q[j]);
      now.q_max[j] = std::max(now.q_max[j], row.q[j]);
    }
    if (row.t_s >= now.first.t_s + kCoastDown_s) {
      if (!now.coasted) now.rest_min = now.rest_max = row.q;
      now.coasted = true;
      for (int j = 0; j < 6; ++j) {
        now.rest_min[j] = std::min(now.rest_min[j], row.q[j]);
        now.rest_max[j] = std::max(now.rest_max[j], row.q[j]);
      }
    }
  });
}

void check_states(const DemoRun& d) {
  std::vector<ArmState> states;
  for (const Stretch& s : d.stretches)
    if (states.empty() || states.back() != s.state) states.push_back(s.state);
  const std::vector<ArmState> expected = {ArmState::wait_neutral, ArmState::wait_home, ArmState::homing,
                                          ArmState::to_ready,     ArmState::running,   ArmState::stopped,
                                          ArmState::wait_neutral, ArmState::running};
  std::string seen;
  for (ArmState s : states) seen += std::string(core::to_string(s)) + " ";
  std::printf("demo: states %s\n", seen.c_str());
  EXPECT_EQ(states, expected) << seen;
  EXPECT_EQ(d.result.trajectory.back().state, (int)ArmState::running);
  EXPECT_TRUE(d.result.measurements.resets.empty());
  // After power-up nothing moves until the long press asks (the plant's true angles)
  ASSERT_GT(d.t_ask_s, 0) << "the demo starts with a long press";
  double moved_mrad = 0;
  for (int j = 0; j < 6; ++j) moved_mrad = std::max(moved_mrad, 1000 * (d.waiting_q_max[j] - d.waiting_q_min[j]));
  std::printf("demo: from power-up to the long press at %.2f s, the largest joint movement %.4f mrad\n", d.t_ask_s, moved_mrad);
  EXPECT_LE(moved_mrad, 0.1);
  EXPECT_TRUE(d.waiting_outputs_off);
  // the safety button stops without a fault; none else happens either: no joint lags or stalls,
  // and the loop never overruns a tick (R2 did while its limits slowed the wrist, at 14,750
  // cycles a tick before the motion pass ran every second tick)
  std::string faults;
  for (const std::string& f : d.result.faults) faults += f + " ";
  EXPECT_TRUE(d.result.faults.empty()) << "faults reported: " << faults;
  EXPECT_EQ(d.telemetry.boots().size(), 1u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(d.result.measurements.steps[k].lost, 0) << "stepper " << k;
  // nor does any iteration outlast its tick (the next one starts late; the move to the ready
  // pose's first took 16,238 cycles while the holding update shared it with the servos leaving park)
  const sim::CycleStats& loop = d.result.measurements.loop_high;
  std::printf("demo: control loop mean %.0f, max %llu cycles\n", loop.mean(), (unsigned long long)loop.max);
  EXPECT_LE(loop.max, kTick_cycles);
}

void check_modes(const DemoRun& d) {
  // the most each mode moved in running, over its stretches
  std::map<int, Stretch> best;
  for (const Stretch& s : d.stretches) {
    if (s.state != ArmState::running) continue;
    // outside the gripper mode the servo keeps its pulse (none before the gripper's first use,
    // so that start-up never moves it): the gripper holds what it holds
    if (s.mode != (int)config::Mode::gripper) {
      EXPECT_LE(s.pulse_max_us - s.pulse_min_us, kPulseJitter_us) << "mode " << s.mode << " at " << s.first.t_s << " s";
    }
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
      // the stick's y closes the gripper for 1 s, then opens it for 1 s (scenarios/demo.txt):
      // D13's pulse, measured from its edges, starts at kGripperStart_us (none before), widens
      // and narrows at the configured rate less the stick's ramps (the open phase first ramps
      // down from full, still closing), within 25 % (the ramps count loop iterations: below
      // 1 kHz they last longer), and never leaves the configured range
      case config::Mode::gripper: {
        const double rate_us_ms = config::kGripperRate_us_per_s / 1000.0;
        const double close_us = rate_us_ms * (1000 - config::kStickRise_ms / 2.0);
        const double open_us = rate_us_ms * (1000 - config::kStickFall_ms - config::kStickRise_ms / 2.0);
        std::printf("demo: gripper pulse %.1f us before, widest %.1f us (nominal %.1f), last %.1f us (nominal %.1f)\n",
                    b.pulse_first_us, b.pulse_max_us, config::kGripperStart_us + close_us, b.pulse_last_us,
                    b.pulse_max_us - open_us);
        EXPECT_EQ(b.pulse_first_us, 0);
        EXPECT_GE(b.pulse_max_us - config::kGripperStart_us, 0.75 * close_us);
        EXPECT_GE(b.pulse_max_us - b.pulse_last_us, 0.75 * open_us);
        EXPECT_GE(b.pulse_last_us, config::kGripperMin_us - kPulseResolution_us);
        EXPECT_LE(b.pulse_max_us, config::kGripperMax_us + kPulseResolution_us);
        break;
      }
    }
  }
}

void check_safety_stop(const DemoRun& d) {
  const std::vector<sim::EstopReaction>& estop = d.result.measurements.estop;
  ASSERT_EQ(estop.size(), 1u) << "the scenario presses the safety button once";
  ASSERT_GE(estop[0].bridges_off_s, 0) << "the bridges never braked";
  const double reaction_ms = 1000 * (estop[0].bridges_off_s - estop[0].pressed_s);
  // Each stepper's train ends at once or slows down to an end, its driver enabled
  for (int k = 0; k < 3; ++k) {
    EXPECT_FALSE(estop[0].trains[k].sped_up) << "stepper " << k;
    std::printf("demo: safety button, stepper %d made %lld steps after the press\n", k, (long long)estop[0].trains[k].steps);
  }
  EXPECT_LE(estop[0].trains_stopped_s() - estop[0].pressed_s, kCoastDown_s);
  bool stopped_seen = false, moved_after = false;
  for (const Stretch& s : d.stretches) {
    if (s.state == ArmState::stopped) {
      stopped_seen = true;
      std::printf("demo: safety button, bridges braking in %.3f ms; stopped from %.2f s, hand moved %.2f mm\n", reaction_ms,
                  s.first.t_s, s.hand_mm);
      EXPECT_TRUE(s.bridges_always_off);
      EXPECT_TRUE(s.drivers_always_enabled) << "the steppers' drivers hold the arm";
      ASSERT_TRUE(s.coasted) << "stopped for less than " << kCoastDown_s << " s";
      for (int j = 0; j < 6; ++j) EXPECT_LE(s.rest_max[j] - s.rest_min[j], stopped_travel_allowed_rad(j)) << "joint " << j + 1;
    } else if (stopped_seen && s.state == ArmState::running) {
      moved_after |= s.hand_mm >= kMoved_mm;
    }
  }
  EXPECT_LE(reaction_ms, 1.0);  // S5 (docs/design.md)
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

// one run (38.5 s simulated, about 10 s here), every check on it
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
