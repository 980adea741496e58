// Joystick shaping (lib/control/joystick.h): centre calibration, dead zone, square to disc,
// response curve, rate limit, stuck-at-rail detection and the neutral interlock.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "control/joystick.h"

using namespace wmra::control;

namespace {

JoystickConfig config() {
  return JoystickConfig{1023, 8, 50, 16, 24, 100,
                        655,    // 2 % dead zone
                        9830,   // expo 0.3
                        33,     // rise: full scale in ~1 s at 1 kHz
                        164,    // fall: in 0.2 s
                        100};   // 0.1 s neutral to arm
}

// configures j, calibrates it at centre (cx, cy) and arms it
void calibrate_and_arm(Joystick& j, uint16_t cx, uint16_t cy, const JoystickConfig& c) {
  EXPECT_TRUE(j.configure(c));
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> noise(-3, 3);
  for (int i = 0; i < 16; ++i) j.update((uint16_t)(cx + noise(rng)), (uint16_t)(cy + noise(rng)));
  for (int i = 0; i < 100; ++i) j.update(cx, cy);
  EXPECT_EQ(j.update(cx, cy).status, 0);
}

// a calibrated, armed joystick with centre (cx, cy)
Joystick ready(uint16_t cx = 515, uint16_t cy = 505, const JoystickConfig& c = config()) {
  Joystick j;
  calibrate_and_arm(j, cx, cy, c);
  return j;
}

JoystickOutput hold(Joystick& j, uint16_t x, uint16_t y, int samples) {
  JoystickOutput o{};
  for (int i = 0; i < samples; ++i) o = j.update(x, y);
  return o;
}

}  // namespace

TEST(Joystick, CentreCalibration) {
  Joystick j = ready(515, 505);
  EXPECT_NEAR(j.centre(0), 515, 1);
  EXPECT_NEAR(j.centre(1), 505, 1);
  // a stick that moves while calibrating is refused until it is still
  Joystick moving;
  ASSERT_TRUE(moving.configure(config()));
  for (int i = 0; i < 160; ++i) {
    const JoystickOutput o = moving.update((uint16_t)(480 + (i % 16) * 5), 512);
    EXPECT_TRUE(o.status & kJoystickCalibrating);
  }
  // deflected at power-up: refused
  Joystick deflected;
  ASSERT_TRUE(deflected.configure(config()));
  const JoystickOutput o = hold(deflected, 700, 512, 200);
  EXPECT_TRUE(o.status & kJoystickCalibrating);
  EXPECT_EQ(o.x_q15, 0);
  // and refuses garbage configuration
  JoystickConfig bad = config();
  bad.rise_q15 = 0;
  EXPECT_FALSE(Joystick().configure(bad));
}

