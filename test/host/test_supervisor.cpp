// The arm's top-level state machine (firmware/core/supervisor.h): start-up order, the
// neutral-stick interlock, the wait for the person's ask before homing, the latched safety stop
// and faults, re-arming, and the mode cycle.
#include <gtest/gtest.h>

#include "core/supervisor.h"

using namespace wmra;
using core::ArmState;

namespace {

core::SupervisorInputs quiet() {
  core::SupervisorInputs in{};
  in.stick_valid = true;
  in.stick_neutral = true;
  in.drives_at_rest = true;
  return in;
}

// run ticks of 1 ms with the same inputs
void run(core::Supervisor& s, const core::SupervisorInputs& in, int ms) {
  for (int i = 0; i < ms; ++i) s.update(in, 1);
}

// a stop command, a re-arm and the stick's neutral hold (in as given otherwise)
void stop_rearm_and_hold(core::Supervisor& s, core::SupervisorInputs in) {
  in.stop_command = true;
  run(s, in, 1);
  in.stop_command = false;
  in.rearm_command = true;
  run(s, in, 1);
  in.rearm_command = false;
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
}

// one tick with a long press (the button's one-tick event)
void long_press(core::Supervisor& s, core::SupervisorInputs in) {
  in.long_press = true;
  run(s, in, 1);
}

// from power-up through the neutral hold to the wait for the person
core::Supervisor waiting_for_home(const core::SupervisorInputs& in) {
  core::Supervisor s;
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
  return s;
}

// and on through a long press and the homing (in.homed set) to the move to the ready pose
core::Supervisor moving_to_ready(core::SupervisorInputs& in) {
  core::Supervisor s = waiting_for_home(in);
  long_press(s, in);
  in.homed = true;
  run(s, in, 1);
  return s;
}

core::Supervisor running_arm() {
  auto in = quiet();
  core::Supervisor s = moving_to_ready(in);
  in.at_ready = true;
  run(s, in, 1);
  return s;
}

TEST(Supervisor, StartsSafeAndHomesOnlyWhenAskedAfterTheStickWasNeutral) {
  core::Supervisor s;
  EXPECT_FALSE(s.drives_enabled());
  auto in = quiet();
  in.stick_neutral = false;
  run(s, in, 2000);
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
  EXPECT_FALSE(s.drives_enabled());
  in.stick_neutral = true;
  run(s, in, core::Supervisor::kNeutralHold_ms - 1);
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
  run(s, in, 2);
  EXPECT_EQ(s.state(), ArmState::wait_home);
  run(s, in, 60000);
  EXPECT_EQ(s.state(), ArmState::wait_home) << "nothing moves until the person asks";
  EXPECT_FALSE(s.drives_enabled());
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::homing);
  EXPECT_TRUE(s.drives_enabled());
  EXPECT_FALSE(s.stick_enabled());
  in.homed = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::to_ready);
  EXPECT_FALSE(s.stick_enabled());
  in.at_ready = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::running);
  EXPECT_TRUE(s.stick_enabled());
}

TEST(Supervisor, AHomeCommandStartsTheHomingFromTheWait) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  ASSERT_EQ(s.state(), ArmState::wait_home);
  EXPECT_TRUE(core::accepts_home(s.state()));
  in.home_command = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::homing);
  EXPECT_FALSE(core::accepts_home(s.state())) << "a homing under way";
}

TEST(Supervisor, AShortPressInTheWaitStartsNothing) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  in.short_press = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::wait_home);
  EXPECT_EQ(s.mode(), config::kModeCycle[0]);
}

// An ask with the stick deflected or at a rail starts nothing, then or later: the long press and
// the home command are not remembered, and the link refuses the command there.
TEST(Supervisor, AnAskWhileTheStickIsNotNeutralStartsNothing) {
  for (bool valid : {true, false}) {
    SCOPED_TRACE(valid ? "stick deflected" : "stick at a rail");
    core::Supervisor s;
    auto in = quiet();
    in.stick_valid = valid;
    in.stick_neutral = !valid;  // a dead channel may read centred
    run(s, in, 2000);
    ASSERT_EQ(s.state(), ArmState::wait_neutral);
    EXPECT_FALSE(core::accepts_home(s.state()));
    long_press(s, in);
    in.home_command = true;
    run(s, in, 1);
    in.home_command = false;
    EXPECT_EQ(s.state(), ArmState::wait_neutral);
    in = quiet();
    run(s, in, 10000);
    EXPECT_EQ(s.state(), ArmState::wait_home) << "no homing from an ask made with the stick not neutral";
  }
}

