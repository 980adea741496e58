#include "armsim/firmware_telemetry.h"

namespace wmra {
namespace armsim {

void FirmwareTelemetry::feed(uint8_t byte) {
  stream_.push(byte);
  while (stream_.next()) take(stream_.frame());
}

void FirmwareTelemetry::take(const protocol::Frame& f) {
  protocol::StateMsg state;
  protocol::ReplyMsg reply;
  protocol::BootMsg boot;
  protocol::CalibrationMsg calibration;
  protocol::InfoMsg info;
  if (protocol::decode(f, state)) {
    states_.push_back(state);
    for (const std::string& name : telemetry::fault_names(state.faults & ~faults_seen_)) faults_.push_back(name);
    faults_seen_ |= state.faults;
  } else if (protocol::decode(f, reply)) {
    replies_.push_back(reply);
  } else if (protocol::decode(f, boot)) {
    boots_.push_back(boot);
  } else if (protocol::decode(f, calibration)) {
    calibrations_.push_back(calibration);
  } else if (protocol::decode(f, info)) {
    infos_.push_back(info);
  }
}

int FirmwareTelemetry::mode() const { return states_.empty() ? -1 : states_.back().mode; }
int FirmwareTelemetry::state() const { return states_.empty() ? -1 : states_.back().state; }

TelemetrySummary FirmwareTelemetry::summary() const {
  TelemetrySummary s;
  s.frames = stream_.frames();
  s.crc_errors = stream_.parser().crc_errors();
  s.seq_gaps = stream_.seq_gaps();
  s.replies = replies_.size();
  for (const protocol::BootMsg& b : boots_) {
    std::string causes;
    for (const std::string& name : telemetry::reset_cause_names(b.reset_cause)) causes += (causes.empty() ? "" : "+") + name;
    s.boot_reset_causes.push_back(causes.empty() ? "none" : causes);
  }
  return s;
}

}  // namespace armsim
}  // namespace wmra
