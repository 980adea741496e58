// Seed 1's three-level relay (lib/control/relay.h) on the thesis's motor, and the joystick
// button (lib/control/button.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "control/button.h"
#include "control/relay.h"

using namespace wmra::control;

TEST(Relay, ThreeLevelLaw) {
  Relay r;
  ASSERT_EQ(r.configure({38, 0, 20000}), RelayStatus::ok);  // E' = 6 deg at 2260 counts/turn
  for (int e = -200; e <= 200; ++e) {
    const int8_t h = r.level(1000 + e, 1000);
    EXPECT_EQ(h, e >= 38 ? 1 : e <= -38 ? -1 : 0) << e;
  }
  EXPECT_EQ(r.update(1100, 1000), 20000);
  EXPECT_EQ(r.update(900, 1000), -20000);
  EXPECT_EQ(r.update(1000, 1000), 0);
  // E' = 0: the ideal on-off relay, and 0 at zero error
  ASSERT_EQ(r.configure({0, 0, 20000}), RelayStatus::ok);
  EXPECT_EQ(r.level(1, 0), 1);
  EXPECT_EQ(r.level(-1, 0), -1);
  EXPECT_EQ(r.level(0, 0), 0);
  // hysteresis (an extension, default 0): on at E', off below E' - h
  ASSERT_EQ(r.configure({40, 10, 20000}), RelayStatus::ok);
  EXPECT_EQ(r.level(35, 0), 0);
  EXPECT_EQ(r.level(40, 0), 1);
  EXPECT_EQ(r.level(31, 0), 1);
  EXPECT_EQ(r.level(29, 0), 0);
  EXPECT_EQ(r.configure({10, 11, 20000}), RelayStatus::invalid);
  EXPECT_EQ(r.configure({-1, 0, 20000}), RelayStatus::invalid);
  EXPECT_EQ(r.configure({10, 0, 0}), RelayStatus::invalid);
  EXPECT_EQ(r.level(1000, -1000), 1);  // kept the last good configuration
}

