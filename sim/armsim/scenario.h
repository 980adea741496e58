// The scenario format: one event per line, '#' comments, times in seconds of
// simulated time.
//
//   init Q1 Q2 Q3 Q4 Q5 Q6     optional, the first line: true joint angles at power-up (rad)
//   T joystick X Y             stick deflection, X and Y in [-1, 1]
//   T button press|down|up     the joystick button (press = down, then up 150 ms later)
//   T estop down|up            the safety button
//   T pot_fault J open|short|ok   potentiometer fault of joint J = 2, 3 or 4
//   T joystick_fault open|ok   the joystick unplugged, or back
//   T serial HEX               bytes into the firmware's UART (an even number of hex digits)
//   T end                      the last line: the run ends at T
// Times never go back. Anything else is an error that names its line.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace wmra {
namespace armsim {

struct Event {
  enum class Kind { joystick, button_press, button_down, button_up, estop_down, estop_up, pot_fault, joystick_fault, serial };
  double t_s = 0;
  Kind kind = Kind::joystick;
  double x = 0, y = 0;          // joystick
  int joint = 0;                // pot_fault: 2..4
  int fault = 0;                // pot_fault: 0 ok, 1 open, 2 short; joystick_fault: 0 ok, 1 open
  std::vector<uint8_t> bytes;   // serial
  int line = 0;
};

struct Scenario {
  bool has_init = false;
  std::array<double, 6> init_q{};
  std::vector<Event> events;  // in time order
  double end_s = 0;
};

class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(int line, const std::string& message)
      : std::runtime_error("line " + std::to_string(line) + ": " + message), line_(line) {}
  int line() const { return line_; }

 private:
  int line_;
};

Scenario parse_scenario(const std::string& text);       // throws ScenarioError
Scenario load_scenario(const std::string& path);        // throws ScenarioError, std::runtime_error

}  // namespace armsim
}  // namespace wmra
