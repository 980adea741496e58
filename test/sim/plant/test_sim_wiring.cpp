// The simulator's wiring, pinned down by small AVR images of our own (test/sim/plant/avr):
// each drives the board's pins the way the firmware will, and the plant must see it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "wiring/arm_simulator.h"
#include "wmra_mega/board.h"

using namespace wmra;
using sim::ArmSimulator;
using sim::SimConfig;

namespace {

std::string image(const char* name) { return std::string(SIM_IMAGES) + "/" + name + ".elf"; }

SimConfig config(const char* name, plant::Joints q = {0, 0.5, 1.0, 0.2, 0.3, 0}) {
  SimConfig c;
  c.elf = image(name);
  c.initial_q = q;
  return c;
}

double microstep_joint_rad(int joint) { return plant::StepperJoint::microstep_motor_rad() / plant::kGearRatio[joint]; }

}  // namespace

// Timer5 toggles STEP on compare in normal mode, the ISRs move OCR5x on, each train stops
// after its count; D49 is toggled read-modify-write on the same port all the while.
TEST(SimWiring, StepTrainsFromTimer5ReachTheDrivers) {
  const plant::Joints q0 = {0, 0.5, 1.0, 0.2, 0.3, 0};
  ArmSimulator sim(config("sim_steps_avr", q0));
  sim.run_until(0.6);
  const sim::Measurements m = sim.measurements();
  const int64_t expected[3] = {100, 1000, 500};
  const double rate_hz[3] = {250, 4000, 2500};
  const int sign[3] = {+1, -1, +1};
  double start_s[3];
  for (int slot = 0; slot < 3; ++slot) {
    const int j = plant::kStepperJoints[slot];
    SCOPED_TRACE("J" + std::to_string(j + 1));
    EXPECT_EQ(m.steps[slot].commanded, expected[slot]);
    EXPECT_EQ(m.steps[slot].lost, 0);
    EXPECT_EQ(m.steps[slot].ignored, 0);
    EXPECT_EQ(m.steps[slot].timing_violations, 0);
    // the last step comes when the count at the rate says, after the image's set-up: the
    // three trains start together, within the image's first 200 us
    start_s[slot] = sim.plant().driver(j).last_step_s() - (expected[slot] - 0.5) / rate_hz[slot];
    EXPECT_GT(start_s[slot], 0.0);
    EXPECT_LT(start_s[slot], 200e-6);
    EXPECT_NEAR(start_s[slot], start_s[0], 1e-6);
    EXPECT_NEAR(sim.q()[j], q0[j] + sign[slot] * expected[slot] * microstep_joint_rad(j), 0.5 * 32 * microstep_joint_rad(j));
    EXPECT_NEAR(sim.plant().stepper(j).q_commanded(), q0[j] + sign[slot] * expected[slot] * microstep_joint_rad(j), 1e-12);
  }
  for (const auto& f : m.sim_faults) ADD_FAILURE() << f;
}

namespace {

// the numbers on the console lines of an image that start with `key`
std::vector<std::vector<long>> console_lines(const ArmSimulator& sim, const std::string& key) {
  std::vector<std::vector<long>> out;
  std::istringstream text(sim.core().console());
  std::string line;
  while (std::getline(text, line)) {
    std::istringstream words(line);
    std::string word;
    if (!(words >> word) || word != key) continue;
    std::vector<long> numbers;
    while (words >> word) {
      char* end = nullptr;
      const long v = std::strtol(word.c_str(), &end, 10);
      if (!word.empty() && *end == 0) numbers.push_back(v);
    }
    out.push_back(numbers);
  }
  return out;
}

double dc_steady_joint_speed(int joint, double volts) {
  const double slope = plant::kDcStallTorqueNm / plant::kDcNoLoadSpeedRadS + plant::kDcViscousNmPerRadS;
  const double torque = plant::kDcStallTorqueNm * std::fabs(volts) / plant::kDcNominalV - plant::kDcCoulombFrictionNm;
  return std::copysign(torque / slope, volts) / plant::kGearRatio[joint];
}

}  // namespace

