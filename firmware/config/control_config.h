// The control loop's rates and the operator interface: joystick shaping, button times, the
// serial link's timeouts, the gripper. Units are in the names.
#pragma once

#include <stdint.h>

namespace wmra {
namespace config {

constexpr uint16_t kLoopHz = 1000;
constexpr uint8_t kMaxRxBytesPerTick = 32;     // serial bytes read per tick (bounds the loop)
// The parser's steps per tick, those bytes' included: a failed frame's bytes are looked at
// again, a step each (those before the next sync in one: protocol/parser.h). A sender that repeats a frame cut short (8 of its 19
// bytes) costs 2.4 steps a byte, 27 a tick at the line's 11.5 bytes; one whose every frame says
// 64 bytes and brings 14, 3.7 (43): with 48 both are read as they come, a stop straight after
// them obeyed within 10 ms (test_link_budget). A flood made to defeat the rescan costs up to 19:
// most of it is lost (rx_overruns), a command straight after it too, until the line has been
// quiet a while. Each step costs ~100 to 160 cycles, after the iteration in the same tick.
constexpr uint8_t kMaxRxStepsPerTick = 48;

// Joystick (lib/control/joystick.h), in ADC counts and Q15 per tick at 1 kHz
constexpr uint16_t kStickRailMargin_counts = 20;
// the stick's travel: the KY-023 through the board's amplifiers swings +-2.25 V (460 counts)
// around the centre; a stick that reaches 96 % of that is full (speed), beyond saturates
constexpr uint16_t kStickTravel_counts = 460;
constexpr uint16_t kStickFullDeflection_counts = 440;
constexpr uint8_t kStickRailTicks = 5;
constexpr uint8_t kStickCalibrationSamples = 16;
constexpr uint16_t kStickCalibrationSpread_counts = 12;
// A new board takes a power-up centre this close to mid-scale. The travel swings around the
// stick's own centre: one further off reads at the rail margin when pushed full, a rail fault in
// mid-motion (at 60 counts a full push did). 30 counts are 0.15 V, 7 % of a full stick.
constexpr uint16_t kStickCentreTolerance_counts = 30;
constexpr int16_t kStickDeadZone_permille = 20;  // about 2 %
// Once the stick's released centre is stored (cmd_stick_centre), a power-up centre further from
// it than this is a hand on the stick, refused until it lets go. Released, the stick then reads
// at most this far from the centre taken, plus 1 count that the joystick keeps a reading by
// (axis()) and 2 of the ADC's noise (4 sigma of half a count): 8 counts, inside the dead zone's
// 8.8 (2 % of 440), so it reads neutral.
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

static_assert(kLoopHz == 1000, "kLoopHz == 1000: the loop's constants (ramps, gains per tick) assume 1 kHz");
static_assert(kStickDeadZone_permille >= 0 && kStickDeadZone_permille < 200, "kStickDeadZone_permille in [0, 200): a dead zone below 20 % of the stick");
static_assert((kStickStoredCentreTolerance_counts + 1 + 2) * 1000 <= kStickDeadZone_permille * kStickFullDeflection_counts,
              "kStickStoredCentreTolerance_counts: a stick released after a calibration at the stored centre's tolerance reads inside the dead zone");
static_assert(kStickRailMargin_counts >= 1 && kStickRailMargin_counts + kStickFullDeflection_counts < 1023 / 2,
              "kStickRailMargin_counts: at least a count, and a full stick at the nominal centre reads outside it "
              "(else every full push is a rail fault)");
static_assert(kStickFullDeflection_counts <= kStickTravel_counts &&
                  1023 / 2 + kStickCentreTolerance_counts + kStickTravel_counts < 1023 - kStickRailMargin_counts &&
                  1023 / 2 - kStickCentreTolerance_counts - kStickTravel_counts > kStickRailMargin_counts,
              "kStickCentreTolerance_counts: a stick centred at the tolerance and pushed through its whole travel "
              "reads inside the rail margins (else a full push is a rail fault)");
static_assert(kStickRailTicks >= 1 && kStickRailTicks <= 20,
              "kStickRailTicks in [1, 20] ticks: a broken wire reads as a pushed stick until it is a rail fault");
static_assert(kStickCalibrationSamples >= 4 && kStickCalibrationSamples <= 64,
              "kStickCalibrationSamples in [4, 64]: fewer average no noise out, more overflow the 16-bit sum of readings");
static_assert(kStickCalibrationSpread_counts >= 4 &&
                  kStickCalibrationSpread_counts * 1000 / 2 < kStickDeadZone_permille * kStickFullDeflection_counts,
              "kStickCalibrationSpread_counts: at least the ADC noise's spread (4 counts, or a centre is never taken), "
              "and half of it (the mean's distance from a released stick) inside the dead zone");
static_assert(kStickNeutral_ms >= 20 && kStickNeutral_ms <= 2000,
              "kStickNeutral_ms in [20, 2000]: a stick passing through the centre must not arm it, a person waits for it");
static_assert(kMaxRxBytesPerTick >= 1, "kMaxRxBytesPerTick: the link must read (its lower bound is in config/derived.h)");
static_assert(kMaxRxStepsPerTick >= kMaxRxBytesPerTick && kMaxRxStepsPerTick <= 2 * kMaxRxBytesPerTick,
              "kMaxRxStepsPerTick in [kMaxRxBytesPerTick, 2 x]: a step for every byte read, and the rescans' at "
              "most as many again (each ~115 cycles on the AVR, after the iteration in the same tick)");
static_assert(kLongPressWhileRunning == LongPress::none || kLongPressWhileRunning == LongPress::go_to_stored_pose_0,
              "kLongPressWhileRunning: one of LongPress's values");
static_assert(kDriftMaxCorrection_mm_s > 0,
              "kDriftMaxCorrection_mm_s > 0: 0 leaves the drift uncorrected (its bound by the hand's speed is in "
              "config/derived.h)");
static_assert(kGripperRate_us_per_s >= 50 && kGripperRate_us_per_s <= 2 * (kGripperMax_us - kGripperMin_us),
              "kGripperRate_us_per_s: at least 50 us/s, at most the servo's whole range in 0.5 s (it cannot follow "
              "faster)");
static_assert(kStickExpo_permille >= 0 && kStickExpo_permille <= 1000, "kStickExpo_permille in [0, 1000]: the response curve is monotone for an expo in [0, 1]");
static_assert(kStickRise_ms >= 50 && kStickFall_ms >= 20, "kStickRise_ms >= 50, kStickFall_ms >= 20: the stick's velocity ramps, no step changes");
static_assert(kButtonDebounce_ms >= 5 && kButtonLongPress_ms > kButtonDebounce_ms, "kButtonDebounce_ms >= 5 (a bounce), kButtonLongPress_ms above it");
static_assert(kDriftGain_per_s >= 0 && kDriftGain_per_s <= 50, "kDriftGain_per_s in [0, 50] /s");
static_assert(kGripperMin_us >= 500 && kGripperMax_us <= 2500 && kGripperMin_us < kGripperMax_us &&
                  kGripperStart_us >= kGripperMin_us && kGripperStart_us <= kGripperMax_us,
              "kGripperMin_us, kGripperMax_us, kGripperStart_us: servo pulses within 0.5..2.5 ms, min < start < max");

}  // namespace config
}  // namespace wmra