// With a centre stored from a released stick, a power-up centre must agree with it within
// stored_tolerance: a hand resting on the stick 10 % off centre (inside the 100 counts of
// mid-scale that a new board accepts) is refused, calibration retried, and once the stick is
// released the released centre is taken. Released there, the stick reads neutral.
TEST(Joystick, StoredCentreRefusesAStickHeldAtPowerUp) {
  JoystickConfig c = config();
  c.stored_tolerance = 5;
  const uint16_t rest_x = 520, rest_y = 497;  // the stick's released centre, stored
  const uint16_t held_x = rest_x - 50;        // held 10 % of its 500-count side off
  // without a stored centre (a new board) the held stick becomes the centre, as before:
  // released, it reads 10 % (8 % past the dead zone, 5 % through the curve) and drives
  Joystick fresh;
  ASSERT_TRUE(fresh.configure(c));
  EXPECT_EQ(hold(fresh, held_x, rest_y, 200).status & kJoystickCalibrating, 0);
  EXPECT_GT(hold(fresh, rest_x, rest_y, 2000).x_q15, 1000);

  Joystick j;
  ASSERT_TRUE(j.configure(c));
  j.set_stored_centre(rest_x, rest_y);
  std::mt19937 rng(2);
  std::uniform_int_distribution<int> noise(-2, 2);
  JoystickOutput o{};
  for (int i = 0; i < 2000; ++i) o = j.update((uint16_t)(held_x + noise(rng)), (uint16_t)(rest_y + noise(rng)));
  EXPECT_TRUE(o.status & kJoystickCalibrating) << "held off-centre: refused for as long as it is held";
  EXPECT_EQ(o.x_q15, 0);
  // just past the tolerance, still refused (whole rounds of 16 samples)
  EXPECT_TRUE(hold(j, rest_x + 6, rest_y, 192).status & kJoystickCalibrating);
  EXPECT_TRUE(hold(j, rest_x, rest_y - 6, 192).status & kJoystickCalibrating);
  for (int i = 0; i < 16; ++i) o = j.update((uint16_t)(rest_x + noise(rng)), (uint16_t)(rest_y + noise(rng)));
  EXPECT_EQ(o.status & kJoystickCalibrating, 0) << "released: calibrated";
  EXPECT_NEAR(j.centre(0), rest_x, 1);
  EXPECT_NEAR(j.centre(1), rest_y, 1);
  for (int i = 0; i < 2000; ++i) {
    o = j.update((uint16_t)(rest_x + noise(rng)), (uint16_t)(rest_y + noise(rng)));
    ASSERT_EQ(o.x_q15, 0);
    ASSERT_EQ(o.y_q15, 0);
  }
  EXPECT_EQ(o.status, 0) << "armed";
  // a centre within the tolerance of the stored one is accepted, and the stick at the stored
  // centre (its rest) is still inside the 2 % dead zone (10 counts)
  Joystick near;
  ASSERT_TRUE(near.configure(c));
  near.set_stored_centre(rest_x, rest_y);
  EXPECT_EQ(hold(near, rest_x + 5, rest_y - 5, 16).status & kJoystickCalibrating, 0);
  const JoystickOutput at_rest = hold(near, rest_x, rest_y, 2000);
  EXPECT_EQ(at_rest.status, 0);
  EXPECT_EQ(at_rest.x_q15, 0);
  EXPECT_EQ(at_rest.y_q15, 0);
  // forgotten (0 0): mid-scale within centre_tolerance again
  near.set_stored_centre(0, 0);
  near.recalibrate();
  EXPECT_EQ(hold(near, held_x, rest_y, 16).status & kJoystickCalibrating, 0);
  // a tolerance wider than the nominal one is a configuration error
  c.stored_tolerance = (uint16_t)(c.centre_tolerance + 1);
  EXPECT_FALSE(Joystick().configure(c));
}

TEST(Joystick, NoOutputUntilNeutral) {
  Joystick j;
  ASSERT_TRUE(j.configure(config()));
  hold(j, 512, 512, 16);  // calibrated
  // pushed right away: nothing comes out
  JoystickOutput o = hold(j, 1000, 512, 500);
  EXPECT_EQ(o.x_q15, 0);
  EXPECT_TRUE(o.status & kJoystickNotArmed);
  hold(j, 512, 512, 99);
  EXPECT_TRUE(j.update(512, 512).status == 0);  // 100 neutral samples
  o = hold(j, 1000, 512, 2000);
  EXPECT_GT(o.x_q15, 30000);
}

TEST(Joystick, DeadZoneIsContinuous) {
  Joystick j = ready(512, 512);
  // 2 % of a ~500-count side is 10 counts
  const uint16_t cx = j.centre(0), cy = j.centre(1);
  EXPECT_EQ(hold(j, cx + 10, cy, 2000).x_q15, 0);
  EXPECT_EQ(hold(j, cx - 10, cy, 2000).x_q15, 0);
  const int16_t just_out = hold(j, cx + 11, cy, 2000).x_q15;
  EXPECT_GT(just_out, 0);
  EXPECT_LT(just_out, 100);  // no jump at the edge: about 1 count past it
  EXPECT_EQ(hold(j, cx + 11, cy, 1).y_q15, 0);
  EXPECT_EQ(hold(j, cx + 300, cy + 8, 2000).y_q15, 0);  // per axis: no drift in y
}

