// armsim's decoder of the firmware's telemetry (firmware/protocol, docs/telemetry.md): the
// mode, state and faults for trajectory.csv and summary.json, and every decoded message for
// scenario tests that check what the firmware said.
#pragma once

#include <string>
#include <vector>

#include "armsim/run.h"
#include "protocol/messages.h"
#include "telemetry_json.h"

namespace wmra {
namespace armsim {

class FirmwareTelemetry : public TelemetryDecoder {
 public:
  void feed(uint8_t byte) override;
  int mode() const override;   // of the latest state frame; -1 before the first
  int state() const override;  // core::ArmState value, likewise
  // every fault the state frames ever reported, in the order they first appeared
  std::vector<std::string> faults() const override { return faults_; }
  TelemetrySummary summary() const override;

  const protocol::StateMsg* last_state() const { return states_.empty() ? nullptr : &states_.back(); }
  const std::vector<protocol::StateMsg>& states() const { return states_; }  // all of them, in order
  const std::vector<protocol::ReplyMsg>& replies() const { return replies_; }
  const std::vector<protocol::BootMsg>& boots() const { return boots_; }
  const std::vector<protocol::CalibrationMsg>& calibrations() const { return calibrations_; }
  const std::vector<protocol::InfoMsg>& infos() const { return infos_; }
  const telemetry::FrameStream& stream() const { return stream_; }  // frames, parser errors, seq gaps

 private:
  void take(const protocol::Frame& f);  // a frame into the lists

  telemetry::FrameStream stream_;
  std::vector<protocol::StateMsg> states_;
  std::vector<protocol::ReplyMsg> replies_;
  std::vector<protocol::BootMsg> boots_;
  std::vector<protocol::CalibrationMsg> calibrations_;
  std::vector<protocol::InfoMsg> infos_;
  uint32_t faults_seen_ = 0;
  std::vector<std::string> faults_;
};

}  // namespace armsim
}  // namespace wmra
