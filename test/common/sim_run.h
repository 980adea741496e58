// Host-side helpers for the tests that run AVR images in simavr through avr-run: the console
// output of a run, and the region timings it writes (--timings FILE.json); and for the tests
// of command-line tools, a command's exit status and output.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

namespace wmra {
namespace simrun {

struct CommandRun {
  int status;       // the exit status; -1 when it could not start or did not exit
  std::string out;  // stdout
};
inline CommandRun run_command(const std::string& command) {
  CommandRun r{-1, ""};
  FILE* p = popen(command.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int s = pclose(p);
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  return r;
}

// stdout of a command; a non-zero exit status fails the calling test
inline std::string output_of(const std::string& command) {
  const CommandRun r = run_command(command);
  EXPECT_EQ(r.status, 0) << command;
  return r.out;
}

// Runs an image with --timings and returns the JSON text ("" on failure), left at json_path.
// ctest runs each test of a suite in its own process, in parallel: each writes its own file and
// renames it into place, so that none reads another's half-written one.
inline std::string timings_of(const std::string& avr_run, const std::string& elf, const std::string& json_path) {
  const std::string mine = json_path + "." + std::to_string(getpid());
  const std::string command = avr_run + " " + elf + " --timings " + mine + " > /dev/null";
  if (std::system(command.c_str()) != 0) {
    ADD_FAILURE() << command;
    return "";
  }
  std::stringstream ss;
  {
    std::ifstream in(mine);
    ss << in.rdbuf();
  }
  std::rename(mine.c_str(), json_path.c_str());
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

struct Budget {
  const char* name;
  double max_cycles;
};
// Prints each region's mean and max cycles (and records the mean in the test's XML); fails
// the test where a region is missing or its max is over its budget
inline void expect_budgets(const std::string& json, std::initializer_list<Budget> budgets) {
  for (const Budget& b : budgets) {
    const Timing t = timing(json, b.name);
    EXPECT_GT(t.mean, 0) << b.name;
    std::printf("%-24s mean %7.1f  max %6.0f cycles\n", b.name, t.mean, t.max);
    ::testing::Test::RecordProperty(b.name, std::to_string(t.mean));
    EXPECT_LE(t.max, b.max_cycles) << b.name;
  }
}

}  // namespace simrun
}  // namespace wmra