TEST(Joystick, FullDeflectionEachSideIsOne) {
  Joystick j = ready(540, 490);  // off-centre: the two sides have different spans
  EXPECT_NEAR(hold(j, 1014, 490, 3000).x_q15, 32767, 40);
  EXPECT_NEAR(hold(j, 9, 490, 3000).x_q15, -32767, 40);
  EXPECT_NEAR(hold(j, 540, 1014, 3000).y_q15, 32767, 40);
  EXPECT_NEAR(hold(j, 540, 9, 3000).y_q15, -32767, 40);
}

// A stick whose travel ends before the rails (the KY-023 through the board's amplifiers: +-2.25 V
// around 2.5 V) is full at full_deflection counts from the centre, and saturates beyond
TEST(Joystick, FullDeflectionBeforeTheRails) {
  JoystickConfig c = config();
  c.full_deflection = 440;
  Joystick j = ready(520, 500, c);
  EXPECT_NEAR(hold(j, 520 + 440, 500, 3000).x_q15, 32767, 200);  // the centre is the mean of noisy samples
  EXPECT_NEAR(hold(j, 520 - 440, 500, 3000).x_q15, -32767, 200);
  EXPECT_NEAR(hold(j, 520 + 460, 500, 3000).x_q15, 32767, 40);  // past it: still one
  Joystick to_rails = ready(520, 500);
  EXPECT_LT(hold(to_rails, 520 + 440, 500, 3000).x_q15, 32767 * 0.95);  // without it, 440 counts fall short
  c.full_deflection = 600;  // beyond half the scale: refused
  Joystick bad;
  EXPECT_FALSE(bad.configure(c));
}

// Square to disc (seed 2): the square's boundary lands on the unit circle, along the same
// direction; the curve is applied to the radius
TEST(Joystick, SquareToDisc) {
  JoystickConfig c = config();
  c.expo_q15 = 0;
  Joystick j;
  ASSERT_TRUE(j.configure(c));
  for (int i = -32767; i <= 32767; i += 97) {
    for (const auto& p : {std::make_pair(32767, i), std::make_pair(i, 32767), std::make_pair(-32767, i),
                          std::make_pair(i, -32767)}) {
      int16_t out[2];
      j.shape((int16_t)p.first, (int16_t)p.second, out);
      const double r = std::hypot(out[0], out[1]);
      EXPECT_NEAR(r, 32767, 12) << p.first << " " << p.second;
      const double cross = (double)out[0] * p.second - (double)out[1] * p.first;  // same direction
      EXPECT_LT(std::abs(cross) / (r * std::hypot(p.first, p.second)), 1e-3);
      EXPECT_GE((double)out[0] * p.first + (double)out[1] * p.second, 0);
    }
  }
  int16_t out[2];
  j.shape(16384, 8192, out);  // inside: radius = max(|x|, |y|)
  EXPECT_NEAR(std::hypot(out[0], out[1]), 16384, 4);
}

TEST(Joystick, ResponseCurveIsMonotone) {
  Joystick j;
  ASSERT_TRUE(j.configure(config()));
  uint16_t prev = 0;
  for (uint32_t r = 0; r <= 32767; ++r) {
    const uint16_t f = j.curve((uint16_t)r);
    ASSERT_GE(f, prev) << r;
    ASSERT_LE(f, r);  // expo 0.3: below the line, fine control near the centre
    prev = f;
  }
  EXPECT_EQ(j.curve(0), 0);
  EXPECT_NEAR(j.curve(32767), 32767, 2);
  EXPECT_NEAR(j.curve(16384), 0.7 * 16384 + 0.3 * 32768 / 8.0, 3);  // (1 - k) r + k r^3 at r = 1/2
}

