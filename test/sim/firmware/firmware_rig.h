// The firmware ELF against the virtual arm, for the scenario tests of test/sim/firmware: the
// simulator, the firmware's telemetry decoded as armsim decodes it, and commands to send it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "armsim/firmware_telemetry.h"
#include "app/settings.h"
#include "armsim/run.h"
#include "config/control_config.h"
#include "core/supervisor.h"
#include "kinematics/arm_model.h"
#include "protocol/frame.h"
#include "protocol/messages.h"
#include "wiring/arm_simulator.h"

namespace wmra {
namespace test {

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kTestFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware_test.elf";

// near the homing switches, so that start-up takes a few seconds
const plant::Joints kNearHome = {1.50, 0.30, -1.00, 0.60, -1.50, 0.02};

// the distance between two points in metres, in mm
inline double distance_mm(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return 1000 * std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// a command frame with a raw payload
inline std::vector<uint8_t> command(protocol::MsgType type, uint8_t seq, std::vector<uint8_t> payload = {}) {
  std::vector<uint8_t> frame(protocol::kMaxFrameBytes);
  frame.resize(protocol::write_frame((uint8_t)type, seq, payload.data(), (uint8_t)payload.size(), frame.data()));
  return frame;
}

// a command frame of a message (VelocityCmd)
template <class Msg>
std::vector<uint8_t> message(const Msg& m, uint8_t seq) {
  std::vector<uint8_t> frame(protocol::kMaxFrameBytes);
  frame.resize(protocol::write_message(m, seq, frame.data()));
  return frame;
}

// a long press: held a little beyond kButtonLongPress_ms
constexpr double kLongPress_s = config::kButtonLongPress_ms / 1000.0 + 0.2;

// A scenario line (armsim's format) that asks for the homing as a host does: `home` at
// kHomeAt_s, once the stick's calibration and neutral hold at power-up have put the arm in
// wait_home (at about 0.6 s).
constexpr double kHomeAt_s = 0.7;
inline std::vector<uint8_t> home_frame() { return command(protocol::MsgType::cmd_home, 0xE0); }
// bytes as a scenario's `serial` line writes them
inline std::string hex(const std::vector<uint8_t>& bytes) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  for (uint8_t b : bytes) {
    out += kHex[b >> 4];
    out += kHex[b & 15];
  }
  return out;
}
inline std::string home_event(double t_s = kHomeAt_s) { return std::to_string(t_s) + " serial " + hex(home_frame()) + "\n"; }

// the same on a simulator run without a Rig: runs to t_s and sends `home`
inline void ask_home_at(sim::ArmSimulator& sim, double t_s = kHomeAt_s) {
  sim.run_until(t_s);
  sim.send_serial(home_frame());
}

// A settings block as lib/drivers/eeprom_store.cpp writes it: "WA", the layout's version, the
// size, the fields packed as avr-gcc packs them (little-endian, no padding), a CRC-16 of all
// that. Version 1 is the layout without pot_calibrated.
inline std::vector<uint8_t> settings_block(const app::Settings& s, uint8_t version = app::kSettingsVersion) {
  std::vector<uint8_t> data;
  const auto put = [&](int64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) data.push_back((uint8_t)(v >> (8 * i)));
  };
  for (int16_t v : s.pot_at_min_counts_x16) put(v, 2);
  for (int16_t v : s.pot_at_max_counts_x16) put(v, 2);
  for (const auto& pose : s.pose_angle)
    for (int32_t v : pose) put(v, 4);
  put(s.pose_valid, 1);
  if (version >= 2) put(s.pot_calibrated, 1);
  if (version >= 3)
    for (uint16_t v : s.stick_centre_counts) put(v, 2);
  std::vector<uint8_t> block = {'W', 'A', version, (uint8_t)data.size(), (uint8_t)(data.size() >> 8)};
  for (uint8_t b : data) block.push_back(b);
  uint16_t crc = protocol::kCrcInit;
  for (uint8_t b : block) crc = protocol::crc16_update(crc, b);
  block.push_back((uint8_t)crc);
  block.push_back((uint8_t)(crc >> 8));
  return block;
}

// What the plant did while a test ran, sampled every millisecond: the joints' extremes, the
// limit switches (as the board sees them, and the contacts themselves: a joint at or past its
// limit), and whether any output was on.
struct PlantWatch {
  plant::Joints q_min, q_max;
  bool switch_closed = false;  // a limit switch of J1..J5 as the Mega reads it
  bool at_limit = false;       // a joint at or past its switch's angle
  bool driven = false;         // a bridge on (the steppers' steps are counted apart)
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
    driven |= !sim.bridges_off();
  }
  double travel_rad(int j) const { return q_max[j] - q_min[j]; }
  double largest_travel_rad() const {
    double m = 0;
    for (int j = 0; j < 6; ++j) m = std::max(m, travel_rad(j));
    return m;
  }
};

