// Frames as lines a person reads (wmra-telemetry session): the arm's status on one line, and
// the boot, info and calibration frames, with the firmware's names for its codes.
#pragma once

#include <string>
#include <vector>

#include "protocol/messages.h"

namespace wmra {
namespace telemetry_cli {

// One line, fields always in this order (the names padded so that lines align):
//   "  12.34 s  running      xy       faults: none  switches: none  q deg: 0.0 45.0 -30.0 0.0 0.0 0.0"
// t is the firmware's clock; faults and switches are comma-separated names.
std::string status_line(const protocol::StateMsg& state);

// The lines of a boot, info or calibration frame ("boot: ...", "info: ...",
// "calibration: ..."); none for any other frame, or one whose payload does not decode.
std::vector<std::string> report_lines(const protocol::Frame& frame);

}  // namespace telemetry_cli
}  // namespace wmra
