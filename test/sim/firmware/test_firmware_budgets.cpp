// The firmware budgets (docs/performance.md, gates), measured in the simulator (cycles are deterministic, so they gate):
// flash, static RAM and its high-water mark, every ISR's worst case, and three steppers at
// 20 kHz at once under a control-loop-like load. Each budget is a named constant with its why.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "armsim/firmware_telemetry.h"
#include "config/control_config.h"
#include "config/joints_config.h"
#include "config/modes_config.h"
#include "config/motion_config.h"
#include "core/supervisor.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"
#include "plant/arm_plant_config.h"
#include "wiring/arm_simulator.h"
#include "wmra_mega/board.h"

namespace {

using namespace wmra;

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kSteppers20kHz = std::string(FIRMWARE_DIR) + "/steppers_20khz_avr.elf";

// The ATmega2560 has 256 KB, the target keeps the image within its lower 128 KB (no far
// calls, no EIND trampolines)
constexpr uint32_t kFlashBudget_bytes = 128u * 1024u;
// static data at most 3 KB, so that the stack keeps at least 1 KB within the 4 KB target
constexpr uint32_t kStaticRamBudget_bytes = 3u * 1024u;
// Static data plus the stack's deepest point, at most 4 KB of the 8 KB
constexpr uint32_t kRamHighWaterBudget_bytes = 4u * 1024u;

// Every ISR's worst case, cycles (vector to RETI plus the response). Measured with the run
// below (the figure in brackets) and rounded up by ~10-20 %, so that growth shows; an ISR
// without a budget fails the test.
const std::map<std::string, uint64_t> kIsrBudget_cycles = {
    {"ADC", 52},               // [44] one conversion stored, the next channel started (assembly)
    {"INT4", 260},             // [226] safety button: every output off (bridges.cpp at -O2)
    {"PCINT0", 220},           // [181] limit switches: read, latch, stop hook
    {"TIMER1_COMPA", 110},     // [95] the 1 kHz tick, the ADC sweep's compare moved on, the stall mark
    {"TIMER1_COMPB", 28},      // [24] the ADC sweep's start (assembly)
    {"TIMER1_COMPC", 90},      // [81] the servo pulse edge
    {"TIMER5_COMPA", 85},      // [73] a step edge: count, next edge, stop on the count
    {"TIMER5_COMPB", 85},      // (assembly, lib/drivers/steppers.cpp; the ramps run in the
    {"TIMER5_COMPC", 85},      //  main loop): 60,000 a second at 3 x 20 kHz
    {"USART0_RX", 100},        // [86] one byte into the receive ring (the start's `home`)
    {"USART0_UDRE", 42},       // [36] one byte out of the transmit ring (assembly)
};

sim::SimConfig config(const std::string& elf) {
  sim::SimConfig c;
  c.elf = elf;
  c.initial_q = {1.45, 0.3, -1.0, 0.6, -1.45, 0.05};  // near the homing switches (scenarios/profile.txt)
  return c;
}

// Start-up (`home`, homing, the move to the ready pose), the stick in XY and then XZ while
// running, and the safety button at the end: every ISR the firmware has in use.
struct ProfileRun {
  sim::Measurements m;
  ProfileRun() {
    sim::ArmSimulator sim(config(kFirmware));
    test::ask_home_at(sim);
    sim.run_until(6.0);
    sim.set_joystick(1, 0);
    sim.run_until(7.0);
    sim.set_button(true);  // short press: XY -> XZ
    sim.run_until(7.1);
    sim.set_button(false);
    sim.set_joystick(0, 1);
    sim.run_until(8.0);
    sim.set_estop(true);
    sim.run_until(8.2);
    m = sim.measurements();
  }
};

const sim::Measurements& profile() {
  static const ProfileRun run;
  return run.m;
}

TEST(FirmwareBudgets, FlashAndRam) {
  const sim::Measurements& m = profile();
  ASSERT_TRUE(m.sim_faults.empty());
  std::printf("flash %u bytes, static RAM %u bytes, high-water %u bytes\n", m.flash_bytes, m.ram_static_bytes,
              m.ram_static_bytes + m.stack_bytes);
  EXPECT_LE(m.flash_bytes, kFlashBudget_bytes);
  EXPECT_LE(m.ram_static_bytes, kStaticRamBudget_bytes);
  EXPECT_LE(m.ram_static_bytes + m.stack_bytes, kRamHighWaterBudget_bytes);
}

TEST(FirmwareBudgets, EveryIsrWithinItsWorstCase) {
  const sim::Measurements& m = profile();
  EXPECT_TRUE(m.isr.count("INT4")) << "the run must press the safety button";
  for (const auto& kv : m.isr) {
    std::printf("%-14s worst %5llu cycles, %llu calls\n", kv.first.c_str(), (unsigned long long)kv.second.max_cycles,
                (unsigned long long)kv.second.count);
    const auto budget = kIsrBudget_cycles.find(kv.first);
    if (budget == kIsrBudget_cycles.end()) {
      ADD_FAILURE() << kv.first << " has no budget";
      continue;
    }
    EXPECT_LE(kv.second.max_cycles, budget->second) << kv.first;
  }
}

// All the work of one tick, the interrupts that land in it included, within
// 12,800 cycles (80 % of the 1 ms tick), and the CPU load at most 60 %, here while the stick
// drives in XY, XZ and R1 (R1 steps J5 and J6 fast): the iterations, the step, ADC and serial
// ISRs, the state frames. The mean and the count of iterations over the old 8,000 are printed,
// not gated: the motion chain runs at 500 Hz (every second tick), so one iteration carries the
// motion pass and the next the drives' loops. Where the cycles go: scripts/profile-firmware.
constexpr uint64_t kTickTarget_cycles = 12800;
constexpr uint64_t kIterationTarget_cycles = 8000;  // printed: the iterations over it
constexpr double kCpuLoadTarget = 0.60;

// The stick deflected in XY, XZ and R1 after start-up; every iteration that ends while the
// stick is deflected counts. The simulator keeps D49's running sums, so each iteration is read
// off as their change over a window shorter than the shortest iteration's spacing; a window
// with two iterations in it (the loop catching up after an overrun) counts as one as long as
// both, which only overstates the worst case.
struct IterationRun {
  sim::CycleStats deflected;  // per iteration while deflected
  // and by the iteration's parity: the motion pass and the drives' loops alternate (each
  // iteration advances the schedule by one), so each parity is one of them
  sim::CycleStats by_parity[2];
  sim::CycleStats own, own_by_parity[2];  // the same less the interrupts that landed in them
  uint64_t over_target = 0;                // iterations longer than the 8,000-cycle target
  uint64_t window_cycles = 0, asleep_cycles = 0;  // while deflected: the CPU's load
  std::vector<uint64_t> in_mode[3];        // each iteration's cycles, in order, while deflected in each mode
  int frames[3] = {0, 0, 0};          // telemetry's state frames while deflected in each mode
  int frames_in_mode[3] = {0, 0, 0};  // of them, running in the mode meant
  static uint64_t asleep(const sim::Measurements& m) { return (uint64_t)std::llround((1 - m.cpu_load) * m.cycles); }
  double cpu_load() const { return 1 - (double)asleep_cycles / window_cycles; }
  IterationRun() {
    sim::ArmSimulator sim(config(kFirmware));
    bool measuring = false;
    int mode_now = 0;
    sim::CycleStats last, last_own;
    sim.every(100e-6, [&](const sim::ArmSimulator& s) {
      const sim::CycleStats now = s.measurements().loop_high;
      const sim::CycleStats now_own = s.measurements().loop_own;
      if (measuring && now.count > last.count) {
        deflected.add(now.sum - last.sum);
        own.add(now_own.sum - last_own.sum);
        over_target += now.sum - last.sum > kIterationTarget_cycles;
        in_mode[mode_now].push_back(now.sum - last.sum);
      }
      if (measuring && now.count == last.count + 1) {
        by_parity[now.count % 2].add(now.sum - last.sum);
        own_by_parity[now.count % 2].add(now_own.sum - last_own.sum);
      }
      if (measuring && now.count > last.count + 1) deflected.count += now.count - last.count - 1;
      last = now;
      last_own = now_own;
    });
    const struct {
      config::Mode mode;
      double x, y;
    } kModes[3] = {{config::Mode::xy, 1, 0}, {config::Mode::xz, 0, 1}, {config::Mode::r1, 0.7, 0.7}};
    double t = 9.0, from_s[3];  // (running from about 7.5 s)
    test::ask_home_at(sim);
    sim.run_until(t);
    for (int k = 0; k < 3; ++k) {
      mode_now = k;
      sim.set_joystick(kModes[k].x, kModes[k].y);
      measuring = true;
      from_s[k] = t;
      const sim::Measurements before = sim.measurements();
      sim.run_until(t += 1.0);
      measuring = false;
      const sim::Measurements after = sim.measurements();
      window_cycles += after.cycles - before.cycles;
      asleep_cycles += asleep(after) - asleep(before);
      sim.set_joystick(0, 0);
      sim.run_until(t += 0.4);
      sim.set_button(true);  // short press: the next mode
      sim.run_until(t += 0.1);
      sim.set_button(false);
      sim.run_until(t += 0.2);
    }
    EXPECT_TRUE(sim.measurements().sim_faults.empty());
    armsim::FirmwareTelemetry telemetry;
    for (uint8_t b : sim.uart_output()) telemetry.feed(b);
    for (const protocol::StateMsg& f : telemetry.states()) {
      for (int k = 0; k < 3; ++k) {
        if (f.t_ms < from_s[k] * 1000 || f.t_ms > (from_s[k] + 1.0) * 1000) continue;
        ++frames[k];
        frames_in_mode[k] += f.state == (uint8_t)core::ArmState::running && f.mode == (uint8_t)kModes[k].mode;
      }
    }
  }
  // The heaviest `n` consecutive iterations' mean, over the three modes: however the same work
  // were shared out between the ticks, one of those n would take at least that.
  double heaviest_mean(size_t n) const {
    double worst = 0;
    for (const std::vector<uint64_t>& v : in_mode) {
      uint64_t sum = 0;
      for (size_t i = 0; i < v.size(); ++i) {
        sum += v[i];
        if (i >= n) sum -= v[i - n];
        if (i + 1 >= n) worst = std::max(worst, (double)sum / n);
      }
    }
    return worst;
  }
};

TEST(FirmwareBudgets, ControlIterationWhileTheStickDrives) {
  static const IterationRun run;
  const sim::CycleStats& it = run.deflected;
  std::printf("iteration with the stick deflected (XY, XZ, R1): mean %.0f, max %llu cycles over %llu iterations (gate %llu)\n",
              it.mean(), (unsigned long long)it.max, (unsigned long long)it.count, (unsigned long long)kTickTarget_cycles);
  std::printf("alternate iterations: mean %.0f, max %llu and mean %.0f, max %llu cycles; CPU load %.1f %%\n",
              run.by_parity[0].mean(), (unsigned long long)run.by_parity[0].max, run.by_parity[1].mean(),
              (unsigned long long)run.by_parity[1].max, 100 * run.cpu_load());
  std::printf("%llu of them over %llu cycles\n", (unsigned long long)run.over_target, (unsigned long long)kIterationTarget_cycles);
  std::printf("less the interrupts in them: mean %.0f, max %llu; alternate mean %.0f, max %llu and mean %.0f, max %llu cycles\n",
              run.own.mean(), (unsigned long long)run.own.max, run.own_by_parity[0].mean(),
              (unsigned long long)run.own_by_parity[0].max, run.own_by_parity[1].mean(),
              (unsigned long long)run.own_by_parity[1].max);
  std::printf("the heaviest 2, 10, 100 consecutive iterations: mean %.0f, %.0f, %.0f cycles (a lower bound on the longest "
              "iteration of any schedule of the same work)\n",
              run.heaviest_mean(2), run.heaviest_mean(10), run.heaviest_mean(100));
  ASSERT_GT(it.count, 1500u) << "three seconds of the stick deflected, at least at half the 1 kHz";
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(run.frames[k], 10);
    EXPECT_EQ(run.frames_in_mode[k], run.frames[k]) << "running in XY, XZ, R1 in turn: mode " << k;
  }
  EXPECT_LE(it.max, kTickTarget_cycles);
  EXPECT_LE(run.cpu_load(), kCpuLoadTarget);
}

