#include "commands.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "kinematics/arm_model.h"
#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

using protocol::MsgType;

namespace {

// a speed in m/s or rad/s, to the nearest mm/s or mrad/s, within int16_t
int16_t parse_milli(const std::string& word, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end || errno == ERANGE || !std::isfinite(v) || std::fabs(v) > 32.767) {
    throw BadInput{what + " must be a number within +-32.767, not '" + word + "'"};
  }
  return (int16_t)std::lround(v * 1000);
}

// a number (an angle in degrees), finite
double parse_double(const std::string& word, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end || errno == ERANGE || !std::isfinite(v)) throw BadInput{what + " must be a number, not '" + word + "'"};
  return v;
}

// calibrate J AT_MIN AT_MAX
protocol::PotCalibrationCmd pot_calibration(const std::vector<std::string>& words) {
  return protocol::PotCalibrationCmd{(uint8_t)parse_int(words[1], 2, 4, "J (the joint)"),
                                     (int16_t)parse_int(words[2], 0, kMaxReading_counts_x16, "AT_MIN (pot counts x 16)"),
                                     (int16_t)parse_int(words[3], 0, kMaxReading_counts_x16, "AT_MAX (pot counts x 16)")};
}

}  // namespace

protocol::PotCalibrationCmd pot_calibration_from_words(const std::vector<std::string>& words) {
  if (words.size() != 6) throw BadInput{"calibrate-from takes J READING1 DEG1 READING2 DEG2"};
  const int joint = (int)parse_int(words[1], 2, 4, "J (the joint)");
  const int r1 = (int)parse_int(words[2], 0, kMaxReading_counts_x16, "READING1 (pot counts x 16)");
  const double a1 = parse_double(words[3], "DEG1");
  const int r2 = (int)parse_int(words[4], 0, kMaxReading_counts_x16, "READING2 (pot counts x 16)");
  const double a2 = parse_double(words[5], "DEG2");
  return pot_calibration_from(joint, r1, a1, r2, a2);
}

// The pot is linear in the joint angle, so the readings at the limits (lib/kinematics/arm_model.h)
// lie on the line through the two points. The soft limits keep a joint 3 deg inside its limits,
// so a joint cannot be driven there to be read; two readings at angles measured with an
// inclinometer can be taken anywhere.
protocol::PotCalibrationCmd pot_calibration_from(int joint, int reading1_counts_x16, double angle1_deg,
                                                 int reading2_counts_x16, double angle2_deg) {
  const double r1 = reading1_counts_x16, a1 = angle1_deg, r2 = reading2_counts_x16, a2 = angle2_deg;
  if (std::fabs(a2 - a1) < kMinPointsApart_deg) throw BadInput{"DEG1 and DEG2 must be at least 10 deg apart"};
  const double per_deg = (r2 - r1) / (a2 - a1);
  const long at_min = std::lround(r1 + (arm::q_min_deg[joint - 1] - a1) * per_deg);
  const long at_max = std::lround(r1 + (arm::q_max_deg[joint - 1] - a1) * per_deg);
  if (per_deg < 0)  // the firmware refuses it (bad_argument): its servo works in units that rise with the angle
    throw BadInput{"the pot's reading falls as the joint's angle rises: it is wired reversed, swap its two outer wires "
                   "(docs/arm-guide.md) and read it again"};
  if (at_min < 0 || at_max > kMaxReading_counts_x16 || at_max <= at_min) {
    throw BadInput{"the limits' readings come out at " + std::to_string(at_min) + " and " + std::to_string(at_max) +
                   ": outside 0.." + std::to_string(kMaxReading_counts_x16) + " or the wrong way round (check the pot's wiring)"};
  }
  return protocol::PotCalibrationCmd{(uint8_t)joint, (int16_t)at_min, (int16_t)at_max};
}

long parse_int(const std::string& word, long lo, long hi, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(word.c_str(), &end, 10);
  if (word.empty() || *end || errno == ERANGE || v < lo || v > hi) {
    throw BadInput{what + " must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                   ", not '" + word + "'"};
  }
  return v;
}

double parse_number(const std::string& word, double lo, double hi, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end || errno == ERANGE || !std::isfinite(v) || v < lo || v > hi) {
    char range[64];
    std::snprintf(range, sizeof range, "%g to %g", lo, hi);
    throw BadInput{what + " must be a number from " + range + ", not '" + word + "'"};
  }
  return v;
}

std::vector<uint8_t> parse_hex(const std::string& hex, const std::string& what) {
  if (hex.empty() || hex.size() % 2) throw BadInput{what + " wants an even number of hex digits"};
  std::vector<uint8_t> bytes;
  for (size_t i = 0; i < hex.size(); i += 2) {
    const std::string pair = hex.substr(i, 2);
    if (!std::isxdigit((unsigned char)pair[0]) || !std::isxdigit((unsigned char)pair[1])) {
      throw BadInput{what + ": '" + pair + "' is not a hex byte"};
    }
    bytes.push_back((uint8_t)std::strtoul(pair.c_str(), nullptr, 16));
  }
  return bytes;
}

