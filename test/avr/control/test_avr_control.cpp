// The control blocks on the ATmega2560 (simavr): bit-identical to the host on the scenarios of
// test/common/control_vectors.h, and their per-call cycle cost (printed, loosely gated so that
// a regression shows).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "control_vectors.h"
#include "sim_run.h"

using wmra::simrun::Timing;

namespace {
struct StringPut {
  std::string* s;
  void operator()(char c) { s->push_back(c); }
};
}  // namespace

TEST(AvrControl, BitIdenticalToHost) {
  const std::string avr = wmra::simrun::output_of(std::string(AVR_RUN) + " " + CONTROL_VECTORS_ELF);
  std::string host;
  StringPut put{&host};
  wmra::control_vectors::emit_all(put);
  EXPECT_EQ(avr, host);
  EXPECT_GT(host.size(), 500u);
}

class AvrControlCycles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    json_ = wmra::simrun::timings_of(AVR_RUN, CONTROL_BENCH_ELF, std::string(BENCH_OUT) + "/control_bench.json");
  }
  static Timing get(const std::string& name) { return wmra::simrun::timing(json_, name); }
  static std::string json_;
};
std::string AvrControlCycles::json_;

// Budgets: the measured figures (README) with headroom, so that a regression fails
TEST_F(AvrControlCycles, PerCallCosts) {
  wmra::simrun::expect_budgets(json_, {
      {"ramp_next_cruise", 100},       {"ramp_next_accelerating", 2000}, {"ramp_next_braking", 2000},
      {"ramp_set_speed", 500},         {"seed0_update", 500},            {"pid_update", 1200},
      {"relay_update", 250},           {"plausibility_update", 250},     {"joystick_update", 5000},
      {"button_update", 200},
  });
}