// The loop's 1 kHz: no iteration of a move to a pose outlasts its tick. A move's first ticks are
// the heaviest besides the stick's: the steppers' ramps every tick, the three DC servos leaving
// park (each its breakaway effort and the PID's restart), the move's targets converted. With
// the holding update on the same tick the move to the ready pose's first took 16,238 cycles;
// the holding update and the governor now run a tick early in a move (arm_control.cpp, dc_tick).
// scenarios/moves-to-a-pose.txt: start-up (the move to the ready pose), then eight times the
// hand driven away in XY and a goto to the ready pose, 3.001 s apart: with no tick missed
// (checked) each move starts on the next phase of the schedule's eight.
constexpr uint64_t kTick_cycles = board::kCpuHz / config::kLoopHz;
// How far a DC joint may stand from a pose it arrived at: the arrival tolerance on its pot's
// reading (kArrivedTolerance_mdeg) and two ADC counts of the pot's span for the reading's
// quantisation and noise (the plant's pots: 0.3 LSB rms).
double dc_arrival_bound_deg(int joint) {
  const double counts_over_range = (plant::kPotHighMv - plant::kPotLowMv) / plant::kAdcRefMv * 1024;
  return config::kArrivedTolerance_mdeg / 1000.0 + 2 * (arm::q_max_deg[joint] - arm::q_min_deg[joint]) / counts_over_range;
}
TEST(FirmwareBudgets, EveryIterationOfTheMovesToAPoseWithinItsTick) {
  const armsim::Scenario scenario = armsim::load_scenario(std::string(SCENARIOS_DIR) + "/moves-to-a-pose.txt");
  // the gotos: the serial commands after the stick first moves (the one before asks for the homing)
  const auto stick = std::find_if(scenario.events.begin(), scenario.events.end(),
                                  [](const armsim::Event& e) { return e.kind == armsim::Event::Kind::joystick; });
  ASSERT_NE(stick, scenario.events.end());
  const double stick_s = stick->t_s;
  std::vector<double> gotos_s;
  for (const armsim::Event& e : scenario.events)
    if (e.kind == armsim::Event::Kind::serial && e.t_s > stick_s) gotos_s.push_back(e.t_s);
  ASSERT_EQ(gotos_s.size(), 8u);
  armsim::RunOptions options;
  options.elf = kFirmware;
  uint64_t first_count = 0, last_count = 0;  // iterations at the rows of the first and the last goto
  double first_s = -1, last_s = -1;
  // the hand at the ready pose (before the stick first moves) and at each goto, the joints 1.9 s
  // after it
  constexpr double kBack_s = 1.9;
  std::array<double, 3> ready{};
  std::vector<std::array<double, 3>> away(gotos_s.size());
  std::vector<std::array<double, 6>> back_q(gotos_s.size());
  const armsim::RunResult r = armsim::run_scenario(scenario, options, [&](const sim::ArmSimulator& sim, const armsim::TrajectoryRow& row) {
    if (row.t_s < stick_s) ready = row.p;
    for (size_t k = 0; k < gotos_s.size(); ++k) {
      if (row.t_s <= gotos_s[k]) away[k] = row.p;
      if (row.t_s <= gotos_s[k] + kBack_s) back_q[k] = row.q;
    }
    if (first_s < 0 && row.t_s >= gotos_s.front()) first_s = row.t_s, first_count = sim.measurements().loop_high.count;
    if (last_s < 0 && row.t_s >= gotos_s.back()) last_s = row.t_s, last_count = sim.measurements().loop_high.count;
  });
  ASSERT_TRUE(r.completed);
  EXPECT_TRUE(r.faults.empty());
  EXPECT_EQ(r.telemetry.replies, gotos_s.size() + 1) << "every goto answered, and the home before them";
  const sim::CycleStats& loop = r.measurements.loop_high;
  std::printf("moves to a pose: control loop mean %.0f, max %llu cycles; %llu iterations in %.3f s between the first goto and the last\n",
              loop.mean(), (unsigned long long)loop.max, (unsigned long long)(last_count - first_count), last_s - first_s);
  EXPECT_NEAR((double)(last_count - first_count), 1000 * (last_s - first_s), 1.0) << "a tick missed: the moves' phases unknown";
  EXPECT_LE(loop.max, kTick_cycles);
  // every goto moved the arm: from where the stick had driven the hand back to the ready pose,
  // each DC joint within its arrival bound (the steppers arrive exactly, in steps)
  for (size_t k = 0; k < gotos_s.size(); ++k) {
    EXPECT_GT(test::distance_mm(away[k], ready), 30.0) << "goto " << k;
    for (int j = 1; j <= 3; ++j) {  // J2, J3, J4
      const double off_deg = back_q[k][j] * 180 / 3.14159265358979323846 - config::kReadyPose_deg[j];
      EXPECT_LT(std::fabs(off_deg), dc_arrival_bound_deg(j)) << "goto " << k << ", J" << j + 1;
    }
  }
}