// The sampled loop of Miranda's thesis, chapter 4, on G(s) = K_m / (s (tau s + 1)), K_m = 2.4 rad/(V s),
// tau = 0.255 s, with the exact (corrected) sample map, 5 V drive, 2260 counts per turn:
// an on-off relay keeps oscillating about the target; a dead zone that is wide enough for the
// sample rate (E' >~ 2 K_m U T / pi, twice the describing function's bound) stops inside +-E'; faster sampling oscillates less.
namespace {
struct Outcome {
  double late_swing_counts;  // peak-to-peak over the last second
  double final_error_counts;
  bool at_rest;
};
Outcome relay_run(int32_t dead_zone_counts, double fs_hz) {
  const double km = 2.4, tau = 0.255, u = 5.0, counts_per_rad = 2260 / (2 * M_PI), T = 1 / fs_hz;
  const double et = std::exp(-T / tau);
  Relay r;
  EXPECT_EQ(r.configure({dead_zone_counts, 0, 32767}), RelayStatus::ok);
  const int32_t target = 2260;  // one turn (the thesis's 2 pi)
  double c = 0, cd = 0, lo = 1e9, hi = -1e9;
  int8_t last = 0;
  const int n = (int)(6 * fs_hz);
  for (int k = 0; k < n; ++k) {
    const int8_t h = r.level(target, (int32_t)std::floor(c * counts_per_rad));
    const double drive = km * u * h;
    const double c_next = c + tau * (1 - et) * cd + drive * (T - tau * (1 - et));  // (4.23)
    cd = et * cd + drive * (1 - et);                                               // (4.24), corrected
    c = c_next;
    if (k > n - fs_hz) {
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
    last = h;
  }
  return Outcome{(hi - lo) * counts_per_rad, target - c * counts_per_rad, last == 0 && std::abs(cd) < 1e-3};
}
}  // namespace

TEST(Relay, OnOffLimitCyclesAndADeadZoneSettles) {
  const Outcome on_off = relay_run(0, 188);
  const Outcome dz = relay_run((int32_t)(4.5 / 360 * 2260 * 1.2), 188);  // 4.5 deg (a simulation of the corrected map, 5 V, 188 Hz) + 20 %
  const Outcome on_off_fast = relay_run(0, 3000);
  std::printf("188 Hz on-off: swing %.1f counts; dead zone: error %.1f counts, at rest %d; 3 kHz on-off: swing %.1f\n",
              on_off.late_swing_counts, dz.final_error_counts, dz.at_rest, on_off_fast.late_swing_counts);
  EXPECT_GT(on_off.late_swing_counts, 10);
  EXPECT_TRUE(dz.at_rest);
  EXPECT_LE(std::abs(dz.final_error_counts), 4.5 / 360 * 2260 * 1.2 + 1);
  EXPECT_LT(dz.late_swing_counts, 0.1);  // coasting to rest
  EXPECT_LT(on_off_fast.late_swing_counts, on_off.late_swing_counts / 4);
}

namespace {
struct Trace {
  Button b;
  uint16_t t = 0;
  int presses = 0, longs = 0;
  explicit Trace(uint16_t start = 0) : t(start) { EXPECT_TRUE(b.configure({20, 1000})); }
  void hold(bool level, int ms) {
    for (int i = 0; i < ms; ++i) {
      const ButtonEvent e = b.update(level, t++);
      presses += e == ButtonEvent::press;
      longs += e == ButtonEvent::long_press;
    }
  }
};
}  // namespace

TEST(Button, DebouncedShortPress) {
  Trace tr;
  tr.hold(false, 50);
  for (int i = 0; i < 5; ++i) {  // contact bounce: 3 ms on, 2 ms off
    tr.hold(true, 3);
    tr.hold(false, 2);
  }
  tr.hold(true, 200);
  EXPECT_TRUE(tr.b.down());
  EXPECT_EQ(tr.presses, 0);  // reported on release
  for (int i = 0; i < 4; ++i) {
    tr.hold(false, 2);
    tr.hold(true, 2);
  }
  tr.hold(false, 100);
  EXPECT_EQ(tr.presses, 1);
  EXPECT_EQ(tr.longs, 0);
  EXPECT_FALSE(tr.b.down());
}

TEST(Button, GlitchesShorterThanTheDebounceAreIgnored) {
  Trace tr;
  for (int i = 0; i < 100; ++i) {
    tr.hold(true, 19);
    tr.hold(false, 30);
  }
  EXPECT_EQ(tr.presses, 0);
  EXPECT_FALSE(tr.b.down());
}

TEST(Button, LongPressOnceAndNoShortPressAfterIt) {
  Trace tr;
  tr.hold(true, 999);  // a long press is timed from the start of the (confirmed) press
  EXPECT_EQ(tr.longs, 0);
  tr.hold(true, 2);
  EXPECT_EQ(tr.longs, 1);
  tr.hold(true, 5000);
  EXPECT_EQ(tr.longs, 1);
  tr.hold(false, 100);
  EXPECT_EQ(tr.presses, 0);
  // two quick presses, 150 ms apart (seed 2's 500 ms lockout would lose the second)
  tr.hold(true, 60);
  tr.hold(false, 90);
  tr.hold(true, 60);
  tr.hold(false, 90);
  EXPECT_EQ(tr.presses, 2);
}

TEST(Button, MillisecondCounterWrap) {
  Trace tr(65500);  // wraps at 65536 during the press
  tr.hold(false, 10);
  tr.hold(true, 1100);
  EXPECT_EQ(tr.longs, 1);
  tr.hold(false, 30);
  tr.hold(true, 100);
  tr.hold(false, 30);
  EXPECT_EQ(tr.presses, 1);
  Button b;
  EXPECT_FALSE(b.configure({0, 1000}));
  EXPECT_FALSE(b.configure({50, 40}));
  EXPECT_EQ(b.update(true, 0), ButtonEvent::none);
}
