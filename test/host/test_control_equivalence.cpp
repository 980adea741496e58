// The control blocks' faster sample functions against their previous versions
// (control_reference.h), bit for bit: 10^6 random samples each, seeded, with random
// configurations, inputs from the everyday range to the int16 extremes (positions are 16-bit:
// pot units), and overran calls.
#include <gtest/gtest.h>

#include <random>

#include "control/pid.h"
#include "control_reference.h"

using namespace wmra;
using namespace wmra::control;

namespace {

struct Random {
  std::mt19937 rng;
  explicit Random(uint32_t seed) : rng(seed) {}
  int32_t in(int32_t lo, int32_t hi) { return std::uniform_int_distribution<int32_t>(lo, hi)(rng); }
  bool one_in(int n) { return in(0, n - 1) == 0; }
  // mostly small, sometimes a saturating value, rarely an extreme
  int16_t spread(int16_t small) {
    const int k = in(0, 99);
    if (k < 80) return (int16_t)in(-small, small);
    if (k < 97) return (int16_t)in(-16384, 16383);
    return (int16_t)in(INT16_MIN, INT16_MAX);
  }
  // a position's random step, kept within 16 bits
  int16_t walk(int16_t from, int32_t step) {
    const int32_t to = (int32_t)from + in(-step, step);
    return (int16_t)(to < INT16_MIN ? INT16_MIN : to > INT16_MAX ? INT16_MAX : to);
  }
  uint8_t samples() {
    const int k = in(0, 99);
    return (uint8_t)(k < 70 ? 1 : k < 90 ? 2 : k < 97 ? in(3, 8) : in(1, 255));
  }
};

// Half of the configurations are tiny (gains, limits, inputs of a few LSB), so that the sums
// land exactly on the limits' edges, where a rounding or an off-by-one would show.
PidConfig random_pid_config(Random& r, bool tiny) {
  PidConfig c;
  if (tiny) {
    c.gains = PidGains{(int16_t)r.in(0, 4), (int16_t)r.in(0, 300), (int16_t)r.in(0, 4)};
    c.out_max_q15 = (int16_t)r.in(1, 12);
    c.rate_q15 = (int16_t)r.in(1, 4);
    c.min_duty_q15 = (int16_t)r.in(0, c.out_max_q15 - 1);
    c.zero_band_q15 = (int16_t)r.in(0, c.out_max_q15);
    return c;
  }
  do {
    c.gains = PidGains{(int16_t)r.in(0, 32767), (int16_t)r.in(0, r.one_in(4) ? 32767 : 400),
                       (int16_t)(r.one_in(8) ? 0 : r.in(0, 32767))};
    c.out_max_q15 = (int16_t)(r.one_in(2) ? 32767 : r.in(1, 32767));
    c.rate_q15 = (int16_t)r.in(1, r.one_in(3) ? 32767 : 2000);
    c.min_duty_q15 = (int16_t)r.in(0, c.out_max_q15 - 1);
    c.zero_band_q15 = (int16_t)r.in(0, r.one_in(4) ? c.out_max_q15 : 500);
  } while (pid_check(c) != PidStatus::ok);
  return c;
}

}  // namespace

TEST(ControlEquivalence, PidUpdateIsBitIdenticalToTheQ19Version) {
  Random r(20240611u);
  Pid pid;
  reference::Pid ref;
  int64_t compared = 0, integrated = 0, held = 0, limited = 0, inside = 0;
  int16_t measurement = 0, setpoint = 0;
  while (compared < 1000000) {
    const bool tiny = r.one_in(2);
    const PidConfig c = random_pid_config(r, tiny);
    const int32_t walk = tiny ? 6 : 300;
    ASSERT_EQ(pid.configure(c), PidStatus::ok);
    ASSERT_EQ(ref.configure(c), PidStatus::ok);
    for (int k = 0; k < 500; ++k, ++compared) {
      if (r.one_in(200)) {  // a bumpless restart or a preset, as the servo does
        const int16_t applied = (int16_t)(tiny ? r.in(-15, 15) : r.in(-32768, 32767));
        pid.start(setpoint, measurement, applied);
        ref.start(setpoint, measurement, applied);
        if (r.one_in(2)) {
          pid.preset_integral(applied);
          ref.preset_integral(applied);
        }
      }
      if (r.one_in(50)) setpoint = tiny ? (int16_t)r.in(-100, 100) : r.spread(20000);
      setpoint = r.walk(setpoint, walk);
      // the joint mostly follows within a few counts, sometimes lags or jumps far
      measurement = r.one_in(100) ? (tiny ? (int16_t)r.in(-100, 100) : r.spread(20000))
                    : r.one_in(3) ? r.walk(measurement, walk)
                                  : r.walk(setpoint, walk / 2);
      const int16_t ff = (int16_t)(tiny ? r.in(-15, 15) : r.one_in(10) ? r.in(-32768, 32767) : r.in(-3000, 3000));
      const uint8_t n = r.samples();
      const int32_t before = ref.integral_q23();
      const int16_t duty = pid.update(setpoint, measurement, ff, n);
      const int16_t duty_ref = ref.update(setpoint, measurement, ff, n);
      ASSERT_EQ(duty, duty_ref) << "sample " << compared;
      ASSERT_EQ(pid.effort_q15(), ref.effort_q15()) << "sample " << compared;
      ASSERT_EQ(pid.integral_q23(), ref.integral_q23()) << "sample " << compared;
      const bool at_limit = ref.effort_q15() == c.out_max_q15 || ref.effort_q15() == -c.out_max_q15;
      integrated += ref.integral_q23() != before;
      held += ref.integral_q23() == before && at_limit;
      limited += at_limit;
      inside += !at_limit && ref.effort_q15() != 0;
    }
  }
  // the random walk reached the branches that matter: integrating, held at a limit, inside
  std::printf("PID: %lld samples bit-identical; integrating %lld, held at +-out_max %lld, at +-out_max %lld, inside %lld\n",
              (long long)compared, (long long)integrated, (long long)held, (long long)limited, (long long)inside);
  EXPECT_GT(integrated, compared / 10);
  EXPECT_GT(held, compared / 100);
  EXPECT_GT(inside, compared / 10);
}
