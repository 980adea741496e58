// The control loop: one iteration per 1 ms tick (arm_control.h). It reads the inputs, checks
// them, updates the supervisor, reacts to a change of state, and dispatches the tick's jobs as
// the tick plan (tick_plan.h) lists them:
//   inputs      ADC snapshot (stick, pots), switches, buttons
//   checks      pots (dc_drives), limit switches (homing) -> latched faults
//   supervisor  the state (wait_home .. running, stopped, fault) and the mode (core/supervisor.h)
//   motion      homing (homing.cpp), a move to a pose (joint_moves.cpp) or resolved rate from
//               the stick or a stream (motion.cpp), into the joints' references
//   drives      DC servos (dc_drives.cpp), stepper ramps (stepper_drives.cpp) -> pins (lib/drivers)
#include "app/arm_control.h"

#include <avr/pgmspace.h>

#include "app/arm.h"
#include "app/dc_drives.h"
#include "app/flash_config.h"
#include "app/homing.h"
#include "app/jog.h"
#include "app/joint_moves.h"
#include "app/motion.h"
#include "app/stepper_drives.h"
#include "app/tick_plan.h"
#include "config/derived.h"
#include "drivers/adc_scan.h"
#include "drivers/bridges.h"
#include "drivers/inputs.h"
#include "drivers/steppers.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace app {

Arm g_arm;

namespace plan {
namespace {
const uint16_t kPlanInFlash[kTicks] PROGMEM = {kPlan[0], kPlan[1], kPlan[2], kPlan[3], kPlan[4], kPlan[5], kPlan[6], kPlan[7]};
}  // namespace
uint16_t jobs(uint8_t tick) { return pgm_read_word(&kPlanInFlash[tick]); }
}  // namespace plan

