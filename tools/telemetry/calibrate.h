// wmra-telemetry calibrate DEVICE J: a DC joint's pot calibrated with a person, one prompt at
// a time: the joint jogged to two angles they measure, the readings at its limits extrapolated
// from those two points, and stored on their yes (docs/telemetry.md, "wmra-telemetry").
#pragma once

#include <string>

namespace wmra {
namespace telemetry_cli {

struct CalibrateOptions {
  std::string device;
  int joint = 0;     // 2, 3 or 4
  int input_fd = 0;  // the person's answers, one a line
};

// Runs the calibration. Returns 0 stored; 1 not stored (the person said no or quit, the input
// ended, a signal, the arm not waiting before homing, the firmware refused it); 2 when a line
// of the input could not be used, whatever else happened (the output says whether it stored).
// Throws IoError when the port cannot be opened, fails, goes away or stays silent.
int run_calibrate(const CalibrateOptions& options);

}  // namespace telemetry_cli
}  // namespace wmra
