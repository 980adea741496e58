// SPEC 8's firmware budgets, measured in the simulator (cycles are deterministic, so they gate):
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
#include "core/supervisor.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"
#include "plant/arm_plant_config.h"
#include "wiring/arm_simulator.h"

namespace {

using namespace wmra;

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kSteppers20kHz = std::string(FIRMWARE_DIR) + "/steppers_20khz_avr.elf";

// SPEC 8: the ATmega2560 has 256 KB, the target keeps the image within 64 KB
constexpr uint32_t kFlashBudget_bytes = 64u * 1024u;
// static data at most 3 KB, so that the stack keeps at least 1 KB within the 4 KB target
constexpr uint32_t kStaticRamBudget_bytes = 3u * 1024u;
// SPEC 8: static data plus the stack's deepest point, at most 4 KB of the 8 KB
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

// SPEC 8: one control iteration (D49 high, the ISRs that land in it included) within 8,000
// cycles, mean and worst, while the stick drives the arm, so that the loop runs at 1 kHz with
// room for the step ISRs and the serial link. The mean is met since session 18 and gated at the
// SPEC's 8,000; the worst is NOT MET YET: its budget is what the loop does today (measured by the
// run below, in brackets, + 10 %), so that growth shows; lower it as it gets faster. Where the cycles go (scripts/profile-firmware, per iteration with the
// stick in XY, XZ, R1): the arm's motion ~6,900 (references, acceleration limit, stepper
// speeds), resolved rate ~2,800, J^-1 ~2,500, the DC servos ~2,500, inputs and checks ~3,300,
// the step ISRs and ramp ~1,500 (~3,600 in R1, where J5 and J6 step fast: the worst case).
// The rate-based step driver (ramps once per iteration in steppers::service, counted in the
// iteration; step ISRs of 82 cycles) took the mean from 27,561 to 25,678 and the worst from
// 57,379 to 33,666.
// The worst case moves by up to 10 % with any change of the loop's timing (how the step ISRs
// fall into the iteration: 42,500 to 49,500 over the builds of one session, 57,379 after a cut
// of ~250 cycles in the DC servos: the worst iterations are in R1, at 9.55 to 9.62 s, where J5
// and J6 step fast), hence its margin. The mean moves by ~2 % alike (the loop overruns, so the
// ticks and with them the arm's path follow the timing).
// The DC joints' gravity model and load-aware speed limits, and servos that count ticks, added
// ~2,300 cycles a mean iteration.
constexpr uint64_t kIterationTarget_cycles = 8000;
// Byte-wise shifts in the joint maps' scales and one product for the ticks that passed (both
// bit-identical) took the mean from 25,436 to 24,802 and the worst from 34,043 to 32,674; the
// drift correction's gain and the pot units as 16-bit products, and the scales' products with
// a negative exponent keeping bytes 2-5 (mul_q16, one shift less; also bit-identical), to
// 24,412 and 32,405; the common scale applied with no product where it is one (nothing limited;
// ResolvedRate.UnlimitedRatesAreJInverseItself), to 23,750 and 32,188; each joint's motion
// limits in one struct and one copy of the stepper tracking per stepper (constant shifts), to
// 23,149 and 30,938; the twist initialised from the call rather than assigned (a 24-byte copy
// loop), to 22,930 and 30,851; two ticks' steps as a sum rather than a library product, to
// 22,351 and 30,486. The DC reference's acceleration taken per tick on overrun calls: 22,605
// and 29,655 (32,936 while the calls past two ticks divided: three 32-bit divisions in the
// longest iterations). The steppers' service walking one table of channel state, and a ramp
// at its wanted speed returning at once (both bit-identical): 22,647 -> 21,974 and 29,499 ->
// 29,373; the plausibility checks as one function for the three DC joints (inlined in the
// servos' loop, they took its registers): 21,517 and 29,873; a ramp's speed step for several
// ticks only past the at-speed return: 21,310 and 29,654; resolved_rate's speed limit near a
// soft stop in a function of its own: 21,106 and 29,361; plausibility's largest change with
// no product for one sample: 20,907 and 30,151 (the worst moved up with the timing). The
// mean's budget is the measurement + 3 %, the worst's keeps about the 10 % it moves by with the
// timing (no higher than at the start of these cuts). Merged with the DC servo's stiction duty
// for a lowering joint (branch s1robust): 21,374 and 29,500. The DC path on 16-bit positions
// (branch dc16: Pid, PlausibilityMonitor, DcServo, effort_for_duty): 20,003 and 28,370 (the
// worst between 27,670 and 29,907 over its steps, with the timing: its budget stays). Branch
// motion16 alone: the braking speed's square root only when the joint is faster than it, the
// commanded position's products inlined and the unit scalings tested once, one test for the
// joints near a soft stop, the wanted step rate in 16 bits, the braking speed's square from a
// 16x16 product (not bit-identical, within 1e-3 rad/s and never above sqrt(1.5 a d)): 20,689
// and 29,201. Both merged, with the DC servos' speed governor: 19,537 and 28,412. Branch glue
// (all bit-identical): the ADC and UDRE ISRs in assembly, J^-1 without its w terms for a twist
// without angular velocity, stick_twist without a zeroed twist, adc::snapshot unrolled:
// 18,234 and 27,932. The drives' loops every second tick (config::kDrivePeriod_ticks: the DC
// servos of J2 and J4 in one slot, J3's with the stepper ramps in the other), one DC servo out
// of line: 14,665 and 22,781 (the loop overran on 22 % of its ticks while driving, 12 % after).
// The pot checks back to every tick (a review: over a servo's period a jump check let twice
// the glitch through): 14,891 and 22,995; with the pose move's brake on a takeover (cold code,
// the loop's timing moved): 14,990 and 22,490. Session 11, merged: the DC path (branch dcpath:
// the servo's and the PID's state within 64 bytes of the object, two samples without a call or
// product, a bridge side off without a product, no feedforward products for a standing
// reference, the governor's bounds every 16 ticks), branch glue11 (the joystick's shape and
// axes kept while their inputs stay, the status report put together only for a frame, a
// cheaper state frame after the iteration, outside this window), the references read in place
// and a lifting start from the holding effort: 13,797 and 22,897. Session 12, merged: the
// trig without joint 6, the DC feedforward's effort_for_duty inlined (branch dc16), the steppers'
// service leaner (branch sv12): 13,353 and 20,306. Session 13: sv12's second commit (constant
// shifts, switches read only for homing): 13,253 and 19,926. Branch kern13: the six references'
// integration as one asm loop, the unlimited tick's copy of the velocities as four-byte moves:
// 12,961 and 20,132. Branch worst13: the periodic jobs at fixed phases of one counter, no two
// heavy ones on a tick (arm_control.cpp's schedule): 13,118 and 18,301 alone. Both: 13,031 and
// 19,319. Session 14: R1/R2 hand J^-1 w in the frame turned by q1, the state frame without its
// own FK (branch frame14): 12,786 and 16,565; the DC joints' friction compensation along the
// motion (ring14, its own state and map): 12,954 and 16,948 (CPU while the stick drives 85.8 %).
// Session 15: the motion pass every second tick, alternating with the drives' loops (branch
// r2frame15): 9,625 and 13,506, the alternate iterations 10,058 / 13,506 and 9,194 / 11,955,
// CPU 66.5 %; the pot units' conversion by the calibration's exponent (branch cut15b): 9,521 and
// 13,435, the alternate iterations 9,894 / 9,149, CPU 65.9 %. Session 16: the stick sampled in
// the motion pass's slot only: 9,338 and 12,425, CPU 64.8 %; the ADC sweep started by Timer1's
// compare B, each channel once: 9,198 and 12,384, 63.9 %; the steppers' tracking and ramps at
// 250 Hz: 8,686 and 12,259, 61.0 %; the moves to a pose cheaper (branch ready16): 8,681 and
// 12,363; duty_moving's shift by 15 as a byte pick: 8,485 and 12,363, the alternate iterations
// 7,785 / 9,184, CPU 59.8 %. Session 17: the drift correction's FK with the holding effort,
// every eighth tick (drives'): 8,361 and 11,194, 59.1 %; the steps counted for their readers
// only, the pots' motion checks with their servo: 8,239 and 10,969, the alternate iterations
// 7,986 / 8,492, CPU 58.4 % (budgets: + 3 % and + 10 %). Session 18: each DC servo's state by
// address from one out-of-line loop (branch dc18): 8,165 and 10,958, 58.0 %; the rotation
// modes' J^-1 of w about the wrist axes (pass18): 8,123 and 10,403 alone, both 8,048 and 10,321,
// 57.3 %; the resolved rate's common factor applied in the acceleration limit's pass, the near
// soft stop test on angles, advance_all's two-tick product (xy18, bit-identical): 7,889 and
// 10,133, 56.4 %; the ISRs inside the iteration cheaper (isr18: the ADC sweep's compare moved on
// by the tick's ISR, the ADC's and the transmit ring's ISRs without SREG, the step ISR with one
// register less, ISR registers saved in GPIOR1/2; 327 cycles of ISRs landed in a mean iteration,
// now 223): 7,788 and 9,859, the alternate iterations 7,743 / 7,833, CPU 55.1 %. Session 19
// (counting the iterations over 8,000 too: 1,480 of 2,999): the holding update from the motion
// pass's trig: 7,720 and 9,962, 1,448 over; the stick reshaped only for a move of more than a
// count (pass19): 7,566 and 9,510 with it, 1,051 over; the DC servo's common run in asm
// (dcasm19): 7,155 and 9,480, the alternate iterations 6,765 / 7,544, CPU 51.4 %, 358 over.
// Session 20 (the bridges' latch, the stick checks at a rail and its stored centre): 7,163 and
// 9,465, 6,785 / 7,540, CPU 51.5 %, 359 of 2,999 over. Session 21 (no drive towards a closed
// switch, with the governor; flash): 7,185 and 9,465, 6,829 / 7,541, CPU 51.6 %, 358 of 3,000.
// Session 22 (the stream taken over by the stick, slowed_by's switch bit; the pass unchanged):
// 7,198 and 9,481, 6,838 / 7,559, CPU 51.8 %, 381 of 3,000. Session 23 (flash: -mrelax's
// shorter calls; the pass unchanged): 7,190 and 9,468, 6,829 / 7,550, CPU 52.0 %, 367 of 3,001.
// SPEC 8: the whole CPU load at most 60 % at 1 kHz, here while the stick drives in XY, XZ and R1
// (R1 steps J5 and J6 fast): the iterations, the step, ADC and serial ISRs, the state frames.
constexpr double kCpuLoadTarget = 0.60;
constexpr double kIterationMeanBudget_cycles = kIterationTarget_cycles;  // [7,190]
constexpr uint64_t kIterationMaxBudget_cycles = 10430;                   // [9,468]
// SPEC 8 wants none over 8,000; until then the count may not grow (it moves with the loop's
// timing: + 20 %)
constexpr uint64_t kIterationsOverTargetBudget = 430;  // [367 of 3,001]

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
  uint64_t over_target = 0;                // iterations longer than SPEC 8's 8,000 cycles
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
    double t = 6.0, from_s[3];
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
  std::printf("iteration with the stick deflected (XY, XZ, R1): mean %.0f, max %llu cycles over %llu iterations (SPEC 8: %llu)\n",
              it.mean(), (unsigned long long)it.max, (unsigned long long)it.count, (unsigned long long)kIterationTarget_cycles);
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
  EXPECT_LE(it.mean(), kIterationMeanBudget_cycles);
  EXPECT_LE(it.max, kIterationMaxBudget_cycles);
  EXPECT_LE(run.over_target, kIterationsOverTargetBudget);
  EXPECT_LE(run.cpu_load(), kCpuLoadTarget);
}

// SPEC 8's 1 kHz: no iteration of a move to a pose outlasts its tick. A move's first ticks are
// the heaviest besides the stick's: the steppers' ramps every tick, the three DC servos leaving
// park (each its breakaway effort and the PID's restart), the move's targets converted. With
// the holding update on the same tick the move to the ready pose's first took 16,238 cycles;
// the holding update and the governor now run a tick early in a move (arm_control.cpp, dc_tick).
// scenarios/moves-to-a-pose.txt: start-up (the move to the ready pose), then eight times the
// hand driven away in XY and a goto to the ready pose, 3.001 s apart: with no tick missed
// (checked) each move starts on the next phase of the schedule's eight.
constexpr uint64_t kTick_cycles = 16000000 / config::kLoopHz;
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
  // the loop kept its 1 kHz (the load is the SPEC's 8,000-cycle iteration)
  EXPECT_NEAR(m.control_rate_hz, 1000.0, 5.0);
}

// SPEC 8: telemetry at 50 state frames a second while running, with the stick moving the arm
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

}  // namespace
