// The control blocks on the ATmega2560 (simavr): bit-identical to the host on the scenarios of
// test/common/control_vectors.h, and their per-call cycle cost (printed, loosely gated so that
// a regression shows).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "control_vectors.h"

namespace {

std::string run(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  EXPECT_EQ(pclose(p), 0) << command;
  return out;
}

struct StringPut {
  std::string* s;
  void operator()(char c) { s->push_back(c); }
};

struct Timing {
  double mean = -1;
  double max = -1;
};

}  // namespace

TEST(AvrControl, BitIdenticalToHost) {
  const std::string avr = run(std::string(AVR_RUN) + " " + CONTROL_VECTORS_ELF);
  std::string host;
  StringPut put{&host};
  wmra::control_vectors::emit_all(put);
  EXPECT_EQ(avr, host);
  EXPECT_GT(host.size(), 500u);
}

class AvrControlCycles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string json = std::string(BENCH_OUT) + "/control_bench.json";
    const std::string command = std::string(AVR_RUN) + " " + CONTROL_BENCH_ELF + " --timings " + json + " > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(json);
    std::stringstream ss;
    ss << in.rdbuf();
    text_ = ss.str();
  }
  static Timing get(const std::string& name) {
    Timing t;
    const size_t at = text_.find("\"" + name + "\"");
    if (at != std::string::npos) std::sscanf(text_.c_str() + at + name.size() + 2, ": {\"cycles\": %lf, \"max\": %lf", &t.mean, &t.max);
    return t;
  }
  static std::string text_;
};
std::string AvrControlCycles::text_;

// Budgets: the measured figures (README) with headroom, so that a regression fails
TEST_F(AvrControlCycles, PerCallCosts) {
  struct Budget {
    const char* name;
    double max_cycles;
  };
  const Budget budgets[] = {
      {"ramp_next_cruise", 100},       {"ramp_next_accelerating", 1500}, {"ramp_next_braking", 1500},
      {"ramp_set_speed", 500},         {"seed0_update", 500},            {"pid_update", 1200},
      {"relay_update", 250},           {"plausibility_update", 250},     {"joystick_update", 5000},
      {"button_update", 200},
  };
  for (const Budget& b : budgets) {
    const Timing t = get(b.name);
    ASSERT_GT(t.mean, 0) << b.name;
    std::printf("%-24s mean %7.1f  max %6.0f cycles\n", b.name, t.mean, t.max);
    RecordProperty(b.name, std::to_string(t.mean));
    EXPECT_LE(t.max, b.max_cycles) << b.name;
  }
}
