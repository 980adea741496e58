#include "armsim/live_console.h"

#include <cerrno>
#include <cstdio>

#include <fcntl.h>
#include <unistd.h>

#include "plant/arm_plant_config.h"

namespace wmra {
namespace armsim {

LiveConsole::LiveConsole(LiveHook& inner, int fd) : inner_(inner), fd_(fd) {
  const int flags = fcntl(fd_, F_GETFL);
  if (flags < 0 || fcntl(fd_, F_SETFL, flags | O_NONBLOCK) != 0) open_ = false;
}

bool LiveConsole::after_slice(sim::ArmSimulator& sim) {
  if (button_up_at_s_ >= 0 && sim.time_s() >= button_up_at_s_) {
    sim.set_button(false);
    button_up_at_s_ = -1;
  }
  while (open_) {
    char buf[256];
    const ssize_t n = read(fd_, buf, sizeof buf);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) break;
    if (n <= 0) {  // the end of stdin (or an error): the console is done, the run goes on
      open_ = false;
      break;
    }
    pending_.append(buf, (size_t)n);
    for (size_t end; (end = pending_.find('\n')) != std::string::npos;) {
      take_line(sim, pending_.substr(0, end));
      pending_.erase(0, end + 1);
    }
  }
  return inner_.after_slice(sim);
}

// The line as a scenario's event at time 0 (the scenario's parser checks its words)
void LiveConsole::take_line(sim::ArmSimulator& sim, const std::string& line) {
  const size_t first = line.find_first_not_of(" \t\r");
  if (first == std::string::npos || line[first] == '#') return;
  Event e;
  try {
    const Scenario one = parse_scenario("0 " + line.substr(first) + "\n0 end\n");
    if (one.events.size() != 1) throw ScenarioError(1, "one event a line, without its time");
    e = one.events[0];
  } catch (const ScenarioError& error) {
    const std::string what = error.what();
    std::fprintf(stderr, "armsim: stdin: '%s': %s\n", line.c_str(), what.substr(what.find(':') + 2).c_str());
    return;
  }
  apply_event(sim, e);
  if (e.kind == Event::Kind::button_press) button_up_at_s_ = sim.time_s() + plant::kButtonPressS;
  ++applied_;
  std::fprintf(stderr, "armsim: %.3f s: %s\n", sim.time_s(), line.substr(first).c_str());
}

}  // namespace armsim
}  // namespace wmra
