// Runs one pose's stick tests on the firmware: the pose stored in slot 1 of the EEPROM before
// power-up, the arm started as a person starts it, then for each test a move to the pose (a
// re-arm first if a test ended stopped; the stick turned back for a moment if a test ended on a
// limit switch, from which the firmware refuses a move), the stick's profile, and the plant's
// true joint angles every 10 ms.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "config/joints_config.h"
#include "core/joint_map.h"
#include "firmware_rig.h"
#include "sweep_figures.h"

namespace wmra {
namespace sweep {

struct TestResult {
  int pose = 0;
  StickTest test;
  bool reached = false;  // the arm came to rest at the pose before the test
  long long move_lost_steps = 0;  // microsteps lost on the way back to the pose before it
  Figures figures;
};

inline app::Settings settings_with_pose(const Joints& q) {
  app::Settings s{};  // no joint calibrated by a person: joints_config.h's calibration
  for (int j = 0; j < 6; ++j) {
    s.pose_angle[0][j] = (int32_t)std::llround(arm::deg_to_rad(config::kReadyPose_deg[j]) * core::kAngleCountsPerRad);
    s.pose_angle[1][j] = (int32_t)std::llround(q[j] * core::kAngleCountsPerRad);
  }
  s.pose_valid = 0x03;
  return s;
}

class PoseRun {
 public:
  PoseRun(const std::string& elf, uint32_t noise_seed, int pose_index, const Joints& pose)
      : rig_(config(elf, noise_seed)), pose_index_(pose_index), pose_(pose) {
    rig_.sim.set_eeprom(test::settings_block(settings_with_pose(pose)));
    rig_.sim.every(kSample_s, [this](const sim::ArmSimulator& s) {
      if (!recording_) return;
      samples_.push_back(s.q());
      rig_.feed_telemetry();
      const protocol::StateMsg* state = rig_.telemetry.last_state();
      slowed_by_.push_back(state ? state->slowed_by : 0);
    });
  }

  bool start() { return rig_.start(15.0) >= 0; }
  // the last test's samples of the plant's true joint angles, every kSample_s from its start
  const std::vector<plant::Joints>& samples() const { return samples_; }
  // and the firmware's slowed_by (core::kSlow*) of its last state frame at each sample
  const std::vector<uint8_t>& slowed_by() const { return slowed_by_; }

  TestResult run(const StickTest& test) {
    TestResult r;
    r.pose = pose_index_;
    r.test = test;
    const long long lost_before_move = lost_steps();
    r.reached = back_to_pose(test.mode);
    r.move_lost_steps = lost_steps() - lost_before_move;
    last_x_ = test.x2;
    last_y_ = test.y2;
    if (!r.reached) return r;
    const long long lost_before = lost_steps();
    samples_.clear();
    slowed_by_.clear();
    recording_ = true;
    const double t0 = rig_.sim.time_s();
    rig_.sim.set_joystick(test.x, test.y);
    if (test.reversal()) {
      rig_.run_to(t0 + kReverseAt_s);
      rig_.sim.set_joystick(test.x2, test.y2);
    }
    rig_.run_to(t0 + kDrive_s);
    rig_.sim.set_joystick(0, 0);
    rig_.run_to(t0 + kDrive_s + kAfter_s + kSample_s / 2);
    recording_ = false;
    std::vector<Joints> q(samples_.begin(), samples_.end());
    r.figures = figures(test, q, lost_steps() - lost_before);
    return r;
  }

 private:
  static sim::SimConfig config(const std::string& elf, uint32_t noise_seed) {
    sim::SimConfig c = test::Rig::config(elf, test::kNearHome, false);
    c.plant.seed = noise_seed;
    return c;
  }

  long long lost_steps() const {
    const sim::Measurements m = rig_.sim.measurements();
    long long n = 0;
    for (const auto& s : m.steps) n += s.lost;
    return n;
  }

  void send(protocol::MsgType type, std::vector<uint8_t> payload) {
    rig_.sim.send_serial(test::command(type, seq_++, payload));
    rig_.run_to(rig_.sim.time_s() + 0.05);
  }

  // Re-armed if a test ended stopped, in `mode`, moved to the pose and at rest there (every joint
  // within 1 mrad of where it was 0.1 s before, for 0.3 s); false after 20 s without
  bool back_to_pose(config::Mode mode) {
    if (rig_.state() == core::ArmState::stopped || rig_.state() == core::ArmState::fault) {
      send(protocol::MsgType::cmd_rearm, {});
      rig_.run_to(rig_.sim.time_s() + 0.5);
    }
    if (rig_.state() != core::ArmState::running) return false;
    send(protocol::MsgType::cmd_mode, {(uint8_t)last_mode_});
    for (int attempt = 0; attempt < 3; ++attempt) {
      send(protocol::MsgType::cmd_goto_pose, {1});
      const auto& replies = rig_.telemetry.replies();
      if (!replies.empty() && replies.back().status == (uint8_t)protocol::ReplyStatus::ok) break;
      // on a limit switch (a refused move): the last test's stick the other way, briefly
      rig_.sim.set_joystick(-last_x_, -last_y_);
      rig_.run_to(rig_.sim.time_s() + 0.5);
      rig_.sim.set_joystick(0, 0);
      rig_.run_to(rig_.sim.time_s() + 0.5);
    }

    const double t_end = rig_.sim.time_s() + 20.0;
    plant::Joints before = rig_.sim.q();
    double still_s = 0;
    while (rig_.sim.time_s() < t_end) {
      rig_.run_to(rig_.sim.time_s() + 0.1);
      const plant::Joints now = rig_.sim.q();
      bool still = true;
      for (int j = 0; j < 6; ++j) still &= std::fabs(now[j] - before[j]) < 1e-3;
      before = now;
      still_s = still ? still_s + 0.1 : 0;
      if (still_s >= 0.3 && rig_.state() == core::ArmState::running) {
        send(protocol::MsgType::cmd_mode, {(uint8_t)mode});
        last_mode_ = mode;
        return at_pose(now);
      }
    }
    return false;
  }

  // within the moves' arrival tolerance of the stored pose (1 deg; the DC joints' pots)
  bool at_pose(const plant::Joints& q) const {
    for (int j = 0; j < 6; ++j)
      if (std::fabs(q[j] - pose_[j]) > arm::deg_to_rad(2.0)) return false;
    return true;
  }

  test::Rig rig_;
  int pose_index_;
  Joints pose_;
  uint8_t seq_ = 0;
  double last_x_ = 0, last_y_ = 0;             // the last test's final stick
  config::Mode last_mode_ = config::Mode::xy;  // and its mode
  bool recording_ = false;
  std::vector<plant::Joints> samples_;
  std::vector<uint8_t> slowed_by_;
};

}  // namespace sweep
}  // namespace wmra
