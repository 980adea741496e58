// The serial protocol on the ATmega2560 (simavr): the same frames, parser results and decoded
// fields as on the host (test/common/protocol_vectors.h), and the cycle cost of the calls the
// firmware makes (printed, loosely gated so that a regression shows).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "protocol_vectors.h"
#include "sim_run.h"

namespace {

struct StringPut {
  std::string* s;
  void operator()(char c) { s->push_back(c); }
};

class AvrProtocol : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string timings = std::string(TIMINGS_OUT) + "/protocol_timings.json";
    const std::string out =
        wmra::simrun::output_of(std::string(AVR_RUN) + " " + PROTOCOL_VECTORS_ELF + " --timings " + timings);
    // the region names ("@ID NAME") are for avr-run, not part of the vectors
    std::istringstream lines(out);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind('@', 0) != 0) avr_ += line + "\n";
    }
    std::ifstream in(timings);
    std::stringstream ss;
    ss << in.rdbuf();
    json_ = ss.str();
  }
  static std::string avr_, json_;
};
std::string AvrProtocol::avr_, AvrProtocol::json_;

}  // namespace

TEST_F(AvrProtocol, SameBytesAsTheHost) {
  std::string host;
  StringPut put{&host};
  wmra::protocol_vectors::emit_all(put);
  EXPECT_EQ(avr_, host);
  // what the stream holds, worked out by hand: the stop and the rearm frames; CRC errors for
  // the bad CRC and the lost byte, framing errors for version 1 and length 65; skipped 00, the
  // two stray syncs, ff, and the failed frames' bytes after their syncs, looked at again (1, 7,
  // 4 and 6 of them): 22
  EXPECT_NE(host.find("C29b1\n"), std::string::npos);
  EXPECT_NE(host.find("\nP1000000 \nP110a000 \nP000200020016\n"), std::string::npos) << host;
  EXPECT_NE(host.find("\nD4\n"), std::string::npos);  // every message came back
}

TEST_F(AvrProtocol, CyclesPerCall) {
  wmra::simrun::expect_budgets(json_, {{"write_state_frame", 3000},
                                       {"parse_state_frame", 8000},
                                       {"decode_state", 1000},
                                       {"check_command", 200}});
}