namespace {

using namespace config;

// One sweep per tick (adc_scan.h) from kAdcSweepPhase_us on: the pots are converted 0.52 to
// 0.83 ms into the tick and read at the next, 0.2 to 0.5 ms old. Older readings make the DC
// joints catch up their lag harder (S7: J3 1.06 rad/s against its 1.0 limit with the pots
// converted first in a sweep from the loop's start).
constexpr uint8_t kAdcOrder[5] = {board::kAdcJoystickX, board::kAdcJoystickY, board::kAdcPotJ2, board::kAdcPotJ3,
                                  board::kAdcPotJ4};
constexpr uint8_t kAdcStickX = 0, kAdcStickY = 1, kAdcPot = 2;  // indices of the results
constexpr uint16_t kAdcSweepPhase_us = 310;
static_assert(kAdcSweepPhase_us + sizeof kAdcOrder * 104 + 30 < 1000, "the sweep done before the next tick reads it");

// homing goes to J1's high switch and J5's low one, which are therefore not armed then
constexpr uint16_t kSwitchesArmedHoming = kSwitchesArmed & ~kHomingSwitch[0] & ~kHomingSwitch[1];
constexpr uint16_t kDcSwitches = 0x00FC;  // J2..J4's low and high switches (bits 2..7, inputs.h)
constexpr uint16_t kOverrunReport_ms = 500;  // long enough for telemetry to see one missed tick

core::ArmState g_prev_state = core::ArmState::boot;
uint8_t g_phase;           // this iteration's tick of the plan
uint8_t g_motion_elapsed;  // control ticks since the motion pass last ran (or the stick took over)
uint8_t g_stick_elapsed;   // and since the stick was last sampled
uint8_t g_ramp_elapsed;    // and since the stepper ramps last ran
uint8_t g_wrist_elapsed;   // and since J6's zero switch and rest were last watched
uint16_t g_ms;
uint16_t g_hold_ms;        // since the drives were last held (a stop), saturating
bool g_moving;             // a joint move in running (to a stored pose), or the person taking one over
bool g_holding_governs;    // the last holding update is one the speed governor follows (every second)
bool g_governor_due;       // and the governor has not run since

// --- drives held, on and off

// The stop (docs/arm-guide.md, safety): the bridges brake (both sides low: the worms hold), each stepper's train
// ends at once or ramps down at its stop's deceleration, its driver enabled: the arm holds
// where it stopped and the step counts stay the joints' angles. The stop hook (the safety
// button's and the switches' interrupts) has done the same already. The DC references stand
// where the joints are; the standstill watch starts.
void hold_drives() {
  dc_drives::hold();
  steppers::halt_trains();
  for (uint8_t j = 0; j < 6; ++j) g_arm.q.qd_rad_s[j] = fx::Real{0};
  g_hold_ms = 0;
}

// The steppers' drivers off (EN high): a released joint may be moved by hand or by gravity, so
// its count is no longer its angle and the steppers are homed again before the next motion.
void drives_off() {
  steppers::kill();
  bridges::all_off();
  g_arm.homed = false;
}

// While the arm stands (stopped, faulted, waiting): a DC joint whose pot moves more than
// kStandstillMove_mdeg from where it came to rest is a fault (a slipping worm, a broken gear);
// and the optional release of the steppers' drivers.
void watch_standstill(uint8_t ticks) {
  const uint16_t before_ms = g_hold_ms;
  g_hold_ms = before_ms > 0xFFFFu - ticks ? 0xFFFFu : (uint16_t)(before_ms + ticks);
  if (before_ms < kStandstillSettle_ms) {
    if (g_hold_ms >= kStandstillSettle_ms) dc_drives::mark_rest();
    return;
  }
  if (dc_drives::moved_from_rest()) raise_fault(core::kFaultBitMovedWhileStopped);
  if (kStepperReleaseAfterStop_ms != 0 && before_ms < kStepperReleaseAfterStop_ms && g_hold_ms >= kStepperReleaseAfterStop_ms)
    drives_off();
}

void outputs_on() {
  steppers::enable_drivers(true);
  bridges::enable();
}

// The references start at rest where the joints are. The outputs stay off when the safety
// button or a switch stopped the arm after this iteration read them (the next one stops).
void drives_on() {
  steppers::resume();
  g_governor_due = false;  // not from holding duties of before the drives went off
  dc_drives::start();
  stepper_drives::references_from_counts();
  inputs::enable_unless_stopped(&outputs_on);
}

// Every joint's reference where the joint is: a DC joint that arrived within
// kArrivedTolerance_mdeg of a move's target would otherwise go on to it with the stick neutral.
void start_running() {
  drives_on();
  stepper_drives::limit_speeds(true);
  motion::start();
  g_moving = false;
}

void enter(core::ArmState state) {
  switch (state) {
    case core::ArmState::homing:
      drives_on();
      stepper_drives::use_largest_j1_stop();
      homing::restart();
      inputs::arm_switches(kSwitchesArmedHoming);
      break;
    case core::ArmState::to_ready:
      if (g_prev_state == core::ArmState::wait_neutral) drives_on();  // the move again after a stop
      joint_moves::begin_ready();
      inputs::arm_switches(kSwitchesArmed);
      break;
    case core::ArmState::running:
      start_running();
      inputs::arm_switches(kSwitchesArmed);
      break;
    case core::ArmState::jog:
      drives_on();
      // before homing a stepper's count is not its angle: the jog stops at the joint's switches
      // itself (core/jog.h), and J1 stops at the largest inertia's rate; a DC joint's pot is its
      // angle, so its switch closing means a pot that reads wrong (limit_unexpected, as after
      // homing), where a jog would otherwise stop at it without a word
      if (!g_arm.homed) stepper_drives::use_largest_j1_stop();
      inputs::arm_switches(g_arm.homed ? kSwitchesArmed : kDcSwitches);
      break;
    default:
      hold_drives();
      inputs::arm_switches(0);
      break;
  }
}

// The holding effort and the speed governor follow the pose (tick_plan.h); the governor's idle
// turn (every 16 ticks) updates J1's stop from the pose.
void pose_jobs(uint16_t jobs, bool stick_drives) {
  if (jobs & (stick_drives ? plan::kHolding : plan::kHoldingIdle)) {
    const kin::JacobianTrig<kin::Fixed>& trig = motion::holding_trig(stick_drives);
    dc_drives::update_holding(trig);
    stepper_drives::update_wrist_load(trig);
    if (stick_drives) motion::update_drift(trig);
    g_governor_due = g_holding_governs = !g_holding_governs;
  } else if (jobs & (stick_drives ? plan::kGovernor : plan::kGovernorIdle)) {
    if (g_governor_due) {
      g_governor_due = false;
      dc_drives::update_governor();
      stepper_drives::limit_speeds(stick_drives);
    } else if (g_arm.homed) {
      stepper_drives::update_j1_stop(motion::last_trig());
    }
  }
}

// Running: a move to a stored pose, the stream's halt, or the motion pass. Returns whether the
// stick (or a stream) drives.
bool running_tick(uint16_t jobs, uint8_t ticks, Requests& rq, const control::JoystickOutput& stick, bool stick_valid,
                  bool stick_neutral, bool long_press) {
  // A stick at a rail (unplugged, broken) moves nothing, whatever else commands: a move
  // or a streamed velocity would go on where the person could not take it over. A deflected stick
  // takes a stream over, as it does a move: the stream ends (the link refuses it until it has
  // stopped arriving), it does not drive again when the stick is let go.
  if (!stick_valid || !stick_neutral) {
    rq.stream_taken_over = rq.velocity_fresh;
    rq.velocity_fresh = false;
  } else if (motion::streaming() && !rq.velocity_fresh) {
    motion::halt_lost_stream();
  }
  motion::set_streaming(rq.velocity_fresh);
  int8_t pose_slot = rq.goto_slot;
  if (long_press && kLongPressWhileRunning == LongPress::go_to_stored_pose_0) pose_slot = 0;
  if (pose_slot >= 0 && stick_valid && pose_valid((uint8_t)pose_slot)) {
    joint_moves::begin(g_arm.settings->pose_angle[pose_slot]);
    g_moving = true;
  }
  // the person takes over, or no stick: the move slows to rest along its line, then the stick
  // drives (the steppers, carrying the arm, are never cut at speed)
  if (g_moving && (!stick_neutral || !stick_valid || rq.velocity_fresh)) joint_moves::brake();
  if (g_moving) {
    joint_moves::tick(jobs & plan::kMoveSpeedCap, jobs & plan::kStepperRamps);
    if (joint_moves::arrived() || joint_moves::braked_to_rest()) start_running();
    return false;
  }
  if (motion::stream_halted()) {
    if (motion::stream_halt_over(ticks) && steppers::at_rest()) start_running();
    return false;
  }
  if (jobs & plan::kMotionPass) {
    motion::pass(stick, rq, g_motion_elapsed, plan::jobs((uint8_t)((g_phase + 1) % plan::kTicks)) & plan::kHolding);
    g_motion_elapsed = 0;
  } else if (jobs & plan::kStepperRamps) {  // the ramps, run below, follow the references
    stepper_drives::track();
  }
  return true;
}

const control::JoystickConfig kStickInFlash PROGMEM = kStickConfig;

void configure(Settings& settings) {
  g_arm.stick.configure(from_flash(kStickInFlash));
  g_arm.stick.set_stored_centre(settings.stick_centre_counts[0], settings.stick_centre_counts[1]);
  g_arm.button.configure(control::ButtonConfig{kButtonDebounce_ms, kButtonLongPress_ms});
  for (uint8_t j = 0; j < 6; ++j) g_arm.drives.positive_rad_s[j] = g_arm.drives.negative_rad_s[j] = kMotionLimits.joint[j].speed_rad_s;
  g_arm.j1_max_change_per_tick = kJ1MaxChangeAtWorst;
  g_arm.j1_max_brake_per_tick = kJ1MaxChangePerTick[0];
  g_arm.j5_max_change_per_tick = kMaxSpeedChangePerTick[4];
  g_arm.j5_lift_way = 0;
  stepper_drives::configure();
  homing::configure();
  dc_drives::configure(settings);
}

// a re-arm's
void clear_faults() {
  g_arm.faults = 0;
  dc_drives::reset_checks();
}

}  // namespace