// Three steppers at 20 kHz at once with the loop running: every step the moves asked for
// reaches the drivers (none lost, none extra), within the DRV8825's timing, at 20 kHz, and the
// loop keeps its 1 kHz. Measured: loop 996.7 Hz (D49 high mean 13,687, max 18,524 cycles: the
// 8,000 of load, the ramps, and the step ISRs that land in it), CPU 87.7 %, 20,000 steps each,
// 0 violations. (The plant's J1 and J5 motors slip at 20 kHz: not this test's subject.) With
// the ramp in the step ISR it was 19.7 Hz, CPU 98.8 %, 18,982 / 1,156 / 20,001 steps.
TEST(FirmwareBudgets, ThreeSteppersAt20kHzWithTheLoopRunning) {
  constexpr int64_t kSteps = 20000;  // steppers_20khz_avr.cpp
  constexpr double kTopSpeed_steps_s = 20000;
  sim::ArmSimulator sim(config(kSteppers20kHz));
  int64_t last[3] = {0, 0, 0};
  double fastest_steps_s[3] = {0, 0, 0};
  constexpr double kWindow_s = 0.01;
  sim.every(kWindow_s, [&](const sim::ArmSimulator& s) {
    const sim::Measurements m = s.measurements();
    for (int k = 0; k < 3; ++k) {
      const double rate = (m.steps[k].commanded - last[k]) / kWindow_s;
      if (rate > fastest_steps_s[k]) fastest_steps_s[k] = rate;
      last[k] = m.steps[k].commanded;
    }
  });
  sim.run_until(1.5);
  const sim::Measurements m = sim.measurements();
  ASSERT_TRUE(m.sim_faults.empty());
  std::printf("loop: D49 high mean %.0f max %llu cycles, %.1f Hz, CPU %.1f %%\n", m.loop_high.mean(),
              (unsigned long long)m.loop_high.max, m.control_rate_hz, 100 * m.cpu_load);
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("stepper " + std::to_string(k));
    std::printf("stepper %d: %lld steps, fastest %.0f steps/s, %lld timing violations, rotor slips %lld\n", k,
                (long long)m.steps[k].commanded, fastest_steps_s[k], (long long)m.steps[k].timing_violations,
                (long long)m.steps[k].lost);
    EXPECT_EQ(m.steps[k].commanded, kSteps);  // no step lost or extra between the ramp and the driver
    EXPECT_EQ(m.steps[k].ignored, 0);
    EXPECT_EQ(m.steps[k].timing_violations, 0);
    EXPECT_GE(fastest_steps_s[k], 0.98 * kTopSpeed_steps_s);
  }
  // the loop kept its 1 kHz (the load is the 8,000-cycle target iteration)
  EXPECT_NEAR(m.control_rate_hz, 1000.0, 5.0);
}

