// The firmware's serial link from the host: a serial port (or a pseudo-terminal, as armsim
// --live offers) opened raw at 115200 8N1.
#pragma once

#include <string>

namespace wmra {
namespace telemetry_cli {

// A port that cannot be opened, read or written; the message names it and says why
struct IoError {
  std::string message;
};

// Opens DEVICE read-write at 115200 8N1, raw (no echo, no line editing, no flow control), and
// drops whatever the port held before. A real Mega resets when its port is opened (DTR).
// Throws IoError when DEVICE cannot be opened or is not a serial port.
int open_serial(const std::string& device);

}  // namespace telemetry_cli
}  // namespace wmra