// The timer plan's PWM reaches the bridges with the datasheet's duty (including the one-count
// spike of OCR = 0 in fast PWM), the joints move at the motor's speed, the ADC reads the pots
// and the stick, a joint driven into its switch trips PCINT0 after the RC delay and stops at
// the hard stop, and the safety button's interrupt switches every output off.
TEST(SimWiring, BridgesPotsJoystickLimitAndSafetyButton) {
  SimConfig c = config("sim_bridges_avr", {0, 0.5, 1.0, -2.70, 0.3, 0});
  c.plant.gravity = false;
  ArmSimulator sim(c);
  sim.set_joystick(0.5, -0.8);
  plant::Joints qd_at_450ms{};
  sim.every(0.45, [&](const ArmSimulator& s) {
    if (s.time_s() > 0.4 && s.time_s() < 0.5) qd_at_450ms = s.plant().qd();
  });
  double j4_contact_s = -1;
  sim.every(20e-6, [&](const ArmSimulator& s) {
    if (j4_contact_s < 0 && s.q()[3] <= arm::q_min_rad(3)) j4_contact_s = s.time_s();
  });
  sim.run_until(0.3);
  EXPECT_DOUBLE_EQ(sim.bridge_duty(1, true), 0.5);
  EXPECT_DOUBLE_EQ(sim.bridge_duty(1, false), 0.0);
  EXPECT_DOUBLE_EQ(sim.bridge_duty(2, true), 0.0);
  EXPECT_DOUBLE_EQ(sim.bridge_duty(2, false), 0.4);
  EXPECT_DOUBLE_EQ(sim.bridge_duty(3, true), 0.01);
  EXPECT_DOUBLE_EQ(sim.bridge_duty(3, false), 0.3);

  sim.run_until(0.7);
  EXPECT_NEAR(qd_at_450ms[1], dc_steady_joint_speed(1, 6.0), 0.04 * dc_steady_joint_speed(1, 6.0));
  EXPECT_NEAR(qd_at_450ms[2], dc_steady_joint_speed(2, -4.8), 0.04 * std::fabs(dc_steady_joint_speed(2, -4.8)));
  for (int j : plant::kDcJoints) EXPECT_EQ(sim.plant().qd()[j], 0.0) << "J" << j + 1 << " stopped";
  EXPECT_NEAR(sim.q()[3], arm::q_min_rad(3) - plant::kHardStopBeyondLimitRad, 1e-9);

  // the ADC: pots at the joints' angles, the stick at its deflection (16 samples averaged)
  const auto adc = console_lines(sim, "adc");
  ASSERT_EQ(adc.size(), 5u);
  const plant::Joints q = sim.q();
  const double expected_mv[5] = {
      plant::kStickCentreMv + plant::kStickCentreOffsetMv[1] - 0.8 * plant::kStickFullScaleMv,  // A0: Y
      plant::kStickCentreMv + plant::kStickCentreOffsetMv[0] + 0.5 * plant::kStickFullScaleMv,  // A1: X
      sim.plant().pot(1).ideal_mv(q[1]), sim.plant().pot(2).ideal_mv(q[2]), sim.plant().pot(3).ideal_mv(q[3])};
  for (int ch = 0; ch < 5; ++ch) {
    EXPECT_NEAR(adc[ch][1], expected_mv[ch] * 1023 / 5000, 1.0) << "A" << ch;
  }

  // PCINT0 when J4's lower switch closed, after the RC (tau ln 2 = 32.6 ms), with PB4 low
  const auto pcint = console_lines(sim, "pcint");
  ASSERT_EQ(pcint.size(), 1u);
  ASSERT_GT(j4_contact_s, 0);
  EXPECT_NEAR(pcint[0][0] * 1e-3, j4_contact_s + plant::kLimitSwitchTauS * std::log(2.0), 1.5e-3);
  EXPECT_EQ((pcint[0][1] >> board::kLimits[3].low.bit) & 1, 0);

  // the safety button: every output off within a few microseconds of the press
  sim.run_until(0.85);
  EXPECT_FALSE(sim.outputs_off());
  sim.set_estop(true);
  sim.run_until(0.9);
  EXPECT_TRUE(sim.outputs_off());
  const sim::Measurements m = sim.measurements();
  ASSERT_EQ(m.estop.size(), 1u);
  EXPECT_GE(m.estop[0].bridges_off_s, m.estop[0].pressed_s);
  EXPECT_LT(m.estop[0].bridges_off_s - m.estop[0].pressed_s, 50e-6);
  EXPECT_EQ(console_lines(sim, "estop").size(), 1u);
  for (const auto& f : m.sim_faults) ADD_FAILURE() << f;
}

