// What `wmra-telemetry calibrate` asks of the firmware for one DC joint: the arm's state, the
// joint's pot reading and the firmware's angle of it, a jog, and a new calibration stored
// (get_calibration, jog and pot_calibration, docs/telemetry.md). The person's side is calibrate.cpp.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/supervisor.h"
#include "protocol/messages.h"
#include "serial_link.h"

namespace wmra {
namespace telemetry_cli {

// SIGINT or SIGTERM ended a wait
struct Interrupted {};

// The pot where the joint stands
struct PotReading {
  int counts_x16;    // the median of a few readings (the pot is noisy), ADC counts x 16
  double angle_deg;  // the firmware's angle of that reading (pot_angle_deg through its calibration)
};

// A DC joint's (2..4) angle for a pot reading, on the line through its limits' readings: the
// firmware's (core::PotMap) to within its 1 mrad. Its state frames' q_mrad flicker by a count's
// 0.3 deg with the pot's noise; this is the angle of the very reading a point takes.
double pot_angle_deg(int joint, int reading_counts_x16, int at_min_counts_x16, int at_max_counts_x16);

// How a jog's frames were answered
struct JogReplies {
  int frames = 0;
  std::map<uint8_t, int> by_status;  // protocol::ReplyStatus -> how many
  int unanswered = 0;
};

// The reply to pot_calibration and, when it is ok, the calibration frame that follows
struct StoreReply {
  bool replied = false;
  uint8_t status = 0;           // protocol::ReplyStatus
  bool reported = false;        // the calibration frame came
  protocol::CalibrationMsg calibration{};
};

// The states the arm leaves by itself: boot and wait_neutral arm it (the stick released), a jog
// ends 100 ms after its last command
inline bool passing(core::ArmState s) {
  return s == core::ArmState::boot || s == core::ArmState::wait_neutral || s == core::ArmState::jog;
}

// The faults' names, "j3_stall, tracking", or "none"
std::string fault_list(uint32_t faults);

class CalibrationLink {
 public:
  // note(line): what the person should see as it happens, once watch() has been called: a
  // change of the faults, a state other than wait_home and jog, a boot frame (the board reset)
  CalibrationLink(const std::string& device, int input_fd, int joint, std::function<void(const std::string&)> note);

  // Waits up to max for the first state frame; whether one came
  bool wait_for_state(Clock::duration max);
  // Waits up to max while the arm is in a state that passes by itself (passing()); the state then
  core::ArmState wait_while_passing(Clock::duration max);
  const protocol::StateMsg& state() const { return state_; }
  core::ArmState arm_state() const { return (core::ArmState)state_.state; }
  void watch() { watching_ = true; }

  // Sends get_calibration a few times ~50 ms apart and takes the median of the joint's
  // readings. Throws IoError when the firmware does not answer, Interrupted.
  PotReading read_pot();
  // The calibration frame of the latest read_pot() or store()
  const protocol::CalibrationMsg& calibration() const { return calibration_; }

  // Turns the joint at speed_mrad_s for seconds (a jog frame every kJogPeriod), then waits for
  // the firmware to end the jog (the joint at rest, the drives off again). Throws Interrupted.
  JogReplies jog(int16_t speed_mrad_s, double seconds);

  // Sends pot_calibration and waits for its reply and the calibration frame after an ok
  // (throws Interrupted, the command perhaps sent)
  StoreReply store(const protocol::PotCalibrationCmd& command);

  bool next_line(std::string& line) { return link_.next_line(line); }

 private:
  void on_frame(const protocol::Frame& f);
  void on_state(const protocol::StateMsg& s);
  uint8_t send(protocol::MsgType type, const uint8_t* payload, uint8_t len);  // its seq
  template <class Msg>
  uint8_t send(const Msg& m) {
    uint8_t payload[protocol::kMaxPayload];
    return send(Msg::kType, payload, protocol::encode(m, payload));
  }
  bool replied(uint8_t seq) const { return replies_.count(seq) != 0; }

  const int joint_;  // 2..4
  const std::function<void(const std::string&)> note_;
  bool watching_ = false;
  protocol::StateMsg state_{};
  int states_ = 0;                       // state frames received
  protocol::CalibrationMsg calibration_{};
  int calibrations_ = 0;                 // calibration frames received
  std::map<uint8_t, uint8_t> commands_;  // the type of each command sent, by seq
  std::map<uint8_t, uint8_t> replies_;   // the status of each reply to them, by seq
  uint8_t next_seq_ = 1;
  SerialLink link_;  // last: its frames reach the members above
};

}  // namespace telemetry_cli
}  // namespace wmra
