// Host-side helpers for the tests that run AVR images in simavr through avr-run: the console
// output of a run, and the region timings it writes (--timings FILE.json).
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace wmra {
namespace simrun {

// stdout of a command; a non-zero exit status fails the calling test
inline std::string output_of(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  EXPECT_EQ(pclose(p), 0) << command;
  return out;
}

// Runs an image with --timings json_path and returns the JSON text ("" on failure)
inline std::string timings_of(const std::string& avr_run, const std::string& elf, const std::string& json_path) {
  const std::string command = avr_run + " " + elf + " --timings " + json_path + " > /dev/null";
  if (std::system(command.c_str()) != 0) {
    ADD_FAILURE() << command;
    return "";
  }
  std::ifstream in(json_path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Timing {
  double mean = -1;
  double max = -1;
};

// One region of avr-run's timings JSON; mean and max stay -1 when it is missing
inline Timing timing(const std::string& json, const std::string& name) {
  Timing t;
  const size_t at = json.find("\"" + name + "\"");
  if (at != std::string::npos) std::sscanf(json.c_str() + at + name.size() + 2, ": {\"cycles\": %lf, \"max\": %lf", &t.mean, &t.max);
  return t;
}

}  // namespace simrun
}  // namespace wmra
