// The tick plan: which periodic jobs each 1 ms control tick carries, as one table over a cycle of
// eight ticks, and the checks over it (the loop's rates, no tick with two heavy jobs). The loop
// (arm_control.cpp) is its one dispatcher: it reads the tick's entry and runs what it names.
//
// Every tick, whatever the plan: the ADC snapshot, the pot and switch checks, the supervisor and
// the safety reactions, the joint moves (homing, a move to a pose) and the stream's halt.
//
// While the stick drives, the motion pass (twist, J^-1, limits, the joints' references) and the
// drives that follow those references alternate, each at 500 Hz: the pass computed every tick
// took over a third of the loop's cycles, and the drives read references a tick old (every joint
// follows 1 ms later: 0.8 mrad at J1's 0.8 rad/s, 1/25 of a pot count at J2). 500 Hz is twice
// seed 1's 188 Hz that removed its relay's oscillation and some 20 times the DC joints'
// bandwidth; every third tick the worm's stick-slip grew (S1 to 5.3 mm). The steppers' tracking
// and ramps need less: 250 Hz is 0.08 of their position loop's time constant (20/s), and S1,
// S2, S3 and S7 are the same as at 500 Hz. The holding effort and the speed governor follow the
// pose, which changes slowly: at a joint's top speed the pose moves 16 mrad between updates.
// The gains and ramps stay per tick: each job takes the ticks since it last ran.
#pragma once

#include <stdint.h>

#include "config/control_config.h"
#include "config/joints_config.h"

