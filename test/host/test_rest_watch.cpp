// When J6's angle is recorded (firmware/core/rest_watch.h): once per rest after it moved, never
// while it moves, never again while it stands (dithering a step or two included), never while
// its count is not its angle.
#include <gtest/gtest.h>

#include "core/rest_watch.h"

namespace wmra {
namespace core {
namespace {

// 1 s within 0.5 deg, 1 deg from the last record: J6's 6,400 steps a turn
constexpr RestWatchConfig kConfig{1000, 9, 18};

struct Session {
  RestWatch w;
  int records = 0;
  int32_t last = 0;
  Session() { w.configure(kConfig); }
  void tick(int32_t position, bool trusted) {
    if (w.update(position, trusted, 1)) {
      ++records;
      last = position;
    }
  }
  // ms ticks at position
  void hold(int32_t position, int ms, bool trusted = true) {
    for (int t = 0; t < ms; ++t) tick(position, trusted);
  }
  // J6 turning from a to b at a step a ms
  void turn(int32_t a, int32_t b, bool trusted = true) {
    for (int32_t p = a; p != b; p += b > a ? 1 : -1) tick(p, trusted);
  }
};

TEST(RestWatch, OneRecordPerRestAfterAMove) {
  Session r;
  r.hold(0, 5000);
  EXPECT_EQ(r.records, 1) << "none recorded yet: the first rest is recorded";
  r.hold(0, 60000);
  EXPECT_EQ(r.records, 1) << "standing: nothing more, however long";
  r.turn(0, 500);
  EXPECT_EQ(r.records, 1) << "nothing while it moves";
  r.hold(500, 999);
  EXPECT_EQ(r.records, 1) << "not before the rest time (counted from where the turn came within the band)";
  r.hold(500, 10);
  EXPECT_EQ(r.records, 2);
  EXPECT_EQ(r.last, 500);
}

TEST(RestWatch, ShortPausesAndSmallMovesRecordNothing) {
  Session r;
  r.w.set_recorded(0);
  for (int k = 0; k < 100; ++k) {  // a roll with pauses shorter than the rest time
    r.turn(k * 100, k * 100 + 100);
    r.hold(k * 100 + 100, 900);
  }
  EXPECT_EQ(r.records, 0);
  r.hold(10000, 200);
  EXPECT_EQ(r.records, 1) << "the rest at its end";
  for (int k = 0; k < 50; ++k) {  // moves back and forth within the change that is recorded
    r.turn(10000, 10017);
    r.hold(10017, 2000);
    r.turn(10017, 10000);
    r.hold(10000, 2000);
  }
  EXPECT_EQ(r.records, 1);
}

TEST(RestWatch, NothingWhileTheCountIsNotTheAngle) {
  Session r;
  r.hold(300, 5000, false);
  EXPECT_EQ(r.records, 0) << "not homed";
  r.hold(300, 5000, true);
  EXPECT_EQ(r.records, 1) << "homed: its rest";
  r.w.clear_recorded();  // the recorded angle forgotten (a homing found it wrong)
  r.turn(300, 200, false);
  r.hold(200, 5000, false);
  EXPECT_EQ(r.records, 1);
}

// A stepper held by its tracking loop that dithers two steps about its reference is at rest: its
// angle is recorded once, and nothing more while it dithers. (Required to stand on one count, a
// J6 that dithered after a move to a pose was never recorded: the EEPROM kept the angle from
// before the move.)
TEST(RestWatch, ADitheringCountIsAtRest) {
  Session r;
  r.w.set_recorded(0);
  r.turn(0, 1600);
  for (int k = 0; k < 600; ++k) r.hold(1600 + (k % 4 == 1 ? 2 : k % 4 == 3 ? -2 : 0), 50);
  EXPECT_EQ(r.records, 1);
  EXPECT_NEAR(r.last, 1600, 2);
}

// A creep faster than the band a rest time is motion
TEST(RestWatch, ACreepOutOfTheBandIsNoRest) {
  Session r;
  r.w.set_recorded(0);
  for (int32_t p = 0; p < 400; ++p) r.hold(p, 100);  // 10 steps a second
  EXPECT_EQ(r.records, 0);
}

}  // namespace
}  // namespace core
}  // namespace wmra
