// The arm's top-level state machine (firmware/core/supervisor.h): start-up order, the
// neutral-stick interlock, the latched safety stop and faults, re-arming, and the mode cycle.
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

// from power-up through the neutral hold and the homing (in.homed set) to the move to the ready pose
core::Supervisor moving_to_ready(core::SupervisorInputs& in) {
  core::Supervisor s;
  run(s, in, core::Supervisor::kNeutralHold_ms + 1);
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

TEST(Supervisor, StartsSafeAndHomesOnlyAfterTheStickWasNeutral) {
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

// A home command during the move to the ready pose (the link refuses it there, just homed) is
// ignored: on main it was kept as a flag, the move went on into running, and the next re-arm,
// after any later stop, homed the steppers (J1 swung to its +90 deg switch) where the person
// expected the arm to stay (review22).
TEST(Supervisor, AHomeCommandDuringTheMoveToTheReadyPoseLeavesNoStaleRequest) {
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
  // from running a home command homes, as before
  in.home_command = true;
  run(s, in, 1);
  in.home_command = false;
  EXPECT_EQ(s.state(), ArmState::wait_neutral);
  run(s, in, core::Supervisor::kNeutralHold_ms);
  EXPECT_EQ(s.state(), ArmState::homing);
}

}  // namespace