// D49 gives the loop's time and rate, sleep gives the CPU load, the ISRs their worst cases,
// the stack pointer the stack's depth.
TEST(SimWiring, LoopTimeCpuLoadIsrsAndStack) {
  ArmSimulator sim(config("sim_loop_avr"));
  sim.run_until(1.0);
  const sim::Measurements m = sim.measurements();
  EXPECT_NEAR((double)m.loop_high.count, 1000, 2);
  // 4,000 cycles of delay loop plus the port write (lds, andi, sts) that ends it
  EXPECT_GE(m.loop_high.min, 4000u);
  EXPECT_LE(m.loop_high.min, 4010u);
  EXPECT_LE(m.loop_high.max, m.loop_high.min + 13);  // at most one Timer2 overflow inside
  EXPECT_NEAR(m.control_rate_hz, 1000.0, 0.1);
  EXPECT_NEAR(m.loop_period.mean(), 16000, 1);
  EXPECT_GT(m.cpu_load, 0.25);
  EXPECT_LT(m.cpu_load, 0.30);
  ASSERT_EQ(m.isr.count("TIMER2_OVF"), 1u);
  EXPECT_EQ(m.isr.at("TIMER2_OVF").max_cycles, 3u + 5u + 5u);  // JMP, RETI, response
  EXPECT_NEAR((double)m.isr.at("TIMER2_OVF").count, 1e6 / 1024, 1);
  ASSERT_EQ(m.isr.count("TIMER1_OVF"), 1u);
  EXPECT_NEAR((double)m.isr.at("TIMER1_OVF").count, 1000, 1);
  EXPECT_GT(m.isr.at("TIMER1_OVF").max_cycles, 20u);
  EXPECT_LT(m.isr.at("TIMER1_OVF").max_cycles, 60u);
  EXPECT_DOUBLE_EQ(sim.gripper_pulse_us(), 500.0);
  EXPECT_GE(m.stack_bytes, 200u);
  EXPECT_LT(m.stack_bytes, 240u);
  EXPECT_GT(m.ram_static_bytes, 0u);
  for (const auto& f : m.sim_faults) ADD_FAILURE() << f;
}

// The profile of the iterations over a budget (armsim --profile-over): each D49 pulse's
// instructions, kept by the pulse's parity when it is longer than the budget. Here a pulse is
// 4,000-odd cycles, 13 more when Timer2's overflow lands in it (about a quarter of them).
TEST(SimWiring, ProfileOfTheIterationsOverABudget) {
  constexpr size_t kTimer2OverflowVectorWord = 15 * 2;  // TIMER2_OVF_vect_num: a JMP, 3 cycles
  struct Run {
    sim::Measurements m;
    uint64_t kept[2], kept_cycles = 0, vector_cycles = 0;
  };
  auto run = [](uint64_t over_cycles) {
    SimConfig c = config("sim_loop_avr");
    c.profile_over_cycles = over_cycles;
    ArmSimulator sim(c);
    sim.run_until(1.0);
    Run r{sim.measurements(), {sim.core().stretches(0), sim.core().stretches(1)}};
    for (int bin = 0; bin < 2; ++bin) {
      const std::vector<uint64_t>& p = sim.core().stretch_profile(bin);
      for (uint64_t cycles : p) r.kept_cycles += cycles;
      if (!p.empty()) r.vector_cycles += p[kTimer2OverflowVectorWord];
    }
    return r;
  };
  // every pulse: both parities alike, and their instructions' cycles are the pulses' own (the
  // edges count from within the port write's instruction: a few cycles each)
  const Run all = run(1);
  EXPECT_EQ(all.kept[0] + all.kept[1], all.m.loop_high.count);
  EXPECT_LE(all.kept[0] > all.kept[1] ? all.kept[0] - all.kept[1] : all.kept[1] - all.kept[0], 1u);
  EXPECT_NEAR((double)all.kept_cycles, (double)all.m.loop_high.sum, 4.0 * all.m.loop_high.count);
  EXPECT_GT(all.vector_cycles, 0u);
  EXPECT_LT(all.vector_cycles, 3 * all.m.loop_high.count / 2);
  // over the plain pulse's length: exactly those with the overflow in them
  const Run with_isr = run(all.m.loop_high.min + 6);
  const uint64_t kept = with_isr.kept[0] + with_isr.kept[1];
  EXPECT_GT(kept, 150u);  // 977 overflows a second, a quarter of the time in a pulse
  EXPECT_LT(kept, 350u);
  EXPECT_EQ(with_isr.vector_cycles, 3 * kept);
  const Run none = run(all.m.loop_high.max);
  EXPECT_EQ(none.kept[0] + none.kept[1], 0u);
  EXPECT_EQ(none.kept_cycles, 0u);
}

