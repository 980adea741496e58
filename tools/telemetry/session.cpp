#include "session.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <vector>

#include <poll.h>
#include <unistd.h>

#include "commands.h"
#include "frame_text.h"
#include "serial_port.h"
#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

namespace {

using Clock = std::chrono::steady_clock;
using protocol::MsgType;

constexpr auto kBootWait = std::chrono::seconds(3);      // a Mega's bootloader runs 1-2 s after the reset
constexpr auto kReplyWait = std::chrono::seconds(1);
constexpr auto kJogPeriod = std::chrono::milliseconds(40);  // the firmware stops a jog 100 ms after the last frame
constexpr uint32_t kStatusEvery_ms = 1000;                 // a status line at least this often, by the firmware's clock

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// SIGINT and SIGTERM are blocked but while the session waits in ppoll(), with this mask: a
// signal that comes between a look at g_stop and the wait still ends the wait at once
sigset_t g_waiting_mask;

int wait_for(pollfd* fds, nfds_t n, int timeout_ms) {
  const timespec t{timeout_ms / 1000, (timeout_ms % 1000) * 1000000L};
  return ppoll(fds, n, timeout_ms < 0 ? nullptr : &t, &g_waiting_mask);
}

class Session {
 public:
  Session(int port, const SessionOptions& options) : port_(port), options_(options) {}

  int run() {
    wait_for_boot();
    std::string line;
    while (!g_stop && next_line(line)) {
      ++line_number_;
      try {
        obey(line);
      } catch (const BadInput& e) {
        ++bad_lines_;
        std::fprintf(stderr, "wmra-telemetry: line %d: %s\n", line_number_, e.message.c_str());
      }
    }
    std::fprintf(stderr, "wmra-telemetry: %s; commands: %d sent, %d replied; lines not used: %d\n",
                 stream_.summary().c_str(), sent_, replied_, bad_lines_);
    return bad_lines_ ? 2 : 0;
  }

 private:
  // --- the port