// Telemetry at 50 state frames a second while running, with the stick moving the arm
// (the iteration at its longest, more than one tick at times). The frames' own clock (t_ms)
// gives the period: at most one period late, and 50 a second over the window.
TEST(FirmwareBudgets, StateFramesAt50HzWhileRunning) {
  test::Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  rig.sim.set_joystick(1, 0);
  rig.run_to(t_running + 1.0);
  const size_t first = rig.telemetry.states().size();
  rig.run_to(t_running + 3.0);
  const std::vector<protocol::StateMsg>& states = rig.telemetry.states();
  ASSERT_GT(states.size(), first + 1);
  uint32_t longest_gap_ms = 0;
  for (size_t k = first + 1; k < states.size(); ++k) {
    longest_gap_ms = std::max(longest_gap_ms, states[k].t_ms - states[k - 1].t_ms);
  }
  const double span_s = (states.back().t_ms - states[first].t_ms) / 1000.0;
  const double rate_hz = (states.size() - 1 - first) / span_s;
  std::printf("state frames: %.1f a second over %.2f s, longest gap %u ms\n", rate_hz, span_s, longest_gap_ms);
  EXPECT_GE(rate_hz, 50.0 * 0.99);  // 50 Hz, one frame short over the 2 s at most
  EXPECT_LE(longest_gap_ms, 2 * protocol::kStatePeriod_ms);
  EXPECT_EQ(rig.state(), core::ArmState::running);
}


