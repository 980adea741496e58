#include "live_pty.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <vector>

#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

namespace wmra {
namespace armsim {

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

std::runtime_error failure(const std::string& what) { return std::runtime_error(what + ": " + std::strerror(errno)); }

}  // namespace

LivePty::LivePty(const std::string& link) : link_(link) {
  master_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) throw failure("cannot open a pseudo-terminal");
  path_ = ptsname(master_);
  // the port's settings, set through the master: raw, so that no echo sends the firmware's own
  // bytes back to it before a host sets the port up (they stay while hosts come and go)
  termios t;
  if (tcgetattr(master_, &t) != 0) throw failure("cannot set up " + path_);
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  cfsetispeed(&t, B115200);
  cfsetospeed(&t, B115200);
  if (tcsetattr(master_, TCSANOW, &t) != 0) throw failure("cannot set up " + path_);
  // opened and closed once, the port reads as hung up (POLLHUP on the master) until a host opens it
  const int port = open(path_.c_str(), O_RDWR | O_NOCTTY);
  if (port < 0) throw failure("cannot open " + path_);
  close(port);

  if (!link_.empty()) {
    struct stat st;
    if (lstat(link_.c_str(), &st) == 0) {
      if (!S_ISLNK(st.st_mode)) throw std::runtime_error(link_ + " exists and is not a symbolic link: not replaced");
      if (unlink(link_.c_str()) != 0) throw failure("cannot replace " + link_);
    }
    if (symlink(path_.c_str(), link_.c_str()) != 0) throw failure("cannot make the link " + link_);
  }

  struct sigaction sa = {};
  sa.sa_handler = on_signal;  // no SA_RESTART: a wait in progress returns at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

LivePty::~LivePty() {
  if (!link_.empty()) {
    char target[PATH_MAX];
    const ssize_t n = readlink(link_.c_str(), target, sizeof target - 1);
    if (n >= 0 && std::string(target, (size_t)n) == path_) unlink(link_.c_str());  // still ours
  }
  if (master_ >= 0) close(master_);
}

bool LivePty::stopped_by_signal() const { return g_stop != 0; }

bool LivePty::after_slice(sim::ArmSimulator& sim) {
  if (!started_) {
    started_ = true;
    origin_ = Clock::now() - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(sim.time_s()));
  }
  forward_output(sim);
  take_input(sim);
  keep_pace(sim);
  return !g_stop;
}

bool LivePty::host_present() {
  pollfd p{master_, 0, 0};
  poll(&p, 1, 0);
  const bool present = !(p.revents & POLLHUP);
  if (present != host_) {
    host_ = present;
    if (present) {
      ++counts_.host_opens;
    } else {
      tcflush(master_, TCIOFLUSH);  // what the host left unread, and any half-read input
    }
  }
  return present;
}

void LivePty::forward_output(const sim::ArmSimulator& sim) {
  const std::vector<uint8_t>& out = sim.uart_output();
  if (forwarded_ == out.size()) return;
  const size_t n = out.size() - forwarded_;
  ssize_t written = 0;
  if (host_present()) {
    written = write(master_, out.data() + forwarded_, n);
    if (written < 0) written = 0;  // EAGAIN: the host reads no more; EIO: it has just closed the port
  }
  counts_.to_host_bytes += (uint64_t)written;
  counts_.dropped_bytes += n - (size_t)written;
  forwarded_ = out.size();
}

void LivePty::take_input(sim::ArmSimulator& sim) {
  uint8_t buf[4096];
  while (host_present()) {
    const ssize_t n = read(master_, buf, sizeof buf);
    if (n <= 0) return;  // EAGAIN: nothing more; EIO: the host has just closed the port
    counts_.from_host_bytes += (uint64_t)n;
    sim.send_serial(std::vector<uint8_t>(buf, buf + n));
  }
}

void LivePty::keep_pace(sim::ArmSimulator& sim) {
  for (;;) {
    const double ahead_s = sim.time_s() - std::chrono::duration<double>(Clock::now() - origin_).count();
    if (ahead_s < -kMaxLag_s) {
      counts_.behind_s += -ahead_s;
      origin_ += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(-ahead_s));
      return;
    }
    if (ahead_s <= 0 || g_stop) return;
    const timespec wait{(time_t)ahead_s, (long)((ahead_s - (time_t)ahead_s) * 1e9)};
    if (host_present()) {
      // a host's bytes go to the firmware as soon as they come, not at the slice's end
      pollfd p{master_, POLLIN, 0};
      if (ppoll(&p, 1, &wait, nullptr) > 0) take_input(sim);
    } else {
      nanosleep(&wait, nullptr);  // the master reads as hung up: polling it would not wait
    }
  }
}

}  // namespace armsim
}  // namespace wmra