struct Rig {
  sim::ArmSimulator sim;
  armsim::FirmwareTelemetry telemetry;
  size_t fed = 0;  // UART bytes given to telemetry

  explicit Rig(const std::string& elf, const plant::Joints& initial_q = kNearHome, bool stock_bootloader = false)
      : sim(config(elf, initial_q, stock_bootloader)) {}
  explicit Rig(const sim::SimConfig& c) : sim(c) {}
  static sim::SimConfig config(const std::string& elf, const plant::Joints& initial_q, bool stock_bootloader) {
    sim::SimConfig c;
    c.elf = elf;
    c.initial_q = initial_q;
    c.stock_bootloader = stock_bootloader;
    return c;
  }
  void run_to(double t_s) {
    sim.run_until(t_s);
    feed_telemetry();
  }
  // the UART's bytes so far to telemetry (run_to does it at its end; a callback within a run, here)
  void feed_telemetry() {
    const std::vector<uint8_t>& out = sim.uart_output();
    for (; fed < out.size(); ++fed) telemetry.feed(out[fed]);
  }
  // runs until the firmware reports this state, at most until t_max_s; the time, or -1
  double run_until_state(core::ArmState s, double t_max_s) {
    for (double t = sim.time_s(); t < t_max_s; t += 0.02) {
      run_to(t + 0.02);
      if (state() == s) return sim.time_s();
    }
    return -1;
  }
  // After power-up and every reset nothing moves until the person asks. This asks as the
  // person does: it waits for wait_home (the stick neutral for the hold), presses the button
  // long (no reply for a test to count) and runs until the arm runs from the ready pose, at most
  // until t_max_s; the time, or -1.
  double start(double t_max_s) {
    if (run_until_state(core::ArmState::wait_home, t_max_s) < 0) return -1;
    press_button(kLongPress_s);
    return run_until_state(core::ArmState::running, t_max_s);
  }
  // the host's way: runs until wait_home and sends `home` there; the time, or -1
  double ask_home(double t_max_s) {
    const double t = run_until_state(core::ArmState::wait_home, t_max_s);
    if (t >= 0) sim.send_serial(home_frame());
    return t;
  }
  // the joystick button held for `held_s` from now (a long press at kButtonLongPress_ms)
  void press_button(double held_s) {
    sim.set_button(true);
    run_to(sim.time_s() + held_s);
    sim.set_button(false);
  }
  core::ArmState state() const {
    return telemetry.state() < 0 ? core::ArmState::boot : (core::ArmState)telemetry.state();
  }
  const protocol::StateMsg& last() const { return *telemetry.last_state(); }
  // the true pose of the frame-6 origin (plant angles, double FK)
  armsim::TrajectoryRow pose() const { return armsim::trajectory_row(sim.time_s(), sim.q(), 0, 0); }
};

}  // namespace test
}  // namespace wmra