void start(Settings& settings, const fx::Angle* j6_at_rest) {
  g_arm.settings = &settings;
  configure(settings);
  homing::set_j6_recorded(j6_at_rest);
  adc::start(kAdcOrder, sizeof kAdcOrder, kAdcSweepPhase_us);
  set_speed_scale(100);
  motion::start_gripper();
}

void stop_from_interrupt() {
  bridges::all_off();
  steppers::halt_trains();
}

void outputs_off() {
  bridges::all_off();
  steppers::kill();
}

void iterate(Requests& rq, uint8_t ticks) {
  const uint8_t phase = g_phase = (uint8_t)((g_phase + 1) % plan::kTicks);  // by iteration: after an overrun no job is skipped
  const uint16_t jobs = plan::jobs(phase);

  // --- inputs
  uint16_t adc[adc::kMaxChannels];
  adc::snapshot(adc);
  // the limit switches for homing, which is entered only from wait_home or wait_neutral: not
  // read while running or moving to the ready pose (a switch hit then is the interrupt's event)
  const core::ArmState before = g_arm.supervisor.state();
  const bool homing_possible = before != core::ArmState::running && before != core::ArmState::to_ready;
  const uint16_t switches = homing_possible ? inputs::closed_switches() : 0;
  const bool safety = inputs::take_safety_event() | inputs::safety_pressed();
  g_ms = (uint16_t)(g_ms + ticks);
  g_motion_elapsed = control::add_saturated_u8(g_motion_elapsed, ticks);
  if (ticks > 1) g_arm.overrun_ms = kOverrunReport_ms;
  else if (g_arm.overrun_ms > 0) --g_arm.overrun_ms;
  // the stick and its button where the motion pass uses them; the joystick's rail check, arming
  // and ramps count ticks, so a 2 ms sample period keeps their times
  g_stick_elapsed = control::add_saturated_u8(g_stick_elapsed, ticks);
  control::JoystickOutput stick = g_arm.stick.output();
  control::ButtonEvent button = control::ButtonEvent::none;
  if (jobs & plan::kStick) {
    stick = g_arm.stick.update(adc[kAdcStickX], adc[kAdcStickY], g_stick_elapsed);
    g_stick_elapsed = 0;
    button = g_arm.button.update(inputs::joystick_button_down(), g_ms);
  }

  // --- checks
  dc_drives::read_and_check(&adc[kAdcPot], ticks, jobs & plan::kDcServos);
  const uint16_t switch_closed = inputs::take_switch_event();
  if (switch_closed) homing::on_switch_closed(switch_closed);

  // --- supervisor
  const bool long_press = button == control::ButtonEvent::long_press;
  const bool halted = before == core::ArmState::stopped || before == core::ArmState::fault;
  if (halted && (rq.rearm || long_press) && !safety) clear_faults();
  const bool stick_valid = !stick_invalid(stick);
  const bool stick_neutral = stick.x_q15 == 0 && stick.y_q15 == 0 && !(stick.status & control::kJoystickCalibrating);
  core::SupervisorInputs in{};
  in.safety_pressed = safety;
  in.faults = g_arm.faults & core::kFaultsLatched;
  in.drives_at_rest = steppers::at_rest();
  in.stick_valid = stick_valid;
  in.stick_neutral = stick_neutral;
  in.short_press = button == control::ButtonEvent::press;
  in.long_press = long_press;
  in.button_down = g_arm.button.down();
  in.rearm_command = rq.rearm;
  in.stop_command = rq.stop;
  in.home_command = rq.home;
  in.homed = g_arm.homed;
  in.at_ready = joint_moves::arrived();
  const bool stick_rests = stick_valid && stick_neutral;
  in.jog_command = rq.jog_new;
  in.jog_over = !(rq.jog_fresh && stick_rests) && jog::at_rest() && steppers::at_rest();
  g_arm.supervisor.update(in, ticks);
  const core::ArmState state = g_arm.supervisor.state();
  if (state != g_prev_state) {
    enter(state);
    g_prev_state = state;
  }

  // --- motion
  bool stick_drives = false;
  switch (state) {
    case core::ArmState::homing:
      homing::tick(switches, ticks);
      break;
    case core::ArmState::to_ready:
      joint_moves::tick(jobs & plan::kMoveSpeedCap, jobs & plan::kStepperRamps);
      break;
    case core::ArmState::running:
      stick_drives = running_tick(jobs, ticks, rq, stick, stick_valid, stick_neutral, long_press);
      break;
    case core::ArmState::jog:
      jog::tick(rq, stick_rests, switches, ticks);
      break;
    default:
      break;
  }
  if (!stick_drives) g_motion_elapsed = 0;  // the motion pass's ticks count from the first it drives

  // --- drives
  if (g_arm.supervisor.drives_enabled()) {
    pose_jobs(jobs, stick_drives);
    if (jobs & plan::kDcServos) dc_drives::run_servos();
  } else {
    watch_standstill(ticks);
  }
  // The steppers' ramps: while the stick drives in the plan's ramp ticks, with the steps counted
  // in the tick before (their tracking reads the counts a tick old, as homing and the moves do,
  // which run the ramps every tick). Nothing else reads the counts while the stick drives; the
  // readers outside it (the report, the drives off, a move or a brake begun) count first.
  g_ramp_elapsed = control::add_saturated_u8(g_ramp_elapsed, ticks);
  const bool ramps_every_tick = (state != core::ArmState::running && state != core::ArmState::to_ready) || motion::stream_halted();
  if ((jobs & plan::kStepperRamps) || ramps_every_tick) {
    steppers::service(g_ramp_elapsed);
    g_ramp_elapsed = 0;
  } else if (jobs & plan::kStepperCount) {
    steppers::count();
  }
  g_wrist_elapsed = control::add_saturated_u8(g_wrist_elapsed, ticks);
  if (jobs & plan::kWristWatch) {
    homing::watch_wrist(g_wrist_elapsed, state == core::ArmState::to_ready || g_moving);
    g_wrist_elapsed = 0;
  }

  rq.stop = rq.rearm = rq.home = rq.jog_new = false;
  rq.goto_slot = -1;
}

bool running_busy() {
  return g_arm.supervisor.state() == core::ArmState::running && (g_moving || motion::streaming() || motion::stream_halted());
}

}  // namespace app
}  // namespace wmra
