// The fixed-point kinematics must give bit-identical results on the ATmega2560 (run in
// simavr) and on the host, for the same inputs (test/common/kinematics_vectors.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "kinematics_vectors.h"
#include "sim_run.h"

namespace {

struct StringPut {
  std::string* s;
  void operator()(char c) { s->push_back(c); }
};

TEST(AvrKinematics, BitIdenticalToHost) {
  const std::string avr = wmra::simrun::output_of(std::string(AVR_RUN) + " " + VECTORS_ELF);
  std::string host;
  StringPut put{&host};
  wmra::vectors::emit_all(put);
  host += "END\n";
  ASSERT_EQ(avr.size(), host.size());
  size_t line = 0, mismatches = 0;
  size_t start = 0;
  while (start < host.size()) {
    const size_t end = host.find('\n', start);
    if (host.compare(start, end - start, avr, start, end - start) != 0) {
      if (++mismatches <= 5) ADD_FAILURE() << "case " << line << "\nhost " << host.substr(start, end - start)
                                           << "\navr  " << avr.substr(start, end - start);
    }
    start = end + 1;
    ++line;
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(line, (size_t)wmra::vectors::kCases + 1);
}

// The hand-written AVR arithmetic (products, saturating sums) against int64 and plain
// integer arithmetic on the chip itself (test/avr/kinematics/fixed_products_avr.cpp).
TEST(AvrKinematics, HandWrittenArithmeticMatchesIntegerReference) {
  const std::string out = wmra::simrun::output_of(std::string(AVR_RUN) + " " + PRODUCTS_ELF);
  EXPECT_NE(out.find("mismatches 0\n"), std::string::npos) << out;
}

}  // namespace
