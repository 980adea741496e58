// The numbers of jointsim's three plants, each with its unit in its name and its source.
//
// Sources: "seed0 X", "seed1 X", "seed2 X" = /work/shared/reference/seedN-digest.md section X;
// "plant" = sim/plant/arm_plant_config.h, the virtual arm's numbers, which the DC joint here
// shares so that gains tuned in jointsim are tuned on the plant that armsim runs. ASSUMPTION
// marks a number none of them gives.
#pragma once

#include <cmath>

#include "plant/arm_plant_config.h"

namespace wmra {
namespace jointsim {

constexpr double kPi = 3.14159265358979323846;
constexpr double kKgfCmToNm = 0.0980665;

// --- seed 0: one stepper joint, the single-motor simulation of seed0 7.5
// Motor AK85H/3.75-1.8 and its 1:20 reducer, joint 1 of Appendix C (seed0 8.3): holding and
// detent torque, phase current and inductance, flux linkage, inertia and friction at the motor
// shaft (the friction is printed in "kg.m/s", read N m s).
constexpr double kSeed0HoldingTorqueNm = 52 * kKgfCmToNm;  // 5.10 N m
constexpr double kSeed0DetentTorqueNm = 2.6 * kKgfCmToNm;  // 5 % of holding
constexpr double kSeed0PhaseCurrentA = 5.0;
constexpr double kSeed0PhaseInductanceH = 6.4e-3;
constexpr double kSeed0FluxLinkageVs = 0.019;  // Psi_M, seed0 Table 6
constexpr double kSeed0InertiaKgm2 = 2.0e-2;   // J_total at the motor
constexpr double kSeed0ViscousNmPerRadS = 5.0e-2;
constexpr int kSeed0RotorTeeth = 50;        // 1.8 deg: 200 full steps = 50 electrical periods
constexpr int kSeed0HalfStepsPerRev = 400;  // half-step drive (seed0 7.5, Table 5)
constexpr int kSeed0HalfStepsPerElectricalPeriod = kSeed0HalfStepsPerRev / kSeed0RotorTeeth;  // 8
constexpr int kSeed0GearRatio = 20;
constexpr int kSeed0EncoderCountsPerJointRev = 6000;  // 500 ppr x4 x 3:1 pulley (seed0 4.2)
// 0.75 encoder counts per half-step
constexpr double kSeed0CountsPerHalfStep =
    (double)kSeed0EncoderCountsPerJointRev / (kSeed0HalfStepsPerRev * kSeed0GearRatio);
// The thesis's driver and supply are not given (seed0 6: a voltage-source bridge). ASSUMPTION:
// a chopper driver at 24 V. Its pull-out torque is the holding torque up to the speed where the
// supply can no longer push the rated current against the inductance and the back-EMF,
//   omega_c = V / (N_r (L I + Psi_M)) = 9.4 rad/s (600 half-steps/s),
// and falls as 1/omega above it (constant power). With the inertia and friction above this puts
// the limits near the thesis's choices: at V_S = 1,000 half-steps/s the motor has 3.05 N m for
// 0.79 N m of friction, i.e. up to ~7,200 half-steps/s^2 in a steady state (alpha = 5,000 is
// the last good value of a test that raises it, seed0 3.4), and it cannot run beyond ~1,950
// half-steps/s at all (test_jointsim measures what the dynamics make of both).
constexpr double kSeed0SupplyV = 24.0;  // ASSUMPTION
constexpr double kSeed0CornerSpeedRadS =
    kSeed0SupplyV / (kSeed0RotorTeeth * (kSeed0PhaseInductanceH * kSeed0PhaseCurrentA + kSeed0FluxLinkageVs));
// The drive damps the rotor's swing about the field with this damping ratio (the virtual arm's
// assumption for its steppers).
constexpr double kSeed0DampingRatio = plant::kStepperDampingRatio;  // ASSUMPTION (plant)
constexpr int kSeed0StepTimerHz = 250000;                           // Seed0Options::timer_hz

// --- seed 1: the DC motor of the relay experiments (seed1 4.3, 5.2)
// G(s) = K_m / (s (tau s + 1)), the drive voltage in, the shaft angle out (direct coupling).
constexpr double kSeed1GainRadPerVS = 2.4;
constexpr double kSeed1TimeConstantS = 0.255;  // measured (the model's 0.25 s computed)
constexpr int kSeed1CountsPerRev = 2260;       // 565 ppr, x4 decoding (seed1 5.3)
// The drive voltage during closed-loop control is never stated (seed1 5.2). ASSUMPTION: 12 V,
// the arm's battery; seed1 4.5 tabulates the dead zone needed at 5 V and 12 V.
constexpr double kSeed1DefaultDriveV = 12.0;

// --- the arm's DC joints 2..4 (seed2 1.2, 1.3, 2.4, 3.6): Mabuchi 578VA with its worm gear, seen
// at the worm's output shaft, then the joint gear (plant::kGearRatio), BTS7960 at 12 V, a pot
// into the 10-bit ADC. The torque-speed line of the plant (stall 9.12 N m / 24 A at 12 V, no-load
// 85 rpm) is T = T_s (V / V_n - omega / omega_0), which is an armature circuit with
//   R = V_n / I_s = 0.5 Ohm,  k_t = T_s / I_s = 0.38 N m/A,  k_e = V_n / omega_0 = 1.35 V s/rad
// at the output shaft (k_t < k_e: the worm's forward efficiency k_t / k_e = 0.28 is in k_t, as a
// self-locking worm's must be below 0.5). jointsim adds the armature inductance, which the
// plant leaves out: V = R i + L di/dt + k_e omega, T = k_t i.
constexpr double kDcArmatureResistanceOhm = plant::kDcNominalV / plant::kDcStallCurrentA;
constexpr double kDcTorqueConstantNmPerA = plant::kDcStallTorqueNm / plant::kDcStallCurrentA;
constexpr double kDcBackEmfVsPerRad = plant::kDcNominalV / plant::kDcNoLoadSpeedRadS;
constexpr double kDcArmatureInductanceH = 0.5e-3;  // ASSUMPTION: L/R = 1 ms, typical of 12 V brush motors
constexpr int kAdcFullScaleCounts = 1023;

}  // namespace jointsim
}  // namespace wmra
