// The firmware ELF against the virtual arm: start-up, and the safety scenarios of SPEC 6 and 9
// (S5 safety button, S10 watchdog). The firmware's state comes from its own
// telemetry, decoded with firmware/protocol; the arm's from the plant.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/supervisor.h"
#include "protocol/frame.h"
#include "protocol/messages.h"
#include "wiring/arm_simulator.h"

namespace {

using namespace wmra;

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kTestFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware_test.elf";

// near the homing switches, so that start-up takes a few seconds
const plant::Joints kNearHome = {1.50, 0.30, -1.00, 0.60, -1.50, 0.02};

struct Telemetry {
  protocol::Parser parser;
  size_t fed = 0;
  std::vector<protocol::StateMsg> states;
  std::vector<protocol::BootMsg> boots;
  std::vector<protocol::ReplyMsg> replies;

  void update(const sim::ArmSimulator& sim) {
    const std::vector<uint8_t>& out = sim.uart_output();
    for (; fed < out.size(); ++fed) {
      if (!parser.feed(out[fed])) continue;
      const protocol::Frame& f = parser.frame();
      if (f.type == (uint8_t)protocol::MsgType::state) {
        protocol::StateMsg m;
        if (protocol::decode(f, m)) states.push_back(m);
      } else if (f.type == (uint8_t)protocol::MsgType::boot) {
        protocol::BootMsg m;
        if (protocol::decode(f, m)) boots.push_back(m);
      } else if (f.type == (uint8_t)protocol::MsgType::reply) {
        protocol::ReplyMsg m;
        if (protocol::decode(f, m)) replies.push_back(m);
      }
    }
  }
  core::ArmState state() const { return states.empty() ? core::ArmState::boot : (core::ArmState)states.back().state; }
};

std::vector<uint8_t> command(protocol::MsgType type, uint8_t seq, std::vector<uint8_t> payload = {}) {
  std::vector<uint8_t> frame(protocol::kMaxFrameBytes);
  frame.resize(protocol::write_frame((uint8_t)type, seq, payload.data(), (uint8_t)payload.size(), frame.data()));
  return frame;
}

struct Rig {
  sim::ArmSimulator sim;
  Telemetry telemetry;
  explicit Rig(const std::string& elf) : sim(config(elf)) {}
  static sim::SimConfig config(const std::string& elf) {
    sim::SimConfig c;
    c.elf = elf;
    c.initial_q = kNearHome;
    return c;
  }
  void run_to(double t_s) {
    sim.run_until(t_s);
    telemetry.update(sim);
  }
  // runs until the firmware reports this state, at most until t_max_s; the time, or -1
  double run_until_state(core::ArmState s, double t_max_s) {
    for (double t = sim.time_s(); t < t_max_s; t += 0.02) {
      run_to(t + 0.02);
      if (telemetry.state() == s) return sim.time_s();
    }
    return -1;
  }
};

TEST(FirmwareStartUp, HomesAndReachesTheReadyPose) {
  Rig rig(kFirmware);
  const double t_running = rig.run_until_state(core::ArmState::running, 12.0);
  ASSERT_GT(t_running, 0) << "the firmware did not reach running; last state "
                          << core::to_string(rig.telemetry.state());
  ASSERT_FALSE(rig.telemetry.boots.empty());
  EXPECT_EQ(rig.telemetry.boots[0].reset_cause & 8, 0) << "not a watchdog reset at power-up";
  rig.run_to(t_running + 0.5);
  // the firmware's joint angles (steppers from homing and step counts, DC from pots) against the plant
  const protocol::StateMsg& s = rig.telemetry.states.back();
  const plant::Joints q = rig.sim.q();
  for (int j = 0; j < 6; ++j) {
    const double tolerance_mrad = (j == 0 || j >= 4) ? 3.0 : 10.0;
    EXPECT_NEAR(s.q_mrad[j], q[j] * 1000.0, tolerance_mrad) << "joint " << j + 1;
  }
  // off the singular J5 = -90 deg, at the configured ready pose (70, 20, -70, 50, -30, 0 deg)
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0};
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(q[j] * 180 / M_PI, ready_deg[j], 1.5) << "joint " << j + 1;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].lost, 0);
  EXPECT_TRUE(rig.sim.measurements().sim_faults.empty());
}

// S5: the safety button turns every output off from its interrupt (well within 1 ms), and nothing is driven (no step,
// no PWM) until it is released and the arm re-armed. (A joint moving at the press coasts:
// the drivers are off, as SPEC 6 asks.)
TEST(FirmwareSafety, S5SafetyButtonStopsUntilReleasedAndRearmed) {
  Rig rig(kFirmware);
  const double t_running = rig.run_until_state(core::ArmState::running, 12.0);
  ASSERT_GT(t_running, 0);
  rig.sim.set_joystick(1.0, 0.0);
  rig.run_to(t_running + 0.5);
  rig.sim.set_estop(true);
  rig.run_to(t_running + 0.52);
  const sim::Measurements m = rig.sim.measurements();
  ASSERT_EQ(m.estop.size(), 1u);
  ASSERT_GE(m.estop[0].outputs_off_s, 0) << "outputs still on";
  // SPEC 6: from the button's interrupt, not the next control tick (up to 1 ms later)
  const double latency_s = m.estop[0].outputs_off_s - m.estop[0].pressed_s;
  EXPECT_LE(latency_s, 100e-6);
  RecordProperty("estop_latency_us", std::to_string(latency_s * 1e6));
  rig.run_to(t_running + 1.0);
  EXPECT_EQ(rig.telemetry.state(), core::ArmState::stopped);
  const sim::Measurements at_stop = rig.sim.measurements();
  rig.sim.set_estop(false);  // released, stick still deflected: nothing driven without a re-arm
  bool driven = false;
  for (double t = t_running + 1.0; t < t_running + 2.0; t += 0.01) {
    rig.run_to(t);
    driven |= !rig.sim.outputs_off();
  }
  EXPECT_FALSE(driven);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].commanded, at_stop.steps[k].commanded);
  EXPECT_EQ(rig.telemetry.state(), core::ArmState::stopped);
  rig.sim.set_joystick(0.0, 0.0);
  rig.sim.send_serial(command(protocol::MsgType::cmd_rearm, 1));
  EXPECT_GT(rig.run_until_state(core::ArmState::running, t_running + 4.0), 0) << "re-arm did not bring it back";
}

// S10: a hung main loop (test build) ends in a watchdog reset, outputs off, and the cause reported
TEST(FirmwareSafety, S10HangEndsInWatchdogResetReported) {
  Rig rig(kTestFirmware);
  const double t_running = rig.run_until_state(core::ArmState::running, 12.0);
  ASSERT_GT(t_running, 0);
  rig.sim.send_serial(command((protocol::MsgType)0x7F, 1));
  rig.run_to(t_running + 0.3);
  const sim::Measurements m = rig.sim.measurements();
  ASSERT_EQ(m.resets.size(), 1u);
  EXPECT_EQ(m.resets[0].cause, "watchdog");
  EXPECT_TRUE(rig.sim.outputs_off());
  ASSERT_GE(rig.telemetry.boots.size(), 2u);
  EXPECT_NE(rig.telemetry.boots.back().reset_cause & 8, 0) << "the boot frame after the reset names the watchdog";
  EXPECT_NE(rig.telemetry.state(), core::ArmState::running);
}

}  // namespace
