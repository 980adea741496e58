#include "session.h"

#include <cstdio>
#include <functional>
#include <map>
#include <vector>

#include "commands.h"
#include "core/supervisor.h"
#include "frame_text.h"
#include "serial_link.h"
#include "serial_port.h"
#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

namespace {

using protocol::MsgType;

constexpr auto kBootWait = std::chrono::seconds(3);      // a Mega's bootloader runs 1-2 s after the reset
constexpr auto kReplyWait = std::chrono::seconds(1);
constexpr auto kJogEndWait = std::chrono::seconds(1);  // a jog's joint slowing to rest, then the 100 ms timeout
constexpr uint32_t kStatusEvery_ms = 1000;                 // a status line at least this often, by the firmware's clock

class Session {
 public:
  explicit Session(const SessionOptions& options)
      : options_(options), link_(options.device, options.input_fd, [this](const protocol::Frame& f) { on_frame(f); }) {}

  int run() {
    wait_for_boot();
    std::string line;
    while (!stop_requested() && link_.next_line(line)) {
      ++line_number_;
      try {
        obey(line);
      } catch (const BadInput& e) {
        ++bad_lines_;
        std::fprintf(stderr, "wmra-telemetry: line %d: %s\n", line_number_, e.message.c_str());
      }
    }
    std::fprintf(stderr, "wmra-telemetry: %s; commands: %d sent, %d replied; lines not used: %d\n",
                 link_.stream().summary().c_str(), link_.sent(), replied_, bad_lines_);
    return bad_lines_ ? 2 : 0;
  }

 private:
  // --- what the firmware sends

  void on_frame(const protocol::Frame& f) {
    if (options_.json) print(telemetry::to_json(f));
    protocol::StateMsg state;
    protocol::ReplyMsg reply;
    if (protocol::decode(f, state)) {
      state_ = state.state;
      if (!options_.json) show_status(state);
    } else if (protocol::decode(f, reply)) {
      const auto sent = commands_.find(reply.command_seq);
      if (sent == commands_.end() || sent->second.type != reply.command_type) return;  // not this session's
      if (!replies_.emplace(reply.command_seq, reply.status).second) return;
      ++replied_;
      // the reply's line as it comes, before an info or calibration frame that follows it
      Sent& command = sent->second;
      const std::string status = telemetry::status_name(reply.status);
      if (command.waited_out) {
        note("> " + command.line + ": " + status + " (late)");
        return;
      }
      if (command.show_reply) note("> " + command.line + ": " + status);
      if (command.jog) {
        ++jog_statuses_[status];
        ++jog_replies_;
      }
    } else {
      if (f.type == (uint8_t)MsgType::info || f.type == (uint8_t)MsgType::calibration) ++reports_;
      if (!options_.json) {
        for (const std::string& line : report_lines(f)) print(line);
      }
    }
  }

  // a status line when the state, mode, faults or switches changed, and once a second otherwise
  void show_status(const protocol::StateMsg& s) {
    const bool changed = !shown_ || s.state != shown_state_.state || s.mode != shown_state_.mode ||
                         s.faults != shown_state_.faults || s.switches != shown_state_.switches;
    if (!changed && s.t_ms >= shown_state_.t_ms && s.t_ms - shown_state_.t_ms < kStatusEvery_ms) return;
    shown_ = true;
    shown_state_ = s;
    print(status_line(s));
  }

  void wait_for_boot() {
    std::fprintf(stderr,
                 "wmra-telemetry: %s open. A Mega resets when its port is first opened: waiting up to 3 s for its boot "
                 "frame. The session keeps the port open, so the commands below do not reset it again.\n",
                 options_.device.c_str());
    if (!link_.pump(Clock::now() + kBootWait, [&] { return link_.heard(); }) && !stop_requested()) {
      std::fprintf(stderr, "wmra-telemetry: nothing from %s in 3 s (the firmware running? the right port?): going on\n",
                   options_.device.c_str());
    }
  }

  // --- the input

  void obey(std::string line) {
    line = line.substr(0, line.find('#'));
    const std::vector<std::string> words = split_words(line);
    if (words.empty()) return;
    std::string text = words[0];
    for (size_t i = 1; i < words.size(); ++i) text += " " + words[i];
    if (words[0] == "sleep") {
      if (words.size() != 2) throw BadInput{"sleep takes SECONDS"};
      const double s = parse_number(words[1], 0, 3600, "sleep (seconds)");
      link_.wait_until(Clock::now() + std::chrono::microseconds((long long)(s * 1e6)));
    } else if (words[0] == "jog") {
      jog(words, text);
    } else {
      command(words, text);
    }
  }

