// The simulator's wiring, pinned down by small AVR images of our own (test/sim_plant/avr):
// each drives the board's pins the way the firmware will, and the plant must see it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "wiring/arm_simulator.h"

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
  for (int slot = 0; slot < 3; ++slot) {
    const int j = plant::kStepperJoints[slot];
    SCOPED_TRACE("J" + std::to_string(j + 1));
    EXPECT_EQ(m.steps[slot].commanded, expected[slot]);
    EXPECT_EQ(m.steps[slot].lost, 0);
    EXPECT_EQ(m.steps[slot].ignored, 0);
    EXPECT_EQ(m.steps[slot].timing_violations, 0);
    // the last step comes when the count at the rate says, after the image's set-up (~86 us)
    const double start_s = sim.plant().driver(j).last_step_s() - (expected[slot] - 0.5) / rate_hz[slot];
    EXPECT_NEAR(start_s, 86.25e-6, 1e-6);
    EXPECT_NEAR(sim.q()[j], q0[j] + sign[slot] * expected[slot] * microstep_joint_rad(j), 0.5 * 32 * microstep_joint_rad(j));
    EXPECT_NEAR(sim.plant().stepper(j).q_commanded(), q0[j] + sign[slot] * expected[slot] * microstep_joint_rad(j), 1e-12);
  }
  for (const auto& f : m.sim_faults) ADD_FAILURE() << f;
}
