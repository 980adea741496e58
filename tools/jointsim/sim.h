// jointsim's simulations: one joint, one controller of lib/control (the code the firmware runs,
// called at its fixed sample rate), a plant integrated at a finer fixed step. Deterministic:
// the only noise is the pot's, seeded. The CLI (main.cpp) and the tests call these.
#pragma once

#include <complex>
#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include "control/pid.h"
#include "control/pole_placement.h"
#include "control/seed0_stepper_controller.h"
#include "models/joint_data.h"
#include "models/stepper_rotor.h"

namespace wmra {
namespace jointsim {

// An option a block refuses (its configure() status, or a range the plant needs), with why.
struct BadOption : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// --- seed 0: a stepper joint under seed 0's controller (seed0 3, 7.5-7.6)
// Seed0StepperController every dt -> V_C -> StepRamp (acceleration limit alpha, so the step
// train never speeds up or slows down faster than alpha) -> step edges at their timer ticks
// -> StepperRotor (AK85H, half steps, seed 0's inertia and friction) -> 1:20 -> encoder (6000
// counts per joint turn, 0.75 count per half-step).
struct Seed0Options {
  int32_t target_counts = 250;
  double kp = 13;                // K_P, steps/s per count
  double kd_s = 0.02;            // K_D, s
  double alpha_steps_s2 = 5000;  // alpha
  double v_s_steps_s = 1000;     // V_S
  double dt_s = 0.01;            // control period, whole milliseconds
  double duration_s = 1.0;
  control::Seed0Variant variant = control::Seed0Variant::thesis;
  double ramp_alpha_steps_s2 = 0;        // the step ramp's acceleration limit; 0: alpha
  // The step timer, 250 kHz (Timer5 at prescaler 64) or 2 MHz (prescaler 8, the arm's steppers).
  // Its 16-bit compare times steps down to F / 65534: 3.8 steps/s at 250 kHz, 31 at 2 MHz, where
  // the PD's creep near the target (K_P e = 13 steps/s at 1 count) is a stop and the joint parks
  // 2 counts short (test_jointsim: TheStepTimersSlowestStepMatters).
  int32_t timer_hz = kSeed0StepTimerHz;
};

struct Seed0Row {
  double t_s;
  int32_t target_counts;
  int32_t position_counts;  // the encoder at the end of the period
  double speed_steps_s;     // the rotor's mean speed over the period
  int64_t lost_steps;       // cumulative
  int32_t command_steps_s;  // V_C for the period
  double train_steps_s;     // the step train's rate at the end of the period (1 / its last interval, signed)
};

struct Seed0Result {
  std::vector<Seed0Row> rows;           // one per control period, the first at t = dt
  double max_train_accel_steps_s2 = 0;  // largest |acceleration| between consecutive step pairs
  int64_t steps_emitted = 0;
};

Seed0Result run_seed0(const Seed0Options& o);
// seed 0's motor on its load (joint_data.h), for StepperRotor
StepperRotorParams seed0_rotor_params();

// --- seed 1: the sampled three-level relay on seed 1's motor (seed1 4.2-4.5, 5.7)
// Relay (lib/control) every 1/fs on the encoder count (2260 per turn) -> drive +-U or 0, held
// -> FirstOrderMotor (K_m = 2.4 rad/(V s), tau = 0.255 s).
struct Seed1Options {
  double fs_hz = 47;
  double deadzone_deg = 0;  // E', the half-width: off for |E| < E'
  double target_rad = 2 * kPi;
  double drive_v = kSeed1DefaultDriveV;
  double duration_s = 6.0;
};

struct Seed1Row {
  double t_s;
  double target_rad;
  double position_rad;
  double velocity_rad_s;
  int h;  // the relay's level from this sample on: -1, 0, +1
};

struct Seed1Result {
  std::vector<Seed1Row> rows;  // one per sample, the first at t = 0
  int32_t dead_zone_counts = 0;
};

Seed1Result run_seed1_relay(const Seed1Options& o);

// --- the arm's DC joints 2..4 (seed2 1.2-1.3, 2.4-2.6, 3.6; the virtual arm's plant)
// Pid or Relay (lib/control) at rate_hz on the pot's ADC counts (x16 position units) -> duty ->
// BTS7960 at 12 V -> DcJointRl (578VA and its worm, L, joint gear) under the gravity and inertia
// of the arm held stretched around this joint (plant::joint_loads; payload 1.2 kg) -> pot (1 ms
// RC, seeded noise) -> 10-bit ADC.
enum class DcController { pid, relay };

struct DcOptions {
  int joint = 2;  // arm numbering, 2..4
  DcController controller = DcController::pid;
  double step_rad = 0.2;
  double start_rad = 0.0;  // this joint's angle at the start; the others are 0 (stretched)
  double duration_s = 3.0;
  double rate_hz = 0;         // 0: the default (kDcDefaultRateHz)
  std::vector<double> poles;  // closed-loop poles, rad/s, < 0; empty: the joint's default
  double deadzone_deg = 0.5;  // relay: E' at the joint
  double hysteresis_deg = 0;  // relay: on at E', off below E' - h (0: seed 1's law)
  double relay_duty = 1.0;    // relay: drive as a fraction of full PWM
  double noise_mv = plant::kPotNoiseMv;
  uint64_t seed = 1;
  bool payload = true;
  double inductance_h = kDcArmatureInductanceH;
  // pid: park the joint once |error| <= park_counts ADC counts for 50 ms: duty 0 (the worm holds
  // it) and the PID restarted bumplessly from 0 each sample, until |error| > 2 park_counts.
  // 0: off (the PID alone, which keeps the integral's effort on at rest).
  int32_t park_counts = 0;
};

// The controllers run at the firmware's control-loop rate.
constexpr double kDcDefaultRateHz = 1000;
constexpr int kPositionUnitsPerCount = 16;  // the PID's position units per ADC count

// The gains for a DC joint by seed 1's pole placement (lib/control/pole_placement.h) on the
// joint linearised at its start pose, G(s) = K / (s (tau s + 1)), duty -> ADC counts:
//   tau = J / (T_s / omega_0 + b),  K = T_s / (T_s / omega_0 + b) / N x counts per rad
// (J the worm's output inertia plus the arm's through the joint gear, b the viscous friction;
// gravity, Coulomb friction, stiction and the worm's self-locking are left to the integral and
// to the stiction compensation).
struct DcDesign {
  double counts_per_rad = 0;
  double inertia_kgm2 = 0;  // at the worm's output
  double k_counts_s = 0;    // K: counts/s at full duty
  double tau_s = 0;
  std::vector<std::complex<double>> poles;
  control::design::DcPidGains continuous;  // duty per count, per count-second, s per count
  control::PidGainsResult fixed;           // pid.h's per-sample gains
  control::PidConfig config;               // with the limits jointsim uses
};
// The default poles of each joint (rad/s); README lists them and why.
std::vector<double> default_dc_poles(int joint);
DcDesign design_dc_pid(const DcOptions& o);

struct DcRow {
  double t_s;
  double target_rad;
  double position_rad;  // the true joint angle
  double velocity_rad_s;
  int adc_counts;  // what the controller saw
  double duty;     // applied, -1..1
  double current_a;
};

struct DcResult {
  std::vector<DcRow> rows;  // one per control sample, the first at t = 0
  DcDesign design;          // (pid only)
};

DcResult run_dc(const DcOptions& o);

// Step-response figures of a DC run (true joint angle): overshoot past the target in the
// direction of the step, the settling time into +-band for good, the steady-state error
// (the mean of target - position over the last tail_s), and the 10-90 % rise time.
struct StepMetrics {
  double overshoot_rad = 0;
  double overshoot_percent = 0;
  double settling_s = -1;  // -1: not settled within the run
  double steady_error_rad = 0;
  double rise_s = -1;
};
StepMetrics step_metrics(const std::vector<DcRow>& rows, double start_rad, double target_rad, double band_rad,
                         double tail_s);

// --- CSV, header line first
void write_csv(std::ostream& out, const Seed0Result& r);
void write_csv(std::ostream& out, const Seed1Result& r);
void write_csv(std::ostream& out, const DcResult& r);

}  // namespace jointsim
}  // namespace wmra
