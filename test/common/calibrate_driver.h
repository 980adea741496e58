// wmra-telemetry calibrate driven as a technician drives it: each of its prompts answered in
// turn, "=" standing for the angle the tool shows now (on the virtual arm the pot lies on the
// configuration's line, so that angle is the true one within a count), the input ended after the
// last answer.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <string>
#include <vector>

#include "child_process.h"

namespace wmra {
namespace test {

struct CalibrateRun {
  int status = -1;  // the tool's exit status; -1: it did not end within the time
  std::string out, err;
};

inline CalibrateRun run_calibrate(const std::string& telemetry_bin, const std::string& port, int joint,
                                  const std::vector<std::string>& answers, const std::string& out_base, double max_s = 60) {
  signal(SIGPIPE, SIG_IGN);  // a tool that ended early: a failed write, not the test's end
  CalibrateRun run;
  int in[2];
  if (pipe2(in, O_CLOEXEC) != 0) return run;  // the tool holds no write end: its input can end
  ChildProcess tool({telemetry_bin, "calibrate", port, std::to_string(joint)}, out_base, "", in[0]);
  close(in[0]);
  const std::regex shown("J" + std::to_string(joint) + " reads \\d+ \\(counts x 16\\), the firmware's angle (-?[0-9.]+) deg\n");
  size_t answered = 0;
  const auto start = std::chrono::steady_clock::now();
  while (run.status < 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < max_s) {
    run.status = tool.exit_status(false);
    usleep(20000);
    const std::string out = tool.out();
    int prompts = 0;
    for (const char* p : {"\npoint 1: + / - ", "\npoint 2 (at least ", "\nstore? (yes/no)\n"}) {
      for (size_t at = out.find(p); at != std::string::npos; at = out.find(p, at + 1)) ++prompts;
    }
    if (answered < answers.size() && prompts > (int)answered) {
      std::string answer = answers[answered++];
      if (answer == "=") {
        std::smatch last;
        for (auto it = std::sregex_iterator(out.begin(), out.end(), shown); it != std::sregex_iterator(); ++it) last = *it;
        answer = last[1];
      }
      answer += "\n";
      if (write(in[1], answer.data(), answer.size()) != (ssize_t)answer.size()) break;
      if (answered == answers.size()) {
        close(in[1]);
        in[1] = -1;
      }
    }
  }
  if (in[1] >= 0) close(in[1]);
  run.out = tool.out();
  run.err = tool.err();
  return run;
}

}  // namespace test
}  // namespace wmra