// The worst load: all the work of each tick (the iteration, the serial link
// with its state frames, the interrupts that land in it: from the wake-up to the next sleep,
// tick_awake) and the CPU load, while the stick ramps in every mode (full one way, released,
// full the other way), commands come (speed_scale, each answered), and then a move to a stored
// pose with the commands still coming. The steppers run as fast as these motions drive them;
// their peak step rates are printed beside their configured top speeds (and what the step
// interrupts would add at those).
// The commands come at the line's full rate (the worst load's flood, docs/performance.md). Gated: no tick lost, no byte lost,
// the state frames at 50 a second (the replies leave them room). The worst tick's 12,800 cycles
// and the CPU load's 60 % are measured and printed, not gated: the firmware does not meet them
// under this load (docs/performance.md); a tick's work then runs into the next one's time.
struct WorstLoadRun {
  uint64_t worst_tick = 0;
  double worst_tick_at_s = 0, cpu_load = 0;
  uint64_t ticks = 0, window_ms = 0, window_cycles = 0, asleep_cycles = 0;
  double peak_steps_s[3] = {0, 0, 0};
  uint64_t step_isr_max = 0;
  std::array<sim::CycleStats, 8> by_plan_tick;
  unsigned rx_overruns = 0;
  size_t replies = 0, state_frames = 0;
  bool ran = false;
};
WorstLoadRun worst_load_run(double command_period_s) {
  WorstLoadRun r;
  test::Rig rig(kFirmware);
  if (rig.start(12.0) < 0) return r;
  // the flood: one command every 0.7 ms (8 bytes take 0.69 ms on the line), for the whole window
  uint8_t seq = 0;
  double next_command_s = rig.sim.time_s();
  int64_t last_steps[3] = {0, 0, 0};
  const sim::Measurements m0 = rig.sim.measurements();
  for (int k = 0; k < 3; ++k) last_steps[k] = m0.steps[k].commanded;
  auto run_flooded = [&](double until_s) {
    for (double t = rig.sim.time_s(); t < until_s; t += 0.01) {
      while (next_command_s < t + 0.01) {
        rig.sim.send_serial(test::command(protocol::MsgType::cmd_speed_scale, seq++, {100}));
        next_command_s += command_period_s;
      }
      rig.run_to(t + 0.01);
      const sim::Measurements m = rig.sim.measurements();
      for (int k = 0; k < 3; ++k) {
        r.peak_steps_s[k] = std::max(r.peak_steps_s[k], std::fabs((double)(m.steps[k].commanded - last_steps[k])) / 0.01);
        last_steps[k] = m.steps[k].commanded;
      }
    }
  };
  rig.sim.send_serial(test::command(protocol::MsgType::cmd_store_pose, seq++, {1}));
  rig.run_to(rig.sim.time_s() + 0.1);
  const sim::Measurements before = rig.sim.measurements();
  rig.sim.reset_tick_awake();
  const size_t replies_before = rig.telemetry.replies().size(), states_before = rig.telemetry.states().size();
  const double kStick[4][2] = {{1, 0}, {0, 1}, {0.7, 0.7}, {0, 1}};  // XY, XZ, R1, R2
  for (int mode = 0; mode < 4; ++mode) {
    for (double way : {1.0, -1.0}) {
      rig.sim.set_joystick(way * kStick[mode][0], way * kStick[mode][1]);
      run_flooded(rig.sim.time_s() + 1.0);
      rig.sim.set_joystick(0, 0);
      run_flooded(rig.sim.time_s() + 0.5);
    }
    rig.sim.set_button(true);  // short press: the next mode
    run_flooded(rig.sim.time_s() + 0.1);
    rig.sim.set_button(false);
    run_flooded(rig.sim.time_s() + 0.3);
  }
  rig.sim.send_serial(test::command(protocol::MsgType::cmd_goto_pose, seq++, {1}));
  next_command_s += command_period_s;
  run_flooded(rig.sim.time_s() + 4.0);
  const sim::Measurements after = rig.sim.measurements();
  r.worst_tick = after.tick_awake.max;
  r.worst_tick_at_s = after.tick_awake_max_at_s;
  r.ticks = after.loop_high.count - before.loop_high.count;
  r.window_ms = (after.cycles - before.cycles) / (board::kCpuHz / 1000);
  r.window_cycles = after.cycles - before.cycles;
  r.asleep_cycles = IterationRun::asleep(after) - IterationRun::asleep(before);
  r.cpu_load = 1 - (double)r.asleep_cycles / r.window_cycles;
  for (const char* v : {"TIMER5_COMPA", "TIMER5_COMPB", "TIMER5_COMPC"}) {
    const auto it = after.isr.find(v);
    if (it != after.isr.end()) r.step_isr_max = std::max<uint64_t>(r.step_isr_max, it->second.max_cycles);
  }
  r.by_plan_tick = after.loop_high_by_plan_tick;
  r.replies = rig.telemetry.replies().size() - replies_before;
  r.state_frames = rig.telemetry.states().size() - states_before;
  if (!rig.telemetry.states().empty()) r.rx_overruns = rig.telemetry.states().back().rx_overruns;
  r.ran = after.sim_faults.empty();
  return r;
}

