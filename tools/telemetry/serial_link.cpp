#include "serial_link.h"

#include <cerrno>
#include <csignal>
#include <cstring>

#include <poll.h>
#include <unistd.h>

#include "serial_port.h"

namespace wmra {
namespace telemetry_cli {

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// SIGINT and SIGTERM are blocked but while the link waits in ppoll(), with this mask: a signal
// that comes between a look at g_stop and the wait still ends the wait at once
sigset_t g_waiting_mask;
bool g_signals_caught = false;

int wait_for(pollfd* fds, nfds_t n, int timeout_ms) {
  const timespec t{timeout_ms / 1000, (timeout_ms % 1000) * 1000000L};
  return ppoll(fds, n, timeout_ms < 0 ? nullptr : &t, g_signals_caught ? &g_waiting_mask : nullptr);
}

}  // namespace

void catch_stop_signals() {
  struct sigaction sa = {};
  sa.sa_handler = on_signal;  // no SA_RESTART: ppoll() returns and the tool ends its own way
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigprocmask(SIG_BLOCK, &stop_signals, &g_waiting_mask);
  g_signals_caught = true;
}

bool stop_requested() { return g_stop != 0; }

SerialLink::SerialLink(const std::string& device, int input_fd, FrameHandler on_frame)
    : device_(device), input_fd_(input_fd), on_frame_(std::move(on_frame)), port_(open_serial(device)) {}

SerialLink::~SerialLink() { close(port_); }

void SerialLink::send(const std::vector<uint8_t>& frame) {
  const ssize_t n = write(port_, frame.data(), frame.size());
  if (n != (ssize_t)frame.size()) throw IoError{device_ + ": write: " + std::strerror(n < 0 ? errno : EIO)};
  ++sent_;
}

// Reads what the port has (without waiting) and hands over every frame in it
void SerialLink::read_port() {
  uint8_t buf[4096];
  const ssize_t n = read(port_, buf, sizeof buf);
  if (n == 0 || (n < 0 && errno == EIO)) throw IoError{device_ + ": the port went away (its device closed)"};
  if (n < 0) {
    if (errno == EINTR || errno == EAGAIN) return;
    throw IoError{device_ + ": " + std::strerror(errno)};
  }
  for (ssize_t i = 0; i < n; ++i) {
    stream_.push(buf[i]);
    while (stream_.next()) {
      const protocol::Frame& f = stream_.frame();
      if (f.type == (uint8_t)protocol::MsgType::state || f.type == (uint8_t)protocol::MsgType::boot) heard_ = true;
      on_frame_(f);
    }
  }
}

bool SerialLink::pump(Clock::time_point deadline, const std::function<bool()>& done) {
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

int SerialLink::repeat(Clock::duration period, Clock::duration span, const std::function<void()>& send_one) {
  int calls = 0;
  const auto start = Clock::now();
  for (auto at = start; at < start + span && !g_stop; at += period) {
    wait_until(at);
    if (g_stop) break;
    send_one();
    ++calls;
  }
  return calls;
}

bool SerialLink::next_line(std::string& line) {
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
    pollfd p[2] = {{input_fd_, POLLIN, 0}, {port_, POLLIN, 0}};
    const int ready = wait_for(p, 2, -1);
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw IoError{std::string("poll: ") + std::strerror(errno)};
    }
    if (p[1].revents) read_port();
    if (p[0].revents) {
      char buf[1024];
      const ssize_t n = read(input_fd_, buf, sizeof buf);
      if (n > 0) input_.append(buf, (size_t)n);
      if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) input_ended_ = true;
    }
  }
}

}  // namespace telemetry_cli
}  // namespace wmra
