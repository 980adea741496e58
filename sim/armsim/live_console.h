// armsim --live --stdin: the person's hands on the virtual arm from the keyboard. Events in the
// scenario's words without a time, one a line on stdin (joystick X Y, button press|down|up,
// estop down|up, pot_fault J open|short|ok, joystick_fault open|ok, serial HEX), apply as they
// arrive; a `button press` lets the button go kButtonPressS later, as in a scenario. A line that
// is no event gets a message on stderr and changes nothing; the end of stdin ends nothing but the
// console. It wraps the hook that paces the run (LivePty), so both see every slice.
#pragma once

#include <string>

#include "armsim/run.h"

namespace wmra {
namespace armsim {

class LiveConsole : public LiveHook {
 public:
  LiveConsole(LiveHook& inner, int fd);  // fd: stdin's, read without blocking
  double slice_s() const override { return inner_.slice_s(); }
  bool after_slice(sim::ArmSimulator& sim) override;
  int events_applied() const { return applied_; }

 private:
  void take_line(sim::ArmSimulator& sim, const std::string& line);

  LiveHook& inner_;
  int fd_;
  bool open_ = true;
  std::string pending_;        // a line not yet ended
  double button_up_at_s_ = -1;  // a press's release, in simulated time (-1: none due)
  int applied_ = 0;
};

}  // namespace armsim
}  // namespace wmra