TEST(Joystick, RateLimitedNoStepChanges) {
  Joystick j = ready(512, 512);
  int16_t prev = 0;
  for (int i = 0; i < 1500; ++i) {  // slam to full, hold
    const JoystickOutput o = j.update(1014, 512);
    EXPECT_LE(o.x_q15 - prev, 33);
    EXPECT_GE(o.x_q15, prev);
    prev = o.x_q15;
  }
  EXPECT_GT(prev, 32000);
  int samples = 0;
  while (prev != 0) {  // let go: falls at the faster rate
    const JoystickOutput o = j.update(512, 512);
    EXPECT_LE(prev - o.x_q15, 164);
    EXPECT_LE(o.x_q15, prev);
    prev = o.x_q15;
    ++samples;
  }
  EXPECT_LE(samples, 201);
  // full right to full left passes through zero at the fall rate, then rises
  hold(j, 1014, 512, 1500);
  prev = hold(j, 1014, 512, 1).x_q15;
  for (int i = 0; i < 2000; ++i) {
    const int16_t x = j.update(9, 512).x_q15;
    EXPECT_LE(std::abs(x - prev), 164);
    prev = x;
  }
  EXPECT_LT(prev, -32000);
}

TEST(Joystick, ChannelStuckAtARailReadsNeutralAndFaults) {
  Joystick j = ready(512, 512);
  hold(j, 800, 800, 1500);  // moving diagonally
  // a 30 ms glitch to the rail on x: x reads neutral (ramps down), y goes on, no fault
  JoystickOutput o = hold(j, 1023, 800, 30);
  EXPECT_EQ(o.status, 0);
  EXPECT_GT(o.y_q15, 10000);
  o = hold(j, 800, 800, 2000);
  EXPECT_GT(o.x_q15, 10000);
  // unplugged: x at 0 for good -> fault after 50 samples, everything to neutral
  o = hold(j, 0, 800, 50);
  EXPECT_TRUE(o.status & kJoystickRailX);
  o = hold(j, 0, 800, 400);
  EXPECT_EQ(o.x_q15, 0);
  EXPECT_EQ(o.y_q15, 0);
  // plugged back in while the stick is deflected: still nothing until neutral
  o = hold(j, 800, 800, 1000);
  EXPECT_EQ(o.y_q15, 0);
  EXPECT_TRUE(o.status & kJoystickRailX);
  hold(j, 512, 512, 100);
  o = hold(j, 512, 800, 2000);
  EXPECT_EQ(o.status, 0);
  EXPECT_GT(o.y_q15, 10000);
}

// The ramps count the caller's clock ticks, not its samples: sampled every tick or every third,
// the output is the same after the same time (a loop that overruns keeps the ramps' timing).
TEST(Joystick, RampsTakeTheSameTimeWhateverTheSampling) {
  Joystick every = ready(512, 512), third = ready(512, 512);
  for (int ms = 3; ms <= 1200; ms += 3) {
    const uint16_t x = ms < 600 ? 1000 : 512;  // full right, then let go
    JoystickOutput a{};
    for (int k = 0; k < 3; ++k) a = every.update(x, 512);
    const JoystickOutput b = third.update(x, 512, 3);
    ASSERT_NEAR(a.x_q15, b.x_q15, 2 * config().fall_q15) << "at " << ms << " ms";
    if (ms == 300) {
      EXPECT_NEAR(b.x_q15, 300 * config().rise_q15, 3 * config().rise_q15);
    }
  }
  EXPECT_EQ(third.update(512, 512, 3).x_q15, 0);
}

// The rail check and the arming count ticks, as the ramps do: sampled every second tick (the
// firmware samples in the motion pass's slot), a stuck channel latches after rail_ticks (50)
// ticks, not samples, and a neutral stick arms after neutral_ticks (100). Red when either counts
// samples (then 100 and 200 ticks).
TEST(Joystick, RailCheckAndArmingCountTicks) {
  Joystick j = ready(512, 512);
  auto hold_ticks = [&j](uint16_t x, uint16_t y, int ticks) {
    JoystickOutput o{};
    for (int t = 0; t < ticks; t += 2) o = j.update(x, y, 2);
    return o;
  };
  EXPECT_FALSE(hold_ticks(0, 512, 48).status & kJoystickRailX);
  EXPECT_TRUE(hold_ticks(0, 512, 2).status & kJoystickRailX);  // 50 ticks
  hold_ticks(512, 512, 98);
  EXPECT_TRUE(j.output().status & kJoystickNotArmed);
  EXPECT_EQ(hold_ticks(512, 512, 2).status, 0);  // 100 ticks neutral
}

