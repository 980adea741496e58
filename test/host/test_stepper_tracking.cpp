// firmware/core/stepper_tracking.h with the real step ramp at J1's numbers (2037 steps/rad,
// 0.6 rad/s^2, 1 kHz commands): a stepper that lags its reference catches up without swinging
// past it, where a plain proportional correction does swing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "control/step_ramp.h"
#include "core/stepper_tracking.h"

namespace {

using namespace wmra;
using Ramp = control::StepRamp<250000>;

constexpr int32_t kAccel_steps_s2 = 1222;  // 0.6 rad/s^2 at 12800 steps per turn

struct Settling {
  int32_t max_overshoot_steps = 0;  // past the reference, against the direction of approach
  int32_t final_error_steps = 0;
};

// The reference stands still at 0; the step count starts `start_steps` away, at rest. The
// step edges of a timer at 250 kHz; commands every millisecond for `seconds`.
template <class Law>
Settling settle(int32_t start_steps, double seconds, Law law) {
  Ramp r;
  control::StepRampConfig c{kAccel_steps_s2, 12};
  c.max_interval_ticks = 12500;
  EXPECT_EQ(r.configure(c), control::RampStatus::ok);
  r.set_position(start_steps);
  Settling run;
  long tick = 0, next_edge = -1;
  for (int ms = 0; ms < seconds * 1000; ++ms) {
    r.set_speed(law(-r.position_steps()));
    if (next_edge < 0 && r.wants_step()) {
      const Ramp::Step s = r.next();
      if (s.interval_ticks) next_edge = tick + s.interval_ticks;
    }
    for (int k = 0; k < 250; ++k, ++tick) {
      if (tick != next_edge) continue;
      const Ramp::Step s = r.next();
      next_edge = s.interval_ticks ? next_edge + s.interval_ticks : -1;
    }
    const int32_t past = start_steps > 0 ? -r.position_steps() : r.position_steps();
    if (past > run.max_overshoot_steps) run.max_overshoot_steps = past;
  }
  run.final_error_steps = -r.position_steps();
  return run;
}

TEST(StepperTracking, CatchesUpWithoutSwingingPastTheReference) {
  const core::StepperTracking tracking{20, kAccel_steps_s2, 20};
  for (int32_t start : {-400, -60, -3, 2, 45, 300}) {
    const Settling run = settle(start, 4.0, [&](int32_t error) { return core::tracking_speed_steps_s(tracking, 0, error); });
    EXPECT_LE(run.max_overshoot_steps, 1) << "from " << start;
    EXPECT_LE(std::abs(run.final_error_steps), 1) << "from " << start;
  }
}

TEST(StepperTracking, APlainGainSwingsPastIt) {
  const Settling run = settle(-300, 4.0, [](int32_t error) { return 20 * error; });
  EXPECT_GT(run.max_overshoot_steps, 50);
}

TEST(StepperTracking, ReferenceSpeedPassesThrough) {
  const core::StepperTracking tracking{20, kAccel_steps_s2, 20};
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, -350, 0), -350);
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, 100, 2), 140);    // linear: 2 <= 1222 / 400
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, 0, -100), -349);  // sqrt(1222 x 100)
  EXPECT_GT(core::tracking_speed_steps_s(tracking, 0, 1 << 30), 0);  // no overflow
  // a standing or creeping reference has a step's error left alone (kTrackingDeadband_steps):
  // its speed alone; a moving one has it corrected
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, 0, 1), 0);
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, -3, -1), -3);
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, 100, 1), 120);
  EXPECT_EQ(core::tracking_speed_steps_s(tracking, -20, -1), -40);
}

}  // namespace
