// Runs made without the simulator, for the report's tests: trajectory rows at a rate, with
// joint angles, mode and state given as functions of time.
#pragma once

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "armsim/run.h"

namespace wmra {
namespace test {

using JointsOfTime = std::function<std::array<double, 6>(double)>;
using IntOfTime = std::function<int(double)>;

inline armsim::RunResult synthetic_run(double seconds, double hz, const JointsOfTime& q,
                                       const IntOfTime& mode = [](double) { return -1; },
                                       const IntOfTime& state = [](double) { return -1; }) {
  armsim::RunResult run;
  const long rows = std::lround(seconds * hz);
  for (long i = 0; i <= rows; ++i) {
    const double t = i / hz;
    run.trajectory.push_back(armsim::trajectory_row(t, q(t), mode(t), state(t)));
  }
  run.measurements.sim_time_s = seconds;
  run.completed = true;
  return run;
}

// every joint on a slow sine within its limits
inline std::array<double, 6> waving(double t) {
  return {0.6 * std::sin(0.5 * t), 0.5 + 0.3 * std::sin(0.7 * t), 1.0 + 0.4 * std::sin(0.9 * t),
          -1.2 + 0.5 * std::sin(1.1 * t), 0.3 * std::sin(1.3 * t), 1.5 * std::sin(0.4 * t)};
}

inline armsim::Scenario scenario_until(double end_s) {
  armsim::Scenario s;
  s.end_s = end_s;
  return s;
}

inline std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace test
}  // namespace wmra
