// Every number of the virtual arm, in one place, with its unit in its name and its source.
//
// Sources: "Torres" = R. A. Torres, Instrumentação e controle de braço robótico para deficientes
// (UnB, 2020), its tables and the datasheets of its Annex II; "datasheet" = the part's public
// datasheet. ASSUMPTION marks a number that none of them gives: a plausible value, chosen here, that a measurement on the real
// arm should replace.
//
// Conventions the firmware must share (they are the wiring of the virtual arm):
//   - stepper joints: DIR high turns the joint in its positive direction;
//   - DC joints: PWM on the BTS7960 L input (left) turns the joint in its positive direction,
//     R (right) in the negative one; the bridge applies 12 V x (duty_L - duty_R);
//   - potentiometers: the joint range [q_min, q_max] spans kPotLowMv..kPotHighMv, rising with
//     the angle, so that an open or shorted wiper (0 mV or 5000 mV, a rail) is told apart from
//     any real angle;
//   - joystick axes: centre ~2.5 V, full deflection +-2.25 V (stick +X, +Y = higher voltage);
//   - limit switches close at the joint limit; a hard stop 3 deg further stops the joint.
#pragma once

#include <cstdint>

#include "kinematics/arm_model.h"

namespace wmra {
namespace plant {

constexpr double kPi = 3.14159265358979323846;
constexpr double deg(double d) { return d * kPi / 180.0; }
constexpr double rpm(double r) { return r * 2.0 * kPi / 60.0; }

constexpr int kJoints = 6;

// --- supply and converter
constexpr double kBatteryV = 12.0;   // Torres: 12 V battery for motors and drivers
constexpr double kAdcRefMv = 5000;   // AVcc of the Mega, the ADC reference
constexpr double kLogicHighMv = 5000;

// --- gear reductions joint:motor (Torres, with his fixes for J2, J3, J5)
constexpr double kGearRatio[kJoints] = {2.0, 4.5, 2.5, 2.0, 10.0, 1.0};

// --- DC joints 2..4: Mabuchi JC/LC-578VA-4720 power-window motor (Torres, Table 3.1, Annex II)
// The datasheet's 9.12 N m stall torque is at the output of the motor's built-in worm gear (no
// bare 578-size motor makes 9 N m), so the model is the motor-and-worm assembly, seen at that
// output shaft, followed by the joint's own 1:N gear.
constexpr double kDcStallTorqueNm = 9.12;  // Torres, Table 3.1
constexpr double kDcStallCurrentA = 24.0;  // Torres, Table 3.1
constexpr double kDcNominalV = 12.0;       // Torres, Table 3.1
constexpr double kDcNoLoadSpeedRadS = rpm(85);  // ASSUMPTION: typical 12 V power-window motor output speed
// inertia of the rotor seen through the worm plus the worm wheel, at the assembly output
constexpr double kDcAssemblyInertiaKgm2 = 0.05;  // ASSUMPTION
// Friction at the assembly output. The breakaway torque sets the PWM dead band: 1.0 N m of 9.12
// is 11 % duty, close to the 30/255 dead zone of Torres's firmware on its test motor.
constexpr double kDcStaticFrictionNm = 1.0;    // ASSUMPTION (from Torres's 30/255 dead zone)
constexpr double kDcCoulombFrictionNm = 0.8;   // ASSUMPTION
constexpr double kDcViscousNmPerRadS = 0.02;   // ASSUMPTION
// A power-window worm gear does not back-drive (such motors are usually worm-geared and
// self-locking): the load never drives the motor; unpowered, the joint holds.
constexpr bool kDcSelfLocking = true;          // ASSUMPTION (an inference, not in Torres)

// --- stepper joints 1, 5, 6 (Torres, Table 3.1, Annex II; DRV8825 as in Torres)
constexpr int kFullStepsPerRev = 200;   // 1.8 deg motors, Torres, Table 3.1
constexpr int kMicrosteps = 32;         // DRV8825 mode pins tied high = 1/32 (Torres)
constexpr int kRotorPolePairs = 50;     // 200 full steps = 50 electrical periods of 4 full steps
constexpr int kMicrostepsPerElectricalPeriod = 4 * kMicrosteps;  // a lost "step" slips this many

struct StepperMotorData {
  double holding_torque_nm;   // datasheet, Torres, Table 3.1
  double rated_current_a;     // per phase, Torres, Table 3.1
  double inductance_h;        // per phase, Torres, Table 3.1
  double detent_torque_nm;
  double rotor_inertia_kgm2;
};
// HT23-397, bipolar series (1.41 A, 10 mH, 177 oz-in = 1.25 N m). Rotor inertia and detent
// torque are not in Torres: ASSUMPTION (typical 56 mm x 76 mm NEMA 23).
constexpr StepperMotorData kNema23Ht23_397 = {1.25, 1.41, 0.010, 0.04, 3.0e-5};
// 42HS48-1684 (1.68 A, 2.8 mH, 4.4 kg cm = 0.43 N m, detent 260 g cm). Rotor inertia ASSUMPTION
// (typical 48 mm NEMA 17).
constexpr StepperMotorData kNema17_42HS48 = {0.43, 1.68, 0.0028, 0.0255, 6.8e-6};

// Pull-out torque falls above a corner speed where the 12 V supply can no longer push the
// rated current against the winding inductance and the back-EMF. A first-order estimate:
//   omega_c = V / (N_r L I + k_e),  k_e ~ T_hold / (sqrt(2) I)
// giving 9.0 rad/s (HT23) and 29 rad/s (42HS48) at the motor; above it T = T_hold omega_c/omega.
constexpr double corner_speed_rad_s(const StepperMotorData& m) {
  return kBatteryV / (kRotorPolePairs * m.inductance_h * m.rated_current_a + m.holding_torque_nm / (1.41421356 * m.rated_current_a));
}
// The rotor and its load swing on the magnetic spring (stiffness T_hold N_r) around the indexer's
// position. The drive damps that swing with a torque on the rotor's speed against the field's
// speed (zero at a steady speed), for this damping ratio with the present inertia; the sum stays
// within the pull-out torque.
constexpr double kStepperDampingRatio = 0.3;        // ASSUMPTION
constexpr double kStepperStaticFrictionNm = 0.01;   // ASSUMPTION, at the motor (bearings, gear)
constexpr double kStepperCoulombFrictionNm = 0.008; // ASSUMPTION
// J5's 1:10 stage (Torres: "a continuous gear train or a planetary gearbox") is taken as
// self-locking like the DC joints, so that the wrist holds when the driver is disabled.
// Set false to see what a back-drivable gearbox does under the e-stop (EN high).
constexpr bool kJ5SelfLocking = true;  // ASSUMPTION

// DRV8825 timing (datasheet): STEP high and low >= 1.9 us, DIR setup before STEP rising >= 650 ns
constexpr double kDrvStepMinHighS = 1.9e-6;
constexpr double kDrvStepMinLowS = 1.9e-6;
constexpr double kDrvDirSetupS = 650e-9;

// --- mass properties (Torres, Table 3.4: r_CM in the link's own frame, m, inertia rows)
struct LinkMass {
  double r_cm_m[3];
  double mass_kg;
  double inertia_kgm2[3][3];
};
constexpr LinkMass kLinks[kJoints] = {
    {{-0.035, -0.062, 0.009}, 0.674, {{0.002, 0.001, 0}, {0.001, 0.002, 0}, {0, 0, 0.002}}},
    {{0.231, 0.007, -0.015}, 1.257, {{0.002, 0, -0.001}, {0, 0.021, 0}, {-0.001, 0, 0.020}}},
    {{0.235, -0.008, 0.090}, 1.235, {{0.002, 0, 0.002}, {0, 0.019, 0}, {0.002, 0, 0.019}}},
    {{0.097, 0.030, 0.005}, 0.672, {{0.002, 0.001, 0}, {0.001, 0.003, 0}, {0, 0, 0.005}}},
    {{0.0, 0.091, 0.0}, 0.537, {{0.002, 0, 0}, {0, 0, 0}, {0, 0, 0.002}}},
    {{0, 0, 0}, 0.0, {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
};
// payload: 1.2 kg at 10 cm from the output shaft along z6 (Torres's load case, Table 3.5)
constexpr double kPayloadKg = 1.2;
constexpr double kPayloadOffsetM = 0.10;
constexpr double kPayloadGyrationRadiusM = 0.03;  // ASSUMPTION: a 6 cm object, for J6's inertia
constexpr double kGravityMs2 = 9.81;              // base z points up (d1 is the base height)

// --- joint travel
constexpr double kHardStopBeyondLimitRad = deg(3);  // ASSUMPTION: mechanical stop past each switch

// --- sensors
// Potentiometer chain (Torres's sensor board): 10-turn pot, amplifier gain set per joint, RC low-pass
// tau = 1 ms, clamp at 5.1 V. Here the joint range spans 5 %..95 % of the ADC range (
// "conditioned so the joint range spans the ADC range"; the margins keep the rails for faults).
constexpr double kPotLowMv = 250;   // at q_min; ASSUMPTION (margin for fault detection)
constexpr double kPotHighMv = 4750; // at q_max
constexpr double kPotFilterTauS = 1e-3;  // Torres's sensor board: RC low-pass tau = 1 ms
constexpr double kPotNoiseMv = 1.5;      // ASSUMPTION: ~0.3 LSB rms at the ADC
constexpr double kPotOpenMv = 0;         // wiper open: the follower input is pulled to ground
constexpr double kPotShortMv = 5000;     // wiper shorted to the supply (clamped at the rail)

// Limit switch channel (Torres's sensor board): RC debounce 47 kOhm x 1 uF = 47 ms, then an op-amp follower
// and the PC817 optocoupler (Torres's control board): the Mega reads low while the switch is closed.
constexpr double kLimitSwitchTauS = 0.047;
constexpr double kZeroSwitchHalfWidthRad = deg(2);  // ASSUMPTION: J6's zero cam, +-2 deg each turn

// Joystick KY-023 through the board's amplifiers (Torres's control board)
constexpr double kStickCentreMv = 2500;
constexpr double kStickFullScaleMv = 2250;                    // ASSUMPTION: 5 %..95 %, rails = fault
constexpr double kStickCentreOffsetMv[2] = {25.0, -15.0};     // ASSUMPTION: X, Y centre errors
constexpr double kStickNoiseMv = 3.0;                         // ASSUMPTION
constexpr double kStickOpenMv = 0;                            // unplugged: the axes fall to 0 V

// Buttons: bare contacts bounce (the joystick's push-button and the safety button)
constexpr double kButtonBounceS = 1.5e-3;  // ASSUMPTION: 1.5 ms of bounce after each change
constexpr double kButtonPressS = 0.15;     // "button press" in a scenario: down for 150 ms

// --- integration
constexpr double kPlantStepS = 20e-6;  // 320 cycles at 16 MHz

// Everything a simulation can change at run time (tests turn noise and filters off).
struct PlantConfig {
  uint64_t seed = 1;
  double pot_noise_mv = kPotNoiseMv;
  double stick_noise_mv = kStickNoiseMv;
  double stick_centre_offset_mv[2] = {kStickCentreOffsetMv[0], kStickCentreOffsetMv[1]};
  double limit_switch_tau_s = kLimitSwitchTauS;
  double pot_filter_tau_s = kPotFilterTauS;
  double button_bounce_s = kButtonBounceS;
  bool gravity = true;
  bool payload = true;
  bool dc_self_locking = kDcSelfLocking;
  bool j5_self_locking = kJ5SelfLocking;
};

}  // namespace plant
}  // namespace wmra
