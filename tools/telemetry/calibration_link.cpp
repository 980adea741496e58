#include "calibration_link.h"

#include <algorithm>

#include "frame_text.h"
#include "kinematics/arm_model.h"
#include "serial_port.h"
#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

namespace {

using core::ArmState;
using protocol::MsgType;
using protocol::ReplyStatus;

constexpr auto kReplyWait = std::chrono::seconds(1);
constexpr int kReadings = 5;  // a pot's reading: the median of these, ~50 ms apart
constexpr auto kReadingEvery = std::chrono::milliseconds(50);
constexpr auto kJogEndWait = std::chrono::seconds(2);  // the firmware ends a jog 100 ms after its last frame, then slows the joint

template <class T>
T median(std::vector<T> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace

std::string fault_list(uint32_t faults) {
  std::string s;
  for (const std::string& n : telemetry::fault_names(faults)) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
}

double pot_angle_deg(int joint, int reading_counts_x16, int at_min_counts_x16, int at_max_counts_x16) {
  const double q_min = arm::q_min_deg[joint - 1], q_max = arm::q_max_deg[joint - 1];
  return q_min + (double)(reading_counts_x16 - at_min_counts_x16) * (q_max - q_min) / (at_max_counts_x16 - at_min_counts_x16);
}

CalibrationLink::CalibrationLink(const std::string& device, int input_fd, int joint, std::function<void(const std::string&)> note)
    : joint_(joint), note_(std::move(note)), link_(device, input_fd, [this](const protocol::Frame& f) { on_frame(f); }) {}

void CalibrationLink::on_frame(const protocol::Frame& f) {
  protocol::StateMsg state;
  protocol::ReplyMsg reply;
  protocol::CalibrationMsg calibration;
  if (protocol::decode(f, state)) {
    on_state(state);
  } else if (protocol::decode(f, reply)) {
    const auto sent = commands_.find(reply.command_seq);
    if (sent != commands_.end() && sent->second == reply.command_type) replies_.emplace(reply.command_seq, reply.status);
  } else if (protocol::decode(f, calibration)) {
    calibration_ = calibration;
    ++calibrations_;
  } else if (f.type == (uint8_t)MsgType::boot && watching_) {
    for (const std::string& line : report_lines(f)) note_(line + " (the board reset)");
  }
}

// The changes a person should know of while calibrating; the jog's own comings and goings are not
void CalibrationLink::on_state(const protocol::StateMsg& s) {
  auto calibrating = [](uint8_t state) { return state == (uint8_t)ArmState::wait_home || state == (uint8_t)ArmState::jog; };
  if (watching_ && states_ > 0) {
    if (s.faults != state_.faults) note_("faults: " + fault_list(s.faults));
    if (s.state != state_.state) {
      if (!calibrating(s.state)) {
        note_("the arm is now " + telemetry::state_name(s.state));
      } else if (!calibrating(state_.state)) {
        note_("the arm waits before homing again (" + telemetry::state_name(s.state) + ")");
      }
    }
  }
  state_ = s;
  ++states_;
}

uint8_t CalibrationLink::send(MsgType type, const uint8_t* payload, uint8_t len) {
  const uint8_t seq = next_seq_++;
  commands_[seq] = (uint8_t)type;
  replies_.erase(seq);  // a seq comes round again after 256 commands
  uint8_t frame[protocol::kMaxFrameBytes];
  const uint8_t n = protocol::write_frame((uint8_t)type, seq, payload, len, frame);
  link_.send(std::vector<uint8_t>(frame, frame + n));
  return seq;
}

bool CalibrationLink::wait_for_state(Clock::duration max) {
  return link_.pump(Clock::now() + max, [&] { return states_ > 0; });
}

ArmState CalibrationLink::wait_while_passing(Clock::duration max) {
  link_.pump(Clock::now() + max, [&] { return !passing(arm_state()); });
  return arm_state();
}

PotReading CalibrationLink::read_pot() {
  std::vector<int> readings;
  const auto start = Clock::now();
  for (int i = 0; i < kReadings; ++i) {
    link_.wait_until(start + i * kReadingEvery);
    const int before = calibrations_;
    const uint8_t seq = send(MsgType::cmd_get_calibration, nullptr, 0);
    const bool answered = link_.pump(Clock::now() + kReplyWait, [&] {
      return replied(seq) && (replies_[seq] != (uint8_t)ReplyStatus::ok || calibrations_ > before);
    });
    if (!answered) {
      if (stop_requested()) throw Interrupted{};
      throw IoError{link_.device() + ": " + (replied(seq) ? "no calibration frame" : "no reply") +
                    " to get_calibration in 1 s (the firmware running? the link?)"};
    }
    if (replies_[seq] != (uint8_t)ReplyStatus::ok) {
      throw IoError{link_.device() + ": the firmware answers get_calibration with " + telemetry::status_name(replies_[seq])};
    }
    readings.push_back(calibration_.reading_counts_x16[joint_ - 2]);
  }
  const int reading = median(readings);
  const int d = joint_ - 2;
  return PotReading{reading, pot_angle_deg(joint_, reading, calibration_.at_min_counts_x16[d], calibration_.at_max_counts_x16[d])};
}

JogReplies CalibrationLink::jog(int16_t speed_mrad_s, double seconds) {
  JogReplies r;
  std::vector<uint8_t> seqs;
  r.frames = link_.repeat(kJogPeriod, std::chrono::microseconds((long long)(seconds * 1e6)),
                          [&] { seqs.push_back(send(protocol::JogCmd{(uint8_t)joint_, speed_mrad_s})); });
  link_.pump(Clock::now() + kReplyWait, [&] {
    return std::all_of(seqs.begin(), seqs.end(), [&](uint8_t seq) { return replied(seq); });
  });
  for (uint8_t seq : seqs) {
    if (replied(seq)) {
      ++r.by_status[replies_[seq]];
    } else {
      ++r.unanswered;
    }
  }
  const int states_before = states_;
  link_.pump(Clock::now() + kJogEndWait, [&] { return states_ > states_before && arm_state() != ArmState::jog; });
  if (stop_requested()) throw Interrupted{};
  return r;
}

StoreReply CalibrationLink::store(const protocol::PotCalibrationCmd& command) {
  StoreReply r;
  const int before = calibrations_;
  const uint8_t seq = send(command);
  link_.pump(Clock::now() + kReplyWait, [&] {
    return replied(seq) && (replies_[seq] != (uint8_t)ReplyStatus::ok || calibrations_ > before);
  });
  if (stop_requested()) throw Interrupted{};
  r.replied = replied(seq);
  if (r.replied) r.status = replies_[seq];
  r.reported = calibrations_ > before;
  r.calibration = calibration_;
  return r;
}

}  // namespace telemetry_cli
}  // namespace wmra
