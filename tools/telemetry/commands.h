// wmra-telemetry's command words to command frames: `encode`'s arguments and each line of a
// session (`mode xz`, `speed 50`, `jog 2 0.05`, ...), and the number parsers behind them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "protocol/messages.h"

namespace wmra {
namespace telemetry_cli {

// Input a person typed that cannot be used; the message says what is wrong with it
struct BadInput {
  std::string message;
};

// The command frame for "COMMAND ARG..." with this seq, as bytes or as lowercase hex (what
// `encode` prints and armsim's scenarios take). Throws BadInput naming the word at fault.
std::vector<uint8_t> encode_frame(const std::vector<std::string>& words, uint8_t seq);
std::string encode(const std::vector<std::string>& words, uint8_t seq);

// A pot's reading, ADC counts x 16 (the firmware's pot unit): 0..16,368
constexpr int kMaxReading_counts_x16 = 1023 * 16;
// The two points of a calibration at least this far apart: closer, a degree misread tilts the
// line through them too far at the limits
constexpr double kMinPointsApart_deg = 10;

// A DC joint's (2..4) pot readings at its limits, extrapolated from two readings at measured
// angles (`calibrate-from`). Throws BadInput when the angles are under kMinPointsApart_deg
// apart, the reading falls as the angle rises (a pot wired reversed), or the limits' readings
// come out beyond 0..kMaxReading_counts_x16.
protocol::PotCalibrationCmd pot_calibration_from(int joint, int reading1_counts_x16, double angle1_deg,
                                                 int reading2_counts_x16, double angle2_deg);
// The same from `calibrate-from J READING1 DEG1 READING2 DEG2`'s words (BadInput for bad ones)
protocol::PotCalibrationCmd pot_calibration_from_words(const std::vector<std::string>& words);

// A whole number in [lo, hi], or BadInput saying "WHAT must be a whole number from LO to HI"
long parse_int(const std::string& word, long lo, long hi, const std::string& what);
// A finite number in [lo, hi], or BadInput likewise
double parse_number(const std::string& word, double lo, double hi, const std::string& what);
// Hex digits, two a byte (no spaces), or BadInput naming `what`
std::vector<uint8_t> parse_hex(const std::string& hex, const std::string& what);

// Splits a line at spaces and tabs
std::vector<std::string> split_words(const std::string& line);

}  // namespace telemetry_cli
}  // namespace wmra
