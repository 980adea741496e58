// wmra-telemetry session DEVICE [--json]: the port opened once and kept open, commands read
// from a file descriptor (stdin) one a line in `encode`'s words, each sent and its reply shown,
// and what the firmware sends shown as it comes (docs/telemetry.md, "wmra-telemetry").
#pragma once

#include <string>

namespace wmra {
namespace telemetry_cli {

struct SessionOptions {
  std::string device;
  bool json = false;  // every frame as decode's JSON line, instead of the lines a person reads
  int input_fd = 0;   // the commands, one a line
};

// Runs the session until the end of the input (once the last command has its reply, or 1 s
// has passed) or SIGINT/SIGTERM, then writes a summary line on stderr. Returns 0, or 2 when a
// line could not be used (the others were still sent). Throws IoError when the port cannot be
// opened, or fails or closes during the session.
int run_session(const SessionOptions& options);

}  // namespace telemetry_cli
}  // namespace wmra
