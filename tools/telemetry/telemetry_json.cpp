#include "telemetry_json.h"

#include <cstdio>

#include "config/modes_config.h"
#include "core/faults.h"
#include "core/resolved_rate.h"
#include "core/supervisor.h"

namespace wmra {
namespace telemetry {

namespace {

using protocol::Frame;
using protocol::MsgType;

constexpr const char* kModeNames[] = {"xy", "xz", "r1", "r2", "gripper"};
static_assert(sizeof kModeNames / sizeof kModeNames[0] == protocol::kModeValues, "a name for every config::Mode");
constexpr const char* kCalibrationNames[] = {"eeprom", "defaults_blank", "defaults_bad_crc", "defaults_other_version"};
static_assert((uint8_t)protocol::Calibration::defaults_other_version == 3, "a name for every Calibration");
constexpr const char* kStatusNames[] = {"ok", "unknown_command", "bad_length", "bad_argument", "refused", "safety_held"};
static_assert((uint8_t)protocol::ReplyStatus::safety_held == 5, "a name for every ReplyStatus");
// MCUSR bits 0..4, and bit 7: the firmware inferred the cause (lib/drivers/watchdog.h)
constexpr const char* kResetCauseNames[] = {"power_on", "external", "brown_out", "watchdog", "jtag", "", "", "inferred"};
constexpr const char* kSlowReasonNames[] = {"singular", "soft_limit", "joint_speed", "drive_load", "tracking", "limit_switch"};
static_assert(core::kSlowSingular == 1 && core::kSlowSoftLimit == 2 && core::kSlowJointSpeed == 4 && core::kSlowDriveLoad == 8 &&
                  core::kSlowTracking == 16 && core::kSlowLimitSwitch == 32,
              "kSlowReasonNames[bit]");
constexpr const char* kSwitchNames[] = {"j1_low", "j1_high", "j2_low", "j2_high", "j3_low", "j3_high",
                                        "j4_low", "j4_high", "j5_low", "j5_high", "j6_zero"};

template <size_t N>
std::string code_name(uint8_t v, const char* const (&names)[N]) {
  return v < N ? names[v] : "unknown_" + std::to_string(v);
}

// the count from the table itself: a count passed beside it once left the last name out
template <size_t N>
std::vector<std::string> bit_names(uint32_t bits, const char* const (&names)[N]) {
  std::vector<std::string> out;
  for (uint8_t b = 0; b < 32; ++b) {
    if (!(bits >> b & 1u)) continue;
    out.push_back(b < N && names[b][0] ? names[b] : "bit_" + std::to_string(b));
  }
  return out;
}

// a JSON object built field by field; every name and string here is a plain identifier
class Object {
 public:
  void raw(const char* key, const std::string& value) {
    s_ += s_.size() > 1 ? ",\"" : "\"";
    s_ += key;
    s_ += "\":";
    s_ += value;
  }
  void num(const char* key, long long v) { raw(key, std::to_string(v)); }
  void str(const char* key, const std::string& v) { raw(key, "\"" + v + "\""); }
  void strs(const char* key, const std::vector<std::string>& v) {
    std::string list = "[";
    for (const auto& s : v) list += (list.size() > 1 ? ",\"" : "\"") + s + "\"";
    raw(key, list + "]");
  }
  template <class T, size_t N>
  void nums(const char* key, const T (&v)[N]) {
    std::string list = "[";
    for (const T& x : v) list += (list.size() > 1 ? "," : "") + std::to_string(x);
    raw(key, list + "]");
  }
  std::string done() const { return s_ + "}"; }

