// The firmware ELF against the virtual arm, for the scenario tests of test/sim_firmware: the
// simulator, the firmware's telemetry decoded as armsim decodes it, and commands to send it.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "armsim/firmware_telemetry.h"
#include "app/settings.h"
#include "armsim/run.h"
#include "core/supervisor.h"
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
  core::ArmState state() const {
    return telemetry.state() < 0 ? core::ArmState::boot : (core::ArmState)telemetry.state();
  }
  const protocol::StateMsg& last() const { return *telemetry.last_state(); }
  // the true pose of the frame-6 origin (plant angles, double FK)
  armsim::TrajectoryRow pose() const { return armsim::trajectory_row(sim.time_s(), sim.q(), 0, 0); }
};

}  // namespace test
}  // namespace wmra