// The shape is kept while its input stays (joystick.h): a stick moved, by one axis alone, a
// count at a time, back and forth, and held, gives after each sample what a new joystick gives
// for that reading alone (rise and fall within one sample, so the output is the shape itself).
// Red with the shape's cache keyed on x only, or the axes' kept readings not forgotten by a
// calibration (a new centre below); a new curve is shaped afresh after arming.
TEST(Joystick, KeptShapeEqualsAFreshOne) {
  JoystickConfig c = config();
  c.rise_q15 = c.fall_q15 = 32767;
  Joystick j = ready(515, 505, c);
  auto fresh = [&](const JoystickConfig& cf, uint16_t x, uint16_t y) {
    Joystick f = ready(515, 505, cf);
    return f.update(x, y);
  };
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> step(-1, 1), axis(0, 1), repeat(1, 4);
  uint16_t x = 700, y = 600;
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    if (axis(rng)) x = (uint16_t)(x + 9 * step(rng));
    else y = (uint16_t)(y + 9 * step(rng));
    for (int k = repeat(rng); k > 0; --k) {
      const JoystickOutput o = j.update(x, y), r = fresh(c, x, y);
      ASSERT_EQ(o.x_q15, r.x_q15) << x << "," << y;
      ASSERT_EQ(o.y_q15, r.y_q15) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 800);
  // a new centre where the stick was (deflected for the old one), then the same held reading
  hold(j, 560, 460, 3);
  calibrate_and_arm(j, 560, 460, c);
  {
    Joystick f = ready(560, 460, c);
    const JoystickOutput o = j.update(x, y), r = f.update(x, y);
    EXPECT_NE(r.x_q15, fresh(c, x, y).x_q15);
    EXPECT_EQ(o.x_q15, r.x_q15);
    EXPECT_EQ(o.y_q15, r.y_q15);
  }
  // a new curve for the same held reading
  JoystickConfig linear = c;
  linear.expo_q15 = 0;
  calibrate_and_arm(j, 515, 505, linear);
  const JoystickOutput o = j.update(x, y), r = fresh(linear, x, y);
  EXPECT_NE(r.x_q15, fresh(c, x, y).x_q15);
  EXPECT_EQ(o.x_q15, r.x_q15);
  EXPECT_EQ(o.y_q15, r.y_q15);
}

// A held stick whose reading flickers by a count (the ADC's noise) keeps its output; a reading
// two counts from the kept one is taken, and one count back from it is not.
TEST(Joystick, OneCountFlickerIsHeld) {
  JoystickConfig c = config();
  c.rise_q15 = c.fall_q15 = 32767;
  Joystick j = ready(515, 505, c);
  const JoystickOutput held = hold(j, 700, 600, 3);
  for (int i = 0; i < 20; ++i) {
    const JoystickOutput o = j.update((uint16_t)(700 + (i % 3) - 1), (uint16_t)(600 - (i % 3) + 1));
    ASSERT_EQ(o.x_q15, held.x_q15) << i;
    ASSERT_EQ(o.y_q15, held.y_q15) << i;
  }
  Joystick fresh = ready(515, 505, c);
  const JoystickOutput moved = j.update(702, 600), expected = fresh.update(702, 600);
  EXPECT_GT(moved.x_q15, held.x_q15);
  EXPECT_EQ(moved.x_q15, expected.x_q15);
  EXPECT_EQ(j.update(701, 600).x_q15, moved.x_q15);
  // released: back to neutral at once
  EXPECT_EQ(j.update(515, 505).x_q15, 0);
}
