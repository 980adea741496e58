#include "frame_text.h"

#include <cstdio>

#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

namespace {

constexpr double kDegPerMrad = 0.180 / 3.14159265358979323846;

std::string joined(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ",") + n;
  return s;
}

std::string format(const char* f, double a, double b = 0) {
  char s[64];
  std::snprintf(s, sizeof s, f, a, b);
  return s;
}

// "firmware 0.7.0, commit 85e4ee73d90a (clean), config f67e1bfa"
std::string identity_text(const protocol::Identity& id) {
  const char* tree = id.build_flags & protocol::kBuildCommitUnknown ? "not built from git"
                     : id.build_flags & protocol::kBuildTreeChanged ? "with changes"
                                                                     : "clean";
  char hash[9];
  std::snprintf(hash, sizeof hash, "%08lx", (unsigned long)id.config_hash);
  return "firmware " + telemetry::version_text(id) + ", commit " + telemetry::to_hex(id.commit, sizeof id.commit) +
         " (" + tree + "), config " + hash;
}

std::vector<std::string> info_lines(const protocol::InfoMsg& m) {
  std::string speeds = "info: joint speed limits deg/s:";
  std::string limits = "info: soft limits deg:";
  for (int j = 0; j < 6; ++j) {
    speeds += format(" %.1f", m.joint_speed_mrad_s[j] * kDegPerMrad);
    limits += "  J" + std::to_string(j + 1) + format(" %.1f..%.1f", m.soft_min_mrad[j] * kDegPerMrad, m.soft_max_mrad[j] * kDegPerMrad);
  }
  return {"info: " + identity_text(m.identity) + "; loop " + std::to_string(m.loop_hz) + " Hz",
          "info: hand " + std::to_string(m.hand_speed_mm_s) + " mm/s, wrist " +
              format("%.1f deg/s", m.wrist_speed_mrad_s * kDegPerMrad) + " at full stick",
          speeds, limits};
}

std::vector<std::string> calibration_lines(const protocol::CalibrationMsg& m) {
  std::string line = "calibration (pot counts x 16 at the lower..upper limit, now):";
  for (int d = 0; d < 3; ++d) {
    line += "  J" + std::to_string(d + 2) + " " + std::to_string(m.at_min_counts_x16[d]) + ".." +
            std::to_string(m.at_max_counts_x16[d]) + " now " + std::to_string(m.reading_counts_x16[d]) +
            (m.from_command >> d & 1 ? " (set)" : " (config)");
  }
  return {line};
}

}  // namespace

std::string status_line(const protocol::StateMsg& s) {
  char head[64];
  std::snprintf(head, sizeof head, "%7.2f s  %-12s %-7s  faults: ", s.t_ms / 1000.0, telemetry::state_name(s.state).c_str(),
                telemetry::mode_name(s.mode).c_str());
  std::string line = head + joined(telemetry::fault_names(s.faults)) + "  switches: " +
                     joined(telemetry::switch_names(s.switches)) + "  q deg:";
  for (int16_t q : s.q_mrad) line += format(" %.1f", q * kDegPerMrad);
  return line;
}

std::vector<std::string> report_lines(const protocol::Frame& f) {
  protocol::BootMsg boot;
  protocol::InfoMsg info;
  protocol::CalibrationMsg calibration;
  if (protocol::decode(f, boot)) {
    return {"boot: " + identity_text(boot.identity) + "; reset: " + joined(telemetry::reset_cause_names(boot.reset_cause)) +
            "; settings: " + telemetry::calibration_name((uint8_t)boot.settings()) +
            "; j6 angle: " + (boot.j6_angle_recorded() ? "recorded" : "none")};
  }
  if (protocol::decode(f, info)) return info_lines(info);
  if (protocol::decode(f, calibration)) return calibration_lines(calibration);
  return {};
}

}  // namespace telemetry_cli
}  // namespace wmra