// The stick leaving neutral in the wait takes the arm back to wait_neutral, the ask of the same
// tick with it: a homing starts only from a stick at rest for the whole hold.
TEST(Supervisor, AStickDeflectedInTheWaitTakesItBackToTheNeutralHold) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  in.stick_neutral = false;
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
  in.stick_neutral = true;
  run(s, in, core::Supervisor::kNeutralHold_ms - 2);
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::wait_neutral) << "not neutral for the whole hold yet";
  run(s, in, 2);
  EXPECT_EQ(s.state(), ArmState::wait_home);
  in.home_command = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::homing) << "a home command once wait_home is reported";
}

// A long press counts only where it began in the wait: one begun with the stick deflected, let
// go before the press is long, starts nothing; the next press does.
TEST(Supervisor, ALongPressBegunWithTheStickDeflectedStartsNothing) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  in.button_down = true;  // the press begins, the stick pushed
  in.stick_neutral = false;
  run(s, in, 300);
  ASSERT_EQ(s.state(), ArmState::wait_neutral);
  in.stick_neutral = true;  // let go, the button still held
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
  ASSERT_EQ(s.state(), ArmState::wait_home) << "neutral for the hold again";
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::wait_home);
  in.button_down = false;
  run(s, in, 100);
  in.button_down = true;
  run(s, in, 1000);
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::homing) << "a press begun in the wait";
}

// A button held since power-up (stuck, or a hand resting on it) is no ask: its long press comes
// while the arm waits, but began before.
TEST(Supervisor, AButtonHeldSincePowerUpStartsNothing) {
  core::Supervisor s;
  auto in = quiet();
  in.button_down = true;
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
  ASSERT_EQ(s.state(), ArmState::wait_home);
  long_press(s, in);
  run(s, in, 10000);
  EXPECT_EQ(s.state(), ArmState::wait_home);
  in.button_down = false;
  run(s, in, 1);
  in.button_down = true;
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::homing) << "released, then pressed long";
}

// A long press or a home command during the homing or the move to the ready pose changes nothing.
TEST(Supervisor, AnAskDuringTheHomingOrTheMoveToTheReadyPoseChangesNothing) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  long_press(s, in);
  ASSERT_EQ(s.state(), ArmState::homing);
  long_press(s, in);
  in.home_command = true;
  run(s, in, 1);
  in.home_command = false;
  EXPECT_EQ(s.state(), ArmState::homing);
  in.homed = true;
  run(s, in, 1);
  ASSERT_EQ(s.state(), ArmState::to_ready);
  long_press(s, in);
  EXPECT_EQ(s.state(), ArmState::to_ready);
  EXPECT_FALSE(core::accepts_home(s.state()));
}

TEST(Supervisor, AStickAtARailIsNeverNeutral) {
  core::Supervisor s;
  auto in = quiet();
  in.stick_valid = false;  // reads "neutral" only because the channel is dead
  run(s, in, 5000);
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
}

TEST(Supervisor, SafetyButtonStopsAtOnceAndStaysStoppedUntilReleasedAndRearmed) {
  auto s = running_arm();
  auto in = quiet();
  in.homed = in.at_ready = true;
  in.safety_pressed = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::stopped);
  EXPECT_FALSE(s.drives_enabled());
  in.long_press = true;  // re-arming while pressed does nothing
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::stopped);
  in.long_press = false;
  in.safety_pressed = false;  // released: still stopped
  run(s, in, 1000);
  EXPECT_EQ(s.state(), ArmState::stopped);
  in.long_press = true;
  run(s, in, 1);
  in.long_press = false;
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
  EXPECT_FALSE(s.drives_enabled());
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
  EXPECT_EQ(s.state(), ArmState::running);  // homed already: no second homing
}