 private:
  std::string s_ = "{";
};

void add_state(Object& o, const protocol::StateMsg& m) {
  o.num("t_ms", m.t_ms);
  o.str("state", state_name(m.state));
  o.str("mode", mode_name(m.mode));
  o.strs("faults", fault_names(m.faults));
  o.strs("slowed_by", slow_reason_names(m.slowed_by));
  o.strs("reset_cause", reset_cause_names(m.reset_cause));
  o.strs("switches", switch_names(m.switches));
  o.nums("q_mrad", m.q_mrad);
  o.nums("qd_mrad_s", m.qd_mrad_s);
  o.nums("p_0p1mm", m.p_0p1mm);
  o.nums("stick_permille", m.stick_permille);
  o.num("speed_scale_pct", m.speed_scale_pct);
  o.num("loop_cycles_max", m.loop_cycles_max);
  o.num("rx_crc_errors", m.rx_crc_errors);
  o.num("rx_framing_errors", m.rx_framing_errors);
  o.num("rx_rejected", m.rx_rejected);
  o.num("rx_overruns", m.rx_overruns);
}

void add_identity(Object& o, const protocol::Identity& id) {
  o.str("version", version_text(id));
  o.str("commit", to_hex(id.commit, sizeof id.commit));
  o.str("tree", id.build_flags & protocol::kBuildCommitUnknown ? "unknown"
                : id.build_flags & protocol::kBuildTreeChanged ? "changed"
                                                                : "clean");
  char hash[9];
  std::snprintf(hash, sizeof hash, "%08lx", (unsigned long)id.config_hash);
  o.str("config_hash", hash);
}

void add_info(Object& o, const protocol::InfoMsg& m) {
  add_identity(o, m.identity);
  o.num("hand_speed_mm_s", m.hand_speed_mm_s);
  o.num("wrist_speed_mrad_s", m.wrist_speed_mrad_s);
  o.nums("joint_speed_mrad_s", m.joint_speed_mrad_s);
  o.nums("soft_min_mrad", m.soft_min_mrad);
  o.nums("soft_max_mrad", m.soft_max_mrad);
  o.num("loop_hz", m.loop_hz);
}

// the fields of a firmware frame; false when its payload does not decode
bool add_report(Object& o, const Frame& f) {
  protocol::StateMsg state;
  protocol::ReplyMsg reply;
  protocol::BootMsg boot;
  protocol::CalibrationMsg calibration;
  protocol::InfoMsg info;
  if (protocol::decode(f, state)) {
    add_state(o, state);
  } else if (protocol::decode(f, reply)) {
    const char* command = type_name(reply.command_type);
    o.str("command", command ? command : "unknown_" + std::to_string(reply.command_type));
    o.num("command_seq", reply.command_seq);
    o.str("status", status_name(reply.status));
  } else if (protocol::decode(f, boot)) {
    o.strs("reset_cause", reset_cause_names(boot.reset_cause));
    o.str("calibration", calibration_name((uint8_t)boot.settings()));
    o.str("j6_angle", boot.j6_angle_recorded() ? "recorded" : "none");
    add_identity(o, boot.identity);
  } else if (protocol::decode(f, info)) {
    add_info(o, info);
  } else if (protocol::decode(f, calibration)) {
    o.nums("at_min_counts_x16", calibration.at_min_counts_x16);
    o.nums("at_max_counts_x16", calibration.at_max_counts_x16);
    o.nums("reading_counts_x16", calibration.reading_counts_x16);
    o.num("from_command", calibration.from_command);
  } else {
    return false;
  }
  return true;
}

// the argument of a command that check_command passed
void add_command_argument(Object& o, const Frame& f) {
  switch ((MsgType)f.type) {
    case MsgType::cmd_mode: o.str("mode", mode_name(f.payload[0])); break;
    case MsgType::cmd_speed_scale: o.num("speed_scale_pct", f.payload[0]); break;
    case MsgType::cmd_goto_pose:
    case MsgType::cmd_store_pose: o.num("slot", f.payload[0]); break;
    case MsgType::cmd_stick_centre: o.str("stick_centre", f.payload[0] ? "store" : "forget"); break;
    case MsgType::cmd_velocity: {
      protocol::VelocityCmd v;
      protocol::decode(f, v);
      o.nums("v_mm_s", v.v_mm_s);
      o.nums("w_mrad_s", v.w_mrad_s);
      break;
    }
    case MsgType::cmd_jog: {
      protocol::JogCmd j{};
      protocol::decode(f, j);
      o.num("joint", j.joint);
      o.num("speed_mrad_s", j.speed_mrad_s);
      break;
    }
    case MsgType::cmd_pot_calibration: {
      protocol::PotCalibrationCmd c{};
      protocol::decode(f, c);
      o.num("joint", c.joint);
      o.num("at_min_counts_x16", c.at_min_counts_x16);
      o.num("at_max_counts_x16", c.at_max_counts_x16);
      break;
    }
    default: break;  // stop, rearm, home, get_calibration, info: no argument
  }
}

}  // namespace

std::string state_name(uint8_t state) {
  return state <= (uint8_t)core::kLastArmState ? core::to_string((core::ArmState)state)
                                                  : "unknown_" + std::to_string(state);
}
std::string mode_name(uint8_t mode) { return code_name(mode, kModeNames); }
std::string calibration_name(uint8_t calibration) { return code_name(calibration, kCalibrationNames); }
std::string status_name(uint8_t status) { return code_name(status, kStatusNames); }
std::vector<std::string> fault_names(uint32_t faults) { return bit_names(faults, core::kFaultNames); }
std::vector<std::string> reset_cause_names(uint8_t mcusr) { return bit_names(mcusr, kResetCauseNames); }
std::vector<std::string> slow_reason_names(uint8_t slowed_by) { return bit_names(slowed_by, kSlowReasonNames); }
std::vector<std::string> switch_names(uint16_t switches) { return bit_names(switches, kSwitchNames); }

const char* type_name(uint8_t type) {
  switch ((MsgType)type) {
    case MsgType::state: return "state";
    case MsgType::reply: return "reply";
    case MsgType::boot: return "boot";
    case MsgType::calibration: return "calibration";
    case MsgType::info: return "info";
    case MsgType::cmd_stop: return "stop";
    case MsgType::cmd_rearm: return "rearm";
    case MsgType::cmd_mode: return "mode";
    case MsgType::cmd_speed_scale: return "speed_scale";
    case MsgType::cmd_home: return "home";
    case MsgType::cmd_goto_pose: return "goto_pose";
    case MsgType::cmd_store_pose: return "store_pose";
    case MsgType::cmd_velocity: return "velocity";
    case MsgType::cmd_pot_calibration: return "pot_calibration";
    case MsgType::cmd_get_calibration: return "get_calibration";
    case MsgType::cmd_stick_centre: return "stick_centre";
    case MsgType::cmd_info: return "get_info";
    case MsgType::cmd_jog: return "jog";
  }
  return nullptr;
}

bool FrameStream::next() {
  if (!parser_.next()) return false;
  ++frames_;
  const Frame& f = parser_.frame();
  if (!is_command(f.type)) {
    if (last_seq_ >= 0 && f.type != (uint8_t)MsgType::boot) {
      const uint8_t missing = (uint8_t)(f.seq - last_seq_ - 1);
      missing_frames_ += missing;
      seq_gaps_ += missing != 0;
    }
    last_seq_ = f.seq;
  }
  return true;
}

std::string FrameStream::summary() const {
  return "frames " + std::to_string(frames_) + ", crc errors " + std::to_string(parser_.crc_errors()) +
         ", framing errors " + std::to_string(parser_.framing_errors()) + ", skipped bytes " +
         std::to_string(parser_.skipped_bytes()) + ", seq gaps " + std::to_string(seq_gaps_);
}

std::string to_json(const Frame& f) {
  Object o;
  const char* name = type_name(f.type);
  if (!name) {
    o.str("type", "unknown");
    o.num("type_id", f.type);
    o.num("seq", f.seq);
    o.str("payload", to_hex(f.payload, f.len));
    return o.done();
  }
  const bool command = is_command(f.type);
  o.str("type", command ? "command" : name);
  if (command) o.str("command", name);
  o.num("seq", f.seq);
  const protocol::ReplyStatus status = command ? protocol::check_command(f) : protocol::ReplyStatus::ok;
  if (command && status == protocol::ReplyStatus::ok) {
    add_command_argument(o, f);
  } else if (command || !add_report(o, f)) {
    o.str("error", command ? status_name((uint8_t)status) : "bad_length");
    o.str("payload", to_hex(f.payload, f.len));
  }
  return o.done();
}

std::string version_text(const protocol::Identity& id) {
  return std::to_string(id.version[0]) + "." + std::to_string(id.version[1]) + "." + std::to_string(id.version[2]);
}

std::string to_hex(const uint8_t* bytes, size_t n) {
  static const char kDigits[] = "0123456789abcdef";
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    s += kDigits[bytes[i] >> 4];
    s += kDigits[bytes[i] & 15];
  }
  return s;
}

}  // namespace telemetry
}  // namespace wmra