  // Reads what the port has (without waiting) and acts on every frame in it
  void read_port() {
    uint8_t buf[4096];
    const ssize_t n = read(port_, buf, sizeof buf);
    if (n == 0 || (n < 0 && errno == EIO)) throw IoError{options_.device + ": the port went away (its device closed)"};
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) return;
      throw IoError{options_.device + ": " + std::strerror(errno)};
    }
    for (ssize_t i = 0; i < n; ++i) {
      stream_.push(buf[i]);
      while (stream_.next()) on_frame(stream_.frame());
    }
  }

  void on_frame(const protocol::Frame& f) {
    if (options_.json) print(telemetry::to_json(f));
    protocol::StateMsg state;
    protocol::ReplyMsg reply;
    if (protocol::decode(f, state)) {
      heard_ = true;
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
      if (f.type == (uint8_t)MsgType::boot) heard_ = true;
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

  void send(const std::vector<uint8_t>& frame) {
    // one write, the bytes back to back: the firmware drops a frame with a 3 ms gap in it
    const ssize_t n = write(port_, frame.data(), frame.size());
    if (n != (ssize_t)frame.size()) throw IoError{options_.device + ": write: " + std::strerror(n < 0 ? errno : EIO)};
    ++sent_;
  }

  // Reads the port until done() or the deadline (or a signal); whether done() came true
  bool pump(Clock::time_point deadline, const std::function<bool()>& done) {
    while (!done()) {
      if (g_stop) return false;
      const auto left_us = std::chrono::duration_cast<std::chrono::microseconds>(deadline - Clock::now()).count();
      if (left_us <= 0) return false;
      pollfd p{port_, POLLIN, 0};
      const int ready = wait_for(&p, 1, (int)((left_us + 999) / 1000));  // never short of the deadline
      if (ready < 0 && errno != EINTR) throw IoError{std::string("poll: ") + std::strerror(errno)};
      if (ready > 0) read_port();
    }
    return true;
  }

  void wait_for_boot() {
    std::fprintf(stderr,
                 "wmra-telemetry: %s open. A Mega resets when its port is first opened: waiting up to 3 s for its boot "
                 "frame. The session keeps the port open, so the commands below do not reset it again.\n",
                 options_.device.c_str());
    if (!pump(Clock::now() + kBootWait, [&] { return heard_; }) && !g_stop) {
      std::fprintf(stderr, "wmra-telemetry: nothing from %s in 3 s (the firmware running? the right port?): going on\n",
                   options_.device.c_str());
    }
  }

  // --- the input

  // The next line of the input, the port read meanwhile; false at its end (or a signal)
  bool next_line(std::string& line) {
    for (;;) {
      const size_t end = input_.find('\n');
      if (end != std::string::npos) {
        line = input_.substr(0, end);
        input_.erase(0, end + 1);
        return true;
      }
      if (input_ended_) {
        line.swap(input_);
        return !line.empty();
      }
      if (g_stop) return false;
      pollfd p[2] = {{options_.input_fd, POLLIN, 0}, {port_, POLLIN, 0}};
      const int ready = wait_for(p, 2, -1);
      if (ready < 0) {
        if (errno == EINTR) continue;
        throw IoError{std::string("poll: ") + std::strerror(errno)};
      }
      if (p[1].revents) read_port();
      if (p[0].revents) {
        char buf[1024];
        const ssize_t n = read(options_.input_fd, buf, sizeof buf);
        if (n > 0) input_.append(buf, (size_t)n);
        if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) input_ended_ = true;
      }
    }
  }

  void obey(std::string line) {
    line = line.substr(0, line.find('#'));
    const std::vector<std::string> words = split_words(line);
    if (words.empty()) return;
    std::string text = words[0];
    for (size_t i = 1; i < words.size(); ++i) text += " " + words[i];
    if (words[0] == "sleep") {
      if (words.size() != 2) throw BadInput{"sleep takes SECONDS"};
      const double s = parse_number(words[1], 0, 3600, "sleep (seconds)");
      pump(Clock::now() + std::chrono::microseconds((long long)(s * 1e6)), [] { return false; });
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
    send(frame);
    const auto deadline = Clock::now() + kReplyWait;
    if (!pump(deadline, [&] { return replies_.count(seq) != 0; })) {
      commands_[seq].waited_out = true;
      if (!g_stop) note("> " + text + ": no reply");
      return;
    }
    const uint8_t status = replies_[seq];
    const bool report_follows = type == (uint8_t)MsgType::cmd_info || type == (uint8_t)MsgType::cmd_get_calibration ||
                                type == (uint8_t)MsgType::cmd_pot_calibration;
    if (report_follows && status == (uint8_t)protocol::ReplyStatus::ok) {
      pump(deadline, [&] { return reports_ > reports_before; });
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
    const auto start = Clock::now();
    const auto end = start + std::chrono::microseconds((long long)(seconds * 1e6));
    for (auto at = start; at < end && !g_stop; at += kJogPeriod) {
      pump(at, [] { return false; });
      if (g_stop) break;
      const uint8_t seq = next_seq_++;
      remember(seq, (uint8_t)MsgType::cmd_jog, text, seqs.empty(), true);
      send(encode_frame(frame_words, seq));
      seqs.push_back(seq);
    }
    pump(Clock::now() + kReplyWait, [&] { return jog_replies_ == (int)seqs.size(); });
    for (uint8_t seq : seqs) commands_[seq].waited_out = true;
    if (jog_replies_ == 0 && !g_stop) note("> " + text + ": no reply");
    std::string summary = "> " + text + ": " + std::to_string(seqs.size()) + " frames:";
    for (const auto& [status, count] : jog_statuses_) summary += " " + std::to_string(count) + " " + status + ",";
    if (jog_replies_ < (int)seqs.size()) summary += " " + std::to_string(seqs.size() - jog_replies_) + " no reply,";
    summary.pop_back();
    note(summary);
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

  const int port_;
  const SessionOptions& options_;
  telemetry::FrameStream stream_;
  bool heard_ = false;  // a state or boot frame came
  bool shown_ = false;
  protocol::StateMsg shown_state_{};
  std::map<uint8_t, Sent> commands_;
  std::map<uint8_t, uint8_t> replies_;  // the status of each reply to this session's commands, by seq
  int reports_ = 0;  // info and calibration frames received
  std::map<std::string, int> jog_statuses_;  // the replies to the jog under way, by status
  int jog_replies_ = 0;
  uint8_t next_seq_ = 1;
  int sent_ = 0, replied_ = 0, bad_lines_ = 0, line_number_ = 0;
  std::string input_;
  bool input_ended_ = false;
};

}  // namespace

int run_session(const SessionOptions& options) {
  const int port = open_serial(options.device);
  struct sigaction sa = {};
  sa.sa_handler = on_signal;  // no SA_RESTART: ppoll() returns and the session ends with its summary
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigprocmask(SIG_BLOCK, &stop_signals, &g_waiting_mask);
  Session session(port, options);
  const int status = session.run();
  close(port);
  return status;
}

}  // namespace telemetry_cli
}  // namespace wmra