TEST(Supervisor, FaultsLatchUntilClearedAndRearmed) {
  auto s = running_arm();
  auto in = quiet();
  in.homed = in.at_ready = true;
  in.faults = 0x4;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::fault);
  EXPECT_FALSE(s.drives_enabled());
  in.rearm_command = true;
  run(s, in, 10);
  EXPECT_EQ(s.state(), ArmState::fault);  // the fault is still there
  in.faults = 0;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
}

// A stop during the move to the ready pose (start-up, J5 still near its singular home): the
// re-arm makes the move again, with the steppers' homing kept, before the stick drives. After
// the ready pose was reached, a re-arm goes back to running.
TEST(Supervisor, AMoveToTheReadyPoseCutShortIsMadeAgainAfterTheRearm) {
  auto in = quiet();
  core::Supervisor s = moving_to_ready(in);
  ASSERT_EQ(s.state(), ArmState::to_ready);
  in.stop_command = true;
  run(s, in, 1);
  ASSERT_EQ(s.state(), ArmState::stopped);
  in.stop_command = false;
  in.rearm_command = true;
  run(s, in, 1);
  in.rearm_command = false;
  ASSERT_EQ(s.state(), ArmState::wait_neutral);
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
  EXPECT_EQ(s.state(), ArmState::to_ready) << "not running from where the move was stopped";
  EXPECT_FALSE(s.stick_enabled());
  in.at_ready = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::running);
  stop_rearm_and_hold(s, in);
  EXPECT_EQ(s.state(), ArmState::running) << "the ready pose was reached: running again at once";
}

TEST(Supervisor, ShortPressCyclesTheModesOnlyWhileRunning) {
  core::Supervisor s;
  auto in = quiet();
  in.short_press = true;
  run(s, in, 1);  // boot: ignored
  EXPECT_EQ(s.mode(), config::kModeCycle[0]);
  s = running_arm();
  for (int k = 1; k <= config::kModeCount; ++k) {
    run(s, in, 1);
    EXPECT_EQ(s.mode(), config::kModeCycle[k % config::kModeCount]);
  }
}

// A home command during the move to the ready pose (the link refuses it there, just homed) or
// while stopped leaves no request behind: the next re-arm, after any later stop, does not home
// the steppers (J1 swinging to its +90 deg switch) where the person expects the arm to stay.
TEST(Supervisor, AHomeCommandWhereItIsRefusedLeavesNoStaleRequest) {
  auto in = quiet();
  core::Supervisor s = moving_to_ready(in);
  ASSERT_EQ(s.state(), ArmState::to_ready);
  in.home_command = true;
  run(s, in, 1);
  in.home_command = false;
  in.at_ready = true;
  run(s, in, 1);
  ASSERT_EQ(s.state(), ArmState::running);
  stop_rearm_and_hold(s, in);
  EXPECT_EQ(s.state(), ArmState::running) << "no homing from a stale home request";
  in.stop_command = true;
  run(s, in, 1);
  in.stop_command = false;
  in.home_command = true;
  run(s, in, 1);
  in.home_command = false;
  in.rearm_command = true;
  run(s, in, 1);
  in.rearm_command = false;
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
  EXPECT_EQ(s.state(), ArmState::running) << "no homing from a home command while stopped";
  // from running a home command stops the arm and homes it after the neutral hold
  in.home_command = true;
  run(s, in, 1);
  in.home_command = false;
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
  EXPECT_FALSE(s.drives_enabled());
  run(s, in, core::Supervisor::kNeutralHold_ms);
  EXPECT_EQ(s.state(), ArmState::homing);
}

// A stop before the homing a home command in running asked for drops the request: the re-arm
// goes back to running (the steppers still homed), not into a homing nobody asked for since.
TEST(Supervisor, AStopDropsAHomeRequestNotYetBegun) {
  auto s = running_arm();
  auto in = quiet();
  in.homed = in.at_ready = true;
  in.home_command = true;
  run(s, in, 1);
  in.home_command = false;
  ASSERT_EQ(s.state(), ArmState::wait_neutral);
  stop_rearm_and_hold(s, in);
  EXPECT_EQ(s.state(), ArmState::running);
}

