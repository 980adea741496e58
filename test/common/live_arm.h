// The virtual arm live for a test: armsim --live with its UART on a pseudo-terminal linked at
// out_dir/NAME.pty (optionally its stdin on a pipe of the test's: --stdin), and a host on that
// port, opened raw as wmra-telemetry opens it.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "child_process.h"
#include "protocol/parser.h"

namespace wmra {
namespace test {

inline double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

struct LiveArm {
  std::string name, dir, link, pty;  // pty: the port's path once armsim printed "pty: PATH" (empty if not)
  int keys = -1;                     // with stdin_events: the write end of armsim's stdin
  std::unique_ptr<ChildProcess> armsim;

  // scenario: a file; empty: one that holds the stick centred until end_s
  LiveArm(const std::string& armsim_bin, const std::string& firmware, const std::string& out_dir, const std::string& test, double end_s,
          const std::string& scenario = "", bool stdin_events = false)
      : name(test), dir(out_dir + "/" + test), link(out_dir + "/" + test + ".pty") {
    std::string run = scenario;
    if (run.empty()) {
      run = out_dir + "/" + test + ".txt";
      std::ofstream(run) << "0 joystick 0 0\n" << end_s << " end\n";
    }
    std::filesystem::remove_all(dir);
    std::vector<std::string> argv{armsim_bin, "--scenario", run, "--out", dir, "--elf", firmware, "--live", "--pty", link};
    int pipe_fds[2] = {-1, -1};
    if (stdin_events && pipe2(pipe_fds, O_CLOEXEC) == 0) {
      argv.push_back("--stdin");
      keys = pipe_fds[1];
    }
    armsim = std::make_unique<ChildProcess>(argv, out_dir + "/" + test + "_armsim", "/dev/null", pipe_fds[0]);
    if (pipe_fds[0] >= 0) close(pipe_fds[0]);
    const auto start = std::chrono::steady_clock::now();
    while (seconds_since(start) < 20 && armsim->pid > 0) {
      const std::string out = armsim->out();
      if (out.rfind("pty: ", 0) == 0 && out.back() == '\n') {
        pty = out.substr(5, out.size() - 6);
        break;
      }
      usleep(10000);
    }
  }
  ~LiveArm() {
    if (keys >= 0) close(keys);
  }
  // a line into armsim's stdin (the person's hands: "estop down", "joystick 0 0.4")
  bool type(const std::string& line) {
    const std::string l = line + "\n";
    return keys >= 0 && write(keys, l.data(), l.size()) == (ssize_t)l.size();
  }
};

// A host on the port: opened raw, as wmra-telemetry opens it
struct Host {
  int fd = -1;
  protocol::Parser parser;
  explicit Host(const std::string& port) {
    fd = open(port.c_str(), O_RDWR | O_NOCTTY);
    if (fd < 0) return;
    termios t;
    tcgetattr(fd, &t);
    cfmakeraw(&t);
    tcsetattr(fd, TCSANOW, &t);
    tcflush(fd, TCIOFLUSH);
  }
  ~Host() { hang_up(); }
  void hang_up() {
    if (fd >= 0) close(fd);
    fd = -1;
  }
  bool send(const std::vector<uint8_t>& frame) { return write(fd, frame.data(), frame.size()) == (ssize_t)frame.size(); }
  // the frames that come within max_s, until `enough` says so
  template <class Enough>
  std::vector<protocol::Frame> frames_until(double max_s, Enough enough) {
    std::vector<protocol::Frame> frames;
    const auto start = std::chrono::steady_clock::now();
    while (seconds_since(start) < max_s && !enough(frames)) {
      pollfd p{fd, POLLIN, 0};
      if (poll(&p, 1, 10) != 1) continue;
      uint8_t buf[512];
      const ssize_t n = read(fd, buf, sizeof buf);
      for (ssize_t i = 0; i < n; ++i) {
        parser.push(buf[i]);
        while (parser.next()) frames.push_back(parser.frame());
      }
    }
    return frames;
  }
};

}  // namespace test
}  // namespace wmra