void print_worst_load(const char* name, const WorstLoadRun& r, double command_period_s) {
  // the steppers' configured top speeds (their joints' speed limits), steps a second
  double top_steps_s[3], top_isr_per_tick = 0;
  for (int k = 0; k < 3; ++k) {
    top_steps_s[k] = config::kStepsPerJointTurn[k] * config::kJointSpeedLimit_crad_s[config::kStepperJoint[k]] / 100.0 / (2 * M_PI);
    top_isr_per_tick += top_steps_s[k] / config::kLoopHz * r.step_isr_max;
  }
  std::printf("%s: the longest tick %llu cycles (at %.3f s; gate %llu), CPU load %.1f %% (gate %.0f %%) over %llu ticks\n", name,
              (unsigned long long)r.worst_tick, r.worst_tick_at_s, (unsigned long long)kTickTarget_cycles, 100 * r.cpu_load,
              100 * kCpuLoadTarget, (unsigned long long)r.ticks);
  std::printf("iterations %llu in %llu ms\n", (unsigned long long)r.ticks, (unsigned long long)r.window_ms);
  std::printf("a command every %.1f ms: %zu replies, %zu state frames (%.1f a second), %u bytes lost (rx_overruns)\n",
              command_period_s * 1e3, r.replies, r.state_frames, r.state_frames * 1000.0 / r.window_ms, r.rx_overruns);
  std::printf("steppers' peak step rates J1 %.0f, J5 %.0f, J6 %.0f steps/s; at their top speeds %.0f, %.0f, %.0f "
              "(the step interrupts, %llu cycles each, would take %.0f cycles a tick)\n",
              r.peak_steps_s[0], r.peak_steps_s[1], r.peak_steps_s[2], top_steps_s[0], top_steps_s[1], top_steps_s[2],
              (unsigned long long)r.step_isr_max, top_isr_per_tick);
  for (int k = 0; k < 8; ++k)
    std::printf("the plan's tick %d (by iteration, a fixed offset from tick_plan.h's numbers): iteration mean %.0f, max %llu cycles\n", k,
                r.by_plan_tick[k].mean(), (unsigned long long)r.by_plan_tick[k].max);
}

TEST(FirmwareBudgets, WorstLoadLosesNoTick) {
  constexpr double kLineRate_s = 0.7e-3;  // 8 bytes take 0.69 ms on the line
  const WorstLoadRun r = worst_load_run(kLineRate_s);
  ASSERT_TRUE(r.ran);
  ASSERT_GT(r.ticks, 15000u);
  print_worst_load("worst load", r, kLineRate_s);
  ::testing::Test::RecordProperty("worst_tick_cycles", std::to_string(r.worst_tick));
  ::testing::Test::RecordProperty("cpu_load", std::to_string(r.cpu_load));
  EXPECT_NEAR((double)r.ticks, (double)r.window_ms, 1.0) << "a tick lost under the worst load";
  EXPECT_EQ(r.rx_overruns, 0u) << "the link fell behind the line";
  EXPECT_GE(r.state_frames * 1000.0 / r.window_ms, 50.0 * 0.99) << "the replies starved the telemetry";
}

}  // namespace