// UART0 both ways at 115200; a watchdog bite is counted with its cause, and after it the
// inputs read as before (simavr's reset clears the PIN registers: the simulator restores them).
TEST(SimWiring, SerialEchoWatchdogResetAndInputsAfterIt) {
  // J1 at its upper switch (PB6 low), J2 at its lower (PD0 low), J6 at its zero cam (PB0 low)
  ArmSimulator sim(config("sim_serial_avr", {arm::q_max_rad(0), arm::q_min_rad(1), 1.0, 0.2, 0.3, 0}));
  sim.run_until(0.01);
  sim.send_serial({'h', 'e', 'l', 'l', 'o'});
  sim.run_until(0.05);
  std::string out(sim.uart_output().begin(), sim.uart_output().end());
  EXPECT_EQ(out, "boot 01 3e 0e 20\nhello");
  sim.send_serial({'W'});
  sim.run_until(0.2);
  out.assign(sim.uart_output().begin(), sim.uart_output().end());
  EXPECT_EQ(out, "boot 01 3e 0e 20\nhelloWboot 08 3e 0e 20\n");
  const sim::Measurements m = sim.measurements();
  ASSERT_EQ(m.resets.size(), 1u);
  EXPECT_EQ(m.resets[0].cause, "watchdog");
  EXPECT_NEAR(m.resets[0].cycle / (double)board::kCpuHz, 0.05 + 0.016, 0.01);  // the 'W' arrives ~50 ms, 15 ms (+-10 %) later
  EXPECT_EQ(m.uart_rx_bytes, 6u);
  EXPECT_EQ(m.uart_rx_dropped, 0u);
  // the plant kept its time through the reset
  EXPECT_NEAR(sim.plant().time_s(), 0.2, 21e-6);

  // halted with the watchdog on (sleep, interrupts off): the watchdog still bites
  sim.send_serial({'H'});
  sim.run_until(0.3);
  out.assign(sim.uart_output().begin(), sim.uart_output().end());
  EXPECT_EQ(out.substr(out.size() - 18), "Hboot 08 3e 0e 20\n");
  const sim::Measurements after = sim.measurements();
  ASSERT_EQ(after.resets.size(), 2u);
  EXPECT_EQ(after.resets[1].cause, "watchdog");
  ASSERT_EQ(after.sim_faults.size(), 1u);
  EXPECT_NE(after.sim_faults[0].find("halted"), std::string::npos);
}

// The buttons bounce; the firmware's edge interrupts see every bounce.
TEST(SimWiring, ButtonsBounceIntoTheirInterrupts) {
  ArmSimulator sim(config("sim_buttons_avr"));
  sim.run_until(0.01);
  auto last = [&] { return console_lines(sim, "button").back(); };
  EXPECT_EQ(last()[0], 0);
  EXPECT_EQ(last()[1], 0);
  sim.set_button(true);
  sim.run_until(0.02);
  const long falls = last()[0];
  EXPECT_GE(falls, 2);  // 3, 5 or 7 edges: 2 to 4 falling
  EXPECT_LE(falls, 4);
  sim.set_button(false);
  sim.set_estop(true);
  sim.run_until(0.03);
  const long estop_changes = last()[1];
  EXPECT_GE(estop_changes, 3);  // an odd number of changes that ends pressed
  EXPECT_EQ(estop_changes % 2, 1);
  const std::string& console = sim.core().console();
  EXPECT_EQ(console.substr(console.rfind("levels ") + 7, 2), "11");  // released button, pressed safety button
  const long before = last()[0];
  sim.set_joystick_unplugged(true);  // unplugged: the button line floats high (pull-up)
  sim.set_button(true);
  sim.run_until(0.04);
  EXPECT_EQ(last()[0], before);
}