// A re-arm never starts a homing: where the steppers are not homed (never since the reset, a
// homing cut short, a count lost while a driver was off) the arm waits for the person again.
TEST(Supervisor, ARearmWithoutHomedSteppersWaitsForThePerson) {
  {
    SCOPED_TRACE("stopped in the wait");
    auto in = quiet();
    core::Supervisor s = waiting_for_home(in);
    stop_rearm_and_hold(s, in);
    EXPECT_EQ(s.state(), ArmState::wait_home);
    run(s, in, 10000);
    EXPECT_EQ(s.state(), ArmState::wait_home);
  }
  {
    SCOPED_TRACE("a homing cut short");
    auto in = quiet();
    core::Supervisor s = waiting_for_home(in);
    long_press(s, in);
    ASSERT_EQ(s.state(), ArmState::homing);
    stop_rearm_and_hold(s, in);
    EXPECT_EQ(s.state(), ArmState::wait_home);
    run(s, in, 1000);
    EXPECT_EQ(s.state(), ArmState::wait_home);
    long_press(s, in);
    EXPECT_EQ(s.state(), ArmState::homing);
  }
  {
    SCOPED_TRACE("a fault in running that lost a stepper's count");
    auto s = running_arm();
    auto in = quiet();
    in.homed = in.at_ready = true;
    in.faults = 0x4;
    run(s, in, 1);
    ASSERT_EQ(s.state(), ArmState::fault);
    in.faults = 0;
    in.homed = false;
    long_press(s, in);  // the re-arm
    ASSERT_EQ(s.state(), ArmState::wait_neutral);
    run(s, in, core::Supervisor::kNeutralHold_ms + 1);
    EXPECT_EQ(s.state(), ArmState::wait_home);
  }
}

}  // namespace

namespace {

// one tick with a jog command accepted by the link
void jog_command(core::Supervisor& s, core::SupervisorInputs in) {
  in.jog_command = true;
  run(s, in, 1);
}

}  // namespace

// A jog from the wait before homing: drives on while it lasts, back to the wait (the steppers
// are not homed) when it is over; a jog never starts the homing
TEST(Supervisor, AJogFromTheWaitGoesBackToTheWait) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  ASSERT_EQ(s.state(), ArmState::wait_home);
  EXPECT_FALSE(s.drives_enabled());
  jog_command(s, in);
  EXPECT_EQ(s.state(), ArmState::jog);
  EXPECT_TRUE(s.drives_enabled());
  EXPECT_FALSE(s.stick_enabled());
  run(s, in, 500);  // the jog goes on until it is over
  EXPECT_EQ(s.state(), ArmState::jog);
  in.jog_over = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::wait_home);
  EXPECT_FALSE(s.drives_enabled());
  in.jog_over = false;
  long_press(s, in);  // the person's ask still starts the homing
  EXPECT_EQ(s.state(), ArmState::homing);
}

TEST(Supervisor, AJogFromRunningGoesBackToRunning) {
  core::Supervisor s = running_arm();
  auto in = quiet();
  in.homed = true;
  jog_command(s, in);
  EXPECT_EQ(s.state(), ArmState::jog);
  EXPECT_FALSE(s.stick_enabled());
  in.jog_over = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::running);
}

// the safety button and faults stop a jog as they stop anything; a jog command elsewhere
// (homing, the move to the ready pose, stopped) starts nothing
TEST(Supervisor, AJogStopsAsAnythingDoesAndStartsOnlyFromTheWaitOrRunning) {
  auto in = quiet();
  core::Supervisor s = waiting_for_home(in);
  jog_command(s, in);
  in.safety_pressed = true;
  run(s, in, 1);
  EXPECT_EQ(s.state(), ArmState::stopped);
  in.safety_pressed = false;
  jog_command(s, in);
  EXPECT_EQ(s.state(), ArmState::stopped);

  core::Supervisor f = waiting_for_home(in);
  jog_command(f, in);
  in.faults = 1;
  run(f, in, 1);
  EXPECT_EQ(f.state(), ArmState::fault);
  in.faults = 0;

  core::Supervisor h = waiting_for_home(in);
  long_press(h, in);
  ASSERT_EQ(h.state(), ArmState::homing);
  jog_command(h, in);
  EXPECT_EQ(h.state(), ArmState::homing);
  auto ready = quiet();
  core::Supervisor r = moving_to_ready(ready);
  ASSERT_EQ(r.state(), ArmState::to_ready);
  jog_command(r, ready);
  EXPECT_EQ(r.state(), ArmState::to_ready);
}