namespace wmra {
namespace app {
namespace plan {

// the jobs (bits of a plan entry)
enum Job : uint16_t {
  kStick = 1u << 0,          // the stick and its button sampled
  kMotionPass = 1u << 1,     // while the stick drives: twist, J^-1, limits -> references (heavy)
  kDcServos = 1u << 2,       // the three DC servos: feedforward, PID, bridges' duties
  kStepperRamps = 1u << 3,   // while the stick drives: the steppers track their references, ramps run (heavy)
  kStepperCount = 1u << 4,   // while the stick drives: the steps made, counted for the next ramps' tick
  kHolding = 1u << 5,        // while the stick drives: the holding effort and the drift correction (heavy)
  kGovernor = 1u << 6,       // while the stick drives: the speed governor, or J1's stop speed (heavy)
  kHoldingIdle = 1u << 7,    // without the motion pass: the holding effort, in its idle tick
  kGovernorIdle = 1u << 8,   // without the motion pass: the governor or J1's stop speed, likewise
  kMoveSpeedCap = 1u << 9,   // a move to a pose: its speed cap from the hand's speed per lead joint
  kWristWatch = 1u << 10,    // J6's zero switch watched, its angle at rest recorded
};

constexpr uint8_t kTicks = 8;  // the plan's cycle
// The holding update runs in the drives' tick before the governor that reads its duties (half a
// cycle apart); the drift correction's FK goes with the holding effort (the same trig, and its
// time constant 1 / kDriftGain_per_s is 25 cycles). Without the stick's motion pass (homing, a
// move, a halt) the two run a tick early, in the idle motion tick: a move's drives' tick is its
// heaviest (the ramps every tick, the servos, on its first the servos' unpark).
constexpr uint16_t kPlan[kTicks] = {
    /* 0 */ kDcServos | kHolding,
    /* 1 */ kStick | kMotionPass | kStepperCount | kMoveSpeedCap,
    /* 2 */ kDcServos | kStepperRamps | kWristWatch,
    /* 3 */ kStick | kMotionPass | kGovernorIdle,
    /* 4 */ kDcServos | kGovernor,
    /* 5 */ kStick | kMotionPass | kStepperCount | kMoveSpeedCap,
    /* 6 */ kDcServos | kStepperRamps,
    /* 7 */ kStick | kMotionPass | kHoldingIdle,
};

// A tick's jobs, read from a copy of the plan in flash: a table indexed at run time is copied
// to RAM otherwise (16 B of the 3 KB static RAM budget).
uint16_t jobs(uint8_t tick);

// --- checks over the plan
constexpr uint8_t count(uint16_t job) {
  uint8_t n = 0;
  for (uint8_t t = 0; t < kTicks; ++t) n += (kPlan[t] & job) ? 1 : 0;
  return n;
}
constexpr uint16_t rate_hz(uint16_t job) { return (uint16_t)(config::kLoopHz / kTicks * count(job)); }
// the period of a job that runs evenly (0: not evenly spaced)
constexpr uint8_t period(uint16_t job) {
  uint8_t first = kTicks, gap = 0;
  for (uint8_t t = 0; t < kTicks; ++t) {
    if (!(kPlan[t] & job)) continue;
    if (first == kTicks) first = t;
    uint8_t next = 1;
    while (!(kPlan[(t + next) % kTicks] & job)) ++next;
    if (gap != 0 && next != gap) return 0;
    gap = next;
  }
  return gap;
}
constexpr bool at_most_one_heavy() {
  for (uint8_t t = 0; t < kTicks; ++t) {
    const uint16_t heavy = kPlan[t] & (kMotionPass | kStepperRamps | kHolding | kGovernor);
    if (heavy & (heavy - 1)) return false;
  }
  return true;
}
// the idle-tick variants ride in motion-pass ticks, which then carry nothing else heavy; each
// runs the tick before its stick-driven twin
constexpr bool idle_jobs_before_twins() {
  for (uint8_t t = 0; t < kTicks; ++t) {
    const uint16_t next = kPlan[(t + 1) % kTicks];
    if ((kPlan[t] & kHoldingIdle) && (!(kPlan[t] & kMotionPass) || !(next & kHolding))) return false;
    if ((kPlan[t] & kGovernorIdle) && (!(kPlan[t] & kMotionPass) || !(next & kGovernor))) return false;
  }
  return true;
}
// the steps are counted in the tick before the ramps', which read them
constexpr bool count_before_ramps() {
  for (uint8_t t = 0; t < kTicks; ++t)
    if (((kPlan[t] & kStepperCount) != 0) != ((kPlan[(t + 1) % kTicks] & kStepperRamps) != 0)) return false;
  return true;
}
constexpr bool stick_with_motion() {
  for (uint8_t t = 0; t < kTicks; ++t)
    if (((kPlan[t] & kStick) != 0) != ((kPlan[t] & kMotionPass) != 0) || ((kPlan[t] & kMotionPass) && (kPlan[t] & kDcServos)))
      return false;
  return true;
}

static_assert(rate_hz(kMotionPass) >= 500 && rate_hz(kDcServos) >= 500 && rate_hz(kStepperRamps) >= 250,
              "the motion chain and each DC drive loop at >= 500 Hz, the stepper ramps at >= 250 Hz");
static_assert(period(kMotionPass) == 2 && period(kDcServos) == 2 && period(kStepperRamps) == 4 && period(kHolding) == 8 &&
                  period(kGovernor) == 8 && period(kHoldingIdle) == 8 && period(kGovernorIdle) == 8 && period(kWristWatch) == 8,
              "every job evenly spaced: its gains and ramps count the ticks since its last run");
static_assert(at_most_one_heavy(), "no tick carries two heavy jobs");
static_assert(idle_jobs_before_twins(), "the idle holding and governor run in motion ticks, the tick before their twins");
static_assert(count_before_ramps(), "the steps counted in the tick before the ramps'");
static_assert(stick_with_motion(), "the stick sampled where the motion pass runs, and the pass apart from the servos");
static_assert(config::kDcUnparkTime_ms >= 2 * period(kDcServos),
              "kDcUnparkTime_ms at least two servo periods: a parked servo counts a noisy reading as its whole period");

// the motion pass's period, its speed-change limits are per pass (config/derived.h)
constexpr uint8_t kMotionPeriod_ticks = period(kMotionPass);

}  // namespace plan
}  // namespace app
}  // namespace wmra