std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> words;
  size_t at = 0;
  while ((at = line.find_first_not_of(" \t\r", at)) != std::string::npos) {
    const size_t end = line.find_first_of(" \t\r", at);
    words.push_back(line.substr(at, end == std::string::npos ? std::string::npos : end - at));
    at = end;
  }
  return words;
}

std::vector<uint8_t> encode_frame(const std::vector<std::string>& words, uint8_t seq) {
  struct Command {
    const char* word;
    MsgType type;
    uint8_t args;
  };
  static const Command kCommands[] = {
      {"stop", MsgType::cmd_stop, 0},         {"rearm", MsgType::cmd_rearm, 0},    {"home", MsgType::cmd_home, 0},
      {"mode", MsgType::cmd_mode, 1},         {"speed", MsgType::cmd_speed_scale, 1}, {"goto", MsgType::cmd_goto_pose, 1},
      {"store", MsgType::cmd_store_pose, 1}, {"velocity", MsgType::cmd_velocity, 6},
      {"calibration", MsgType::cmd_get_calibration, 0}, {"calibrate", MsgType::cmd_pot_calibration, 3},
      {"calibrate-from", MsgType::cmd_pot_calibration, 5}, {"stick-centre", MsgType::cmd_stick_centre, 1},
      {"info", MsgType::cmd_info, 0},         {"jog", MsgType::cmd_jog, 2},
  };
  if (words.empty()) throw BadInput{"encode wants a command"};
  const std::string& word = words[0];
  const Command* c = nullptr;
  for (const Command& k : kCommands) {
    if (word == k.word) c = &k;
  }
  if (!c) throw BadInput{"unknown command '" + word + "'"};
  if (words.size() != 1u + c->args) {
    throw BadInput{word + " takes " + std::to_string(c->args) + " argument" + (c->args == 1 ? "" : "s") + ", got " +
                   std::to_string(words.size() - 1)};
  }
  uint8_t payload[protocol::kMaxPayload];
  uint8_t len = c->args ? 1 : 0;
  switch (c->type) {
    case MsgType::cmd_mode:
      payload[0] = protocol::kModeValues;
      for (uint8_t m = 0; m < protocol::kModeValues; ++m) {
        if (words[1] == telemetry::mode_name(m)) payload[0] = m;
      }
      if (payload[0] == protocol::kModeValues) throw BadInput{"mode must be xy, xz, r1, r2 or gripper, not '" + words[1] + "'"};
      break;
    case MsgType::cmd_speed_scale: payload[0] = (uint8_t)parse_int(words[1], 0, 100, "speed (percent)"); break;
    case MsgType::cmd_stick_centre:
      if (words[1] != "store" && words[1] != "forget") throw BadInput{"stick-centre must be store or forget, not '" + words[1] + "'"};
      payload[0] = words[1] == "store";
      break;
    case MsgType::cmd_goto_pose:
    case MsgType::cmd_store_pose:
      payload[0] = (uint8_t)parse_int(words[1], 0, protocol::kPoseSlots - 1, word + " (slot)");
      break;
    case MsgType::cmd_velocity: {
      static const char* kNames[] = {"VX (m/s)", "VY (m/s)", "VZ (m/s)", "WX (rad/s)", "WY (rad/s)", "WZ (rad/s)"};
      protocol::VelocityCmd v;
      for (int i = 0; i < 3; ++i) {
        v.v_mm_s[i] = parse_milli(words[1 + i], kNames[i]);
        v.w_mrad_s[i] = parse_milli(words[4 + i], kNames[3 + i]);
      }
      len = protocol::encode(v, payload);
      break;
    }
    case MsgType::cmd_jog: {
      const protocol::JogCmd j{(uint8_t)parse_int(words[1], 1, 6, "J (the joint)"), parse_milli(words[2], "RAD_S (rad/s)")};
      len = protocol::encode(j, payload);
      break;
    }
    case MsgType::cmd_pot_calibration: {
      const protocol::PotCalibrationCmd p = c->args == 3 ? pot_calibration(words) : pot_calibration_from_words(words);
      len = protocol::encode(p, payload);
      break;
    }
    default: break;  // no argument
  }
  uint8_t frame[protocol::kMaxFrameBytes];
  const uint8_t n = protocol::write_frame((uint8_t)c->type, seq, payload, len, frame);
  return std::vector<uint8_t>(frame, frame + n);
}

std::string encode(const std::vector<std::string>& words, uint8_t seq) {
  const std::vector<uint8_t> frame = encode_frame(words, seq);
  return telemetry::to_hex(frame.data(), frame.size());
}

}  // namespace telemetry_cli
}  // namespace wmra