  // Sends the command and waits for its reply (and for the info or calibration frame that
  // follows an ok to those), up to 1 s
  void command(const std::vector<std::string>& words, const std::string& text) {
    const uint8_t seq = next_seq_++;
    const std::vector<uint8_t> frame = encode_frame(words, seq);
    const uint8_t type = frame[2];
    remember(seq, type, text, true);
    const int reports_before = reports_;
    link_.send(frame);
    const auto deadline = Clock::now() + kReplyWait;
    if (!link_.pump(deadline, [&] { return replies_.count(seq) != 0; })) {
      commands_[seq].waited_out = true;
      if (!stop_requested()) note("> " + text + ": no reply");
      return;
    }
    const uint8_t status = replies_[seq];
    const bool report_follows = type == (uint8_t)MsgType::cmd_info || type == (uint8_t)MsgType::cmd_get_calibration ||
                                type == (uint8_t)MsgType::cmd_pot_calibration;
    if (report_follows && status == (uint8_t)protocol::ReplyStatus::ok) {
      link_.pump(deadline, [&] { return reports_ > reports_before; });
    }
  }

  // jog J RAD_S [SECONDS]: the jog frame every 40 ms for SECONDS (0.1..60, default 1), each
  // under a seq of its own; the first reply as it comes, then how all of them went
  void jog(const std::vector<std::string>& words, const std::string& text) {
    if (words.size() != 3 && words.size() != 4) throw BadInput{"jog takes J RAD_S [SECONDS]"};
    const double seconds = words.size() == 4 ? parse_number(words[3], 0.1, 60, "SECONDS (of the jog)") : 1.0;
    const std::vector<std::string> frame_words(words.begin(), words.begin() + 3);
    encode_frame(frame_words, 0);  // the joint and speed checked before anything is sent
    jog_statuses_.clear();
    jog_replies_ = 0;
    std::vector<uint8_t> seqs;
    link_.repeat(kJogPeriod, std::chrono::microseconds((long long)(seconds * 1e6)), [&] {
      const uint8_t seq = next_seq_++;
      remember(seq, (uint8_t)MsgType::cmd_jog, text, seqs.empty(), true);
      link_.send(encode_frame(frame_words, seq));
      seqs.push_back(seq);
    });
    link_.pump(Clock::now() + kReplyWait, [&] { return jog_replies_ == (int)seqs.size(); });
    for (uint8_t seq : seqs) commands_[seq].waited_out = true;
    if (jog_replies_ == 0 && !stop_requested()) note("> " + text + ": no reply");
    std::string summary = "> " + text + ": " + std::to_string(seqs.size()) + " frames:";
    for (const auto& [status, count] : jog_statuses_) summary += " " + std::to_string(count) + " " + status + ",";
    if (jog_replies_ < (int)seqs.size()) summary += " " + std::to_string(seqs.size() - jog_replies_) + " no reply,";
    summary.pop_back();
    note(summary);
    // the joint comes to rest and the arm leaves its jog (100 ms after the last frame) before
    // the next command: another joint's jog would be refused meanwhile
    link_.pump(Clock::now() + kJogEndWait, [&] { return state_ != (uint8_t)core::ArmState::jog; });
  }

  // a command sent under seq: its reply is matched by seq and type (a seq comes round again
  // after 256 commands, so the older one's reply is forgotten)
  void remember(uint8_t seq, uint8_t type, const std::string& text, bool show_reply, bool jog = false) {
    commands_[seq] = Sent{type, text, show_reply, jog, false};
    replies_.erase(seq);
  }

  void print(const std::string& line) {
    std::fputs((line + "\n").c_str(), stdout);
    std::fflush(stdout);
  }
  // a line about the commands: on stdout with the status lines, or on stderr beside --json's
  // frames (stdout stays JSON)
  void note(const std::string& line) {
    if (!options_.json) return print(line);
    std::fprintf(stderr, "%s\n", line.c_str());
  }

  struct Sent {
    uint8_t type;
    std::string line;
    bool show_reply;  // its reply's line when it comes (a jog's first frame, any other command)
    bool jog;         // one of a jog's frames: its reply counts in jog_statuses_
    bool waited_out;  // the wait for its reply is over: a reply now is late
  };

  const SessionOptions& options_;
  SerialLink link_;
  bool shown_ = false;
  protocol::StateMsg shown_state_{};
  uint8_t state_ = 0xFF;  // the latest state frame's state
  std::map<uint8_t, Sent> commands_;
  std::map<uint8_t, uint8_t> replies_;  // the status of each reply to this session's commands, by seq
  int reports_ = 0;  // info and calibration frames received
  std::map<std::string, int> jog_statuses_;  // the replies to the jog under way, by status
  int jog_replies_ = 0;
  uint8_t next_seq_ = 1;
  int replied_ = 0, bad_lines_ = 0, line_number_ = 0;
};

}  // namespace

int run_session(const SessionOptions& options) {
  Session session(options);
  catch_stop_signals();
  return session.run();
}

}  // namespace telemetry_cli
}  // namespace wmra
