// A board on the master side of a pseudo-terminal, as the firmware behaves on its link, for
// tests of wmra-telemetry's session and calibrate: a boot frame boot_delay_s after the port is
// opened (a Mega's bootloader runs first), then a state frame every 20 ms, and a reply to every
// command as reply_status says (-1: none). It starts in wait_home; stop makes it stopped, rearm
// running, mode sets the mode; info sends an info frame after its reply. A test's board adds
// to it through the virtual hooks.
#pragma once

#include <chrono>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include "child_process.h"
#include "protocol/parser.h"
#include "protocol_frames.h"

namespace wmra {
namespace test {

struct FakeBoard {
  using Clock = std::chrono::steady_clock;

  int master = -1;
  std::string port;
  double boot_delay_s = 0.3;
  std::function<int(const protocol::Frame&)> reply_status = [](const protocol::Frame&) { return 0; };
  uint8_t state = 7, mode = 0;  // wait_home, xy
  uint32_t faults = 0;
  std::vector<protocol::Frame> commands;
  std::vector<double> command_at_s;  // since the port was opened
  double booted_at_s = -1;           // likewise
  bool open = false;
  Clock::time_point opened;
  uint8_t seq = 0;
  double next_state_s = 0;
  protocol::Parser parser;

  FakeBoard() {
    master = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return;
    port = ptsname(master);
    termios t;
    tcgetattr(master, &t);
    cfmakeraw(&t);
    tcsetattr(master, TCSANOW, &t);
    close(::open(port.c_str(), O_RDWR | O_NOCTTY));  // the master reads as hung up until the tool opens the port
  }
  virtual ~FakeBoard() {
    if (master >= 0) close(master);
  }
  FakeBoard(const FakeBoard&) = delete;
  FakeBoard& operator=(const FakeBoard&) = delete;

  void send(const std::vector<uint8_t>& bytes) { (void)!write(master, bytes.data(), bytes.size()); }

  static double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

  // --- the hooks

  // Every pass of serve()'s loop once the port is open (t_s since then): a board's own motion
  virtual void tick(double) {}
  // The state frame sent now (t_ms, state, mode and faults filled in by the caller)
  virtual void fill_state(protocol::StateMsg& s) {
    s.switches = 1 << 10;
    s.q_mrad[1] = 785;  // 45.0 deg
  }
  // A command whose reply said ok has just been answered
  virtual void obey(const protocol::Frame& f) {
    using protocol::MsgType;
    switch ((MsgType)f.type) {
      case MsgType::cmd_stop: state = 5; break;
      case MsgType::cmd_rearm: state = 4; break;
      case MsgType::cmd_mode: mode = f.payload[0]; break;
      case MsgType::cmd_info:
        send(protocol_frames::message_bytes(
            protocol::InfoMsg{protocol::Identity{{1, 2, 3}, {0x85, 0xe4, 0xee, 0x73, 0xd9, 0x0a}, 0, 0xf67e1bfa}, 150, 800,
                              {800, 1000, 1000, 1600, 1500, 1500}, {-1518, -733, -2304, -2740, -1518, -6231},
                              {1518, 2304, 2740, 2740, 1518, 6231}, 1000},
            ++seq));
        break;
      default: break;
    }
  }

  // Plays the board until the tool exits (its exit status) or max_s has passed (-1)
  int serve(ChildProcess& tool, double max_s) {
    using namespace protocol;
    const auto start = Clock::now();
    while (seconds_since(start) < max_s) {
      const int status = tool.exit_status(false);
      if (status >= 0) return status;
      pollfd p{master, POLLIN, 0};
      poll(&p, 1, 2);
      if (!open) {
        if (p.revents & POLLHUP) continue;
        open = true;
        opened = Clock::now();
      }
      const double t_s = seconds_since(opened);
      tick(t_s);
      if (booted_at_s < 0 && t_s >= boot_delay_s) {
        booted_at_s = t_s;
        send(protocol_frames::message_bytes(
            BootMsg{1, 0, Identity{{1, 2, 3}, {0x85, 0xe4, 0xee, 0x73, 0xd9, 0x0a}, 0, 0xf67e1bfa}}, seq = 0));
        next_state_s = t_s + 0.02;
      }
      if (booted_at_s >= 0 && t_s >= next_state_s) {
        StateMsg s{};
        s.t_ms = (uint32_t)((t_s - booted_at_s) * 1000);
        s.state = state;
        s.mode = mode;
        s.faults = faults;
        fill_state(s);
        send(protocol_frames::message_bytes(s, ++seq));
        next_state_s += 0.02;
      }
      uint8_t buf[256];
      const ssize_t n = read(master, buf, sizeof buf);
      for (ssize_t i = 0; i < n; ++i) {
        parser.push(buf[i]);
        while (parser.next()) {
          const Frame f = parser.frame();
          commands.push_back(f);
          command_at_s.push_back(t_s);
          const int status = reply_status(f);
          if (status < 0) continue;
          send(protocol_frames::message_bytes(ReplyMsg{f.type, f.seq, (uint8_t)status}, ++seq));
          if (status == 0) obey(f);
        }
      }
    }
    return -1;
  }
};

}  // namespace test
}  // namespace wmra
