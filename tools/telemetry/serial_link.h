// The firmware's serial link as a host tool holds it open (wmra-telemetry session, calibrate):
// the port read as frames come, each handed to the tool; command frames written whole; waits
// that keep reading the port; the person's input lines read meanwhile; SIGINT and SIGTERM
// ending any wait at once.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

using Clock = std::chrono::steady_clock;

// The period of a jog's frames: the firmware stops a jog 100 ms after the last one
constexpr auto kJogPeriod = std::chrono::milliseconds(40);

// Makes SIGINT and SIGTERM end the link's waits (no SA_RESTART) and stop_requested() true;
// call once, before the first wait
void catch_stop_signals();
bool stop_requested();

class SerialLink {
 public:
  using FrameHandler = std::function<void(const protocol::Frame&)>;

  // Opens device as open_serial() does (throws IoError); input_fd holds the person's lines
  SerialLink(const std::string& device, int input_fd, FrameHandler on_frame);
  ~SerialLink();
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  // Writes the frame in one piece: the firmware drops a frame with a 3 ms gap in it. Throws IoError.
  void send(const std::vector<uint8_t>& frame);

  // Reads the port, handing each frame over, until done() or the deadline (or a stop signal);
  // whether done() came true. Throws IoError when the port fails or goes away.
  bool pump(Clock::time_point deadline, const std::function<bool()>& done);
  void wait_until(Clock::time_point deadline) { pump(deadline, [] { return false; }); }

  // Calls send_one() every period until span has passed from now (or a stop signal), the port
  // read between; how many times it was called
  int repeat(Clock::duration period, Clock::duration span, const std::function<void()>& send_one);

  // The next line of the input without its newline, the port read meanwhile; false at the
  // input's end (or a stop signal)
  bool next_line(std::string& line);

  bool heard() const { return heard_; }  // a state or boot frame came
  const telemetry::FrameStream& stream() const { return stream_; }
  const std::string& device() const { return device_; }
  int sent() const { return sent_; }  // frames written

 private:
  void read_port();

  const std::string device_;
  const int input_fd_;
  const FrameHandler on_frame_;
  int port_ = -1;
  telemetry::FrameStream stream_;
  bool heard_ = false;
  int sent_ = 0;
  std::string input_;  // read from input_fd_, not yet handed out as lines
  bool input_ended_ = false;
};

}  // namespace telemetry_cli
}  // namespace wmra
