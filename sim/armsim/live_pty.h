// armsim --live: the simulation paced to the wall clock, and the firmware's UART on a
// pseudo-terminal that a host tool opens as it would the board's serial port.
//
// Bytes a host writes reach the firmware's UART at 115200 baud's pace (sim.send_serial); the
// bytes the firmware sends go to the host as they come out. While no host has the port open
// they are dropped, as on a line nobody listens to, and what a host leaves unread when it
// closes the port is dropped too: the next host starts clean. Hosts may open and close the
// port any number of times. Unlike a Mega, the virtual arm does not reset when the port is
// opened (no DTR): a host sees state frames at once, and the boot frame only at the run's start.
//
// SIGINT and SIGTERM end the run at the next slice (1 ms of simulated time); run_scenario then
// writes its files as at the scenario's end.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "armsim/run.h"

namespace wmra {
namespace armsim {

class LivePty : public LiveHook {
 public:
  // Opens the pseudo-terminal, raw as a serial port at 115200 8N1; makes `link` (unless
  // empty) a symbolic link to it, replacing an older symbolic link but no other file; and
  // installs the SIGINT and SIGTERM handlers. Throws std::runtime_error saying what failed.
  explicit LivePty(const std::string& link);
  ~LivePty() override;  // closes the pseudo-terminal and removes the link
  LivePty(const LivePty&) = delete;
  LivePty& operator=(const LivePty&) = delete;

  const std::string& path() const { return path_; }  // the port, /dev/pts/N

  double slice_s() const override { return kSlice_s; }
  bool after_slice(sim::ArmSimulator& sim) override;

  struct Counts {
    uint64_t to_host_bytes = 0;
    uint64_t dropped_bytes = 0;  // sent by the firmware while no host read them
    uint64_t from_host_bytes = 0;
    int host_opens = 0;
    double behind_s = 0;  // how far the simulation fell behind the wall clock, in all
  };
  const Counts& counts() const { return counts_; }
  bool stopped_by_signal() const;

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr double kSlice_s = 0.001;
  // farther behind the wall clock than this (a loaded computer), the simulation goes on from
  // where it is instead of racing to catch up: simulated time stays even for the host
  static constexpr double kMaxLag_s = 0.2;

  bool host_present();  // a host has the port open; notes opens and closes
  void forward_output(const sim::ArmSimulator& sim);
  void take_input(sim::ArmSimulator& sim);
  void keep_pace(sim::ArmSimulator& sim);  // waits until the wall clock reaches the simulated time

  int master_ = -1;
  std::string path_, link_;
  bool host_ = false;
  bool started_ = false;
  Clock::time_point origin_;  // the wall-clock time of simulated time 0
  size_t forwarded_ = 0;      // of the firmware's UART output
  Counts counts_;
};

}  // namespace armsim
}  // namespace wmra
