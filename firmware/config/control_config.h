// The control loop's rates and the operator interface: joystick shaping, button times, the
// serial link's timeouts, the gripper. Units are in the names.
#pragma once

#include <stdint.h>

namespace wmra {
namespace config {

constexpr uint16_t kLoopHz = 1000;
constexpr uint8_t kMaxRxBytesPerTick = 32;     // serial bytes parsed per tick (bounds the loop)

// Joystick (lib/control/joystick.h), in ADC counts and Q15 per tick at 1 kHz
constexpr uint16_t kStickRailMargin_counts = 20;
// the stick's travel: the KY-023 through the board's amplifiers swings +-2.25 V (460 counts)
// around the centre; a stick that reaches 96 % of that is full (speed), beyond saturates
constexpr uint16_t kStickFullDeflection_counts = 440;
constexpr uint8_t kStickRailTicks = 5;
constexpr uint8_t kStickCalibrationSamples = 16;
constexpr uint16_t kStickCalibrationSpread_counts = 12;
constexpr uint16_t kStickCentreTolerance_counts = 60;
constexpr int16_t kStickDeadZone_permille = 20;  // SPEC 5: about 2 %
// Once the stick's released centre is stored (cmd_stick_centre), a power-up centre further from
// it than this is a hand on the stick, refused until it lets go. Released, the stick then reads
// at most this far from the centre taken, plus 1 count that the joystick keeps a reading by
// (axis()) and 2 of the ADC's noise (4 sigma of half a count): 8 counts, inside the dead zone's
// 8.8 (2 % of 440), so it reads neutral. The 60 counts above are 13 % of a full stick.
constexpr uint16_t kStickStoredCentreTolerance_counts = 5;
constexpr int16_t kStickExpo_permille = 300;     // response curve (1 - k) r + k r^3
constexpr uint16_t kStickRise_ms = 300;          // from rest to full deflection, at the least
// From full back to rest, as long as the rise: a stop sets the arm swinging on J1's stepper (the
// rotor on its magnetic spring: 1.6 Hz stretched with the payload, up to 3.5 Hz folded), and a
// stop that takes half that period or more leaves much less swing. With 150 ms the hand overshot
// S1's stop by about 0.6 mm more (over noise seeds 1..32). Released at full speed, the hand now
// comes to rest about 22 mm on (0.15 m/s x 0.3 s / 2) where no joint's acceleration limit already
// stretches the stop; at S1's pose, J1's already does (25 mm, 23 with 150 ms).
constexpr uint16_t kStickFall_ms = 300;
constexpr uint16_t kStickNeutral_ms = 300;

// Joystick button
constexpr uint16_t kButtonDebounce_ms = 20;
constexpr uint16_t kButtonLongPress_ms = 1000;
// what a long press does while running (in stopped or fault it always re-arms)
enum class LongPress : uint8_t { none, go_to_stored_pose_0 };
constexpr LongPress kLongPressWhileRunning = LongPress::go_to_stored_pose_0;

// Drift correction: the hand's commanded position is integrated, and the difference to the
// forward kinematics of the joint references is fed back at this gain.
constexpr int16_t kDriftGain_per_s = 5;
constexpr int16_t kDriftMaxCorrection_mm_s = 20;

// Gripper servo on D13: pulse range, and its rate at full stick in the gripper mode
constexpr uint16_t kGripperMin_us = 1000;
constexpr uint16_t kGripperMax_us = 2000;
constexpr uint16_t kGripperStart_us = 1500;
constexpr uint16_t kGripperRate_us_per_s = 500;

static_assert(kLoopHz == 1000, "the loop's constants (ramps, gains per tick) assume 1 kHz");
static_assert(kStickDeadZone_permille >= 0 && kStickDeadZone_permille < 200, "dead zone below 20 %");
static_assert((kStickStoredCentreTolerance_counts + 1 + 2) * 1000 <= kStickDeadZone_permille * kStickFullDeflection_counts,
              "a stick released after a calibration at the stored centre's tolerance reads inside the dead zone");
static_assert(kStickExpo_permille >= 0 && kStickExpo_permille <= 1000, "expo in [0, 1]");
static_assert(kStickRise_ms >= 50 && kStickFall_ms >= 20, "the stick's velocity ramps: no step changes");
static_assert(kButtonDebounce_ms >= 5 && kButtonLongPress_ms > kButtonDebounce_ms, "button times");
static_assert(kDriftGain_per_s >= 0 && kDriftGain_per_s <= 50, "drift gain in [0, 50] /s");
static_assert(kGripperMin_us >= 500 && kGripperMax_us <= 2500 && kGripperMin_us < kGripperMax_us &&
                  kGripperStart_us >= kGripperMin_us && kGripperStart_us <= kGripperMax_us,
              "servo pulses within 0.5..2.5 ms");

}  // namespace config
}  // namespace wmra
