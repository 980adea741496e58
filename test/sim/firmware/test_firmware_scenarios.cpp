// The firmware ELF against the virtual arm: start-up, and the safety scenarios (docs/arm-guide.md, safety; docs/design.md)
// (S5 safety button, S10 watchdog). The firmware's state comes from its own
// telemetry, decoded with firmware/protocol; the arm's from the plant.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/control_config.h"
#include "config/joints_config.h"
#include "core/faults.h"
#include "core/joint_map.h"
#include "core/resolved_rate.h"
#include "atmega2560.h"
#include "drivers/steppers.h"
#include "drivers/system_tick.h"
#include "drivers/watchdog.h"
#include "firmware_rig.h"
#include "kinematics/arm_model.h"
#include "plant/arm_plant_config.h"
#include "wiring/timer_decode.h"
#include "wmra_mega/board.h"

namespace {

using namespace wmra;
using test::Rig;
using test::command;
using test::distance_mm;
using test::kFirmware;
using test::kTestFirmware;

TEST(FirmwareStartUp, HomesAndReachesTheReadyPose) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0) << "the firmware did not reach running; last state "
                          << core::to_string(rig.state());
  ASSERT_FALSE(rig.telemetry.boots().empty());
  EXPECT_EQ(rig.telemetry.boots()[0].reset_cause & 8, 0) << "not a watchdog reset at power-up";
  rig.run_to(t_running + 0.5);
  // the firmware's joint angles (steppers from homing and step counts, DC from pots) against the plant
  const protocol::StateMsg& s = rig.last();
  const plant::Joints q = rig.sim.q();
  // DC joints, in counts of their pot: simavr truncates the millivolts (0.2 count) and the count
  // (1), scales by 1023 where the firmware uses the datasheet's 1024 (up to 0.95 count), and the
  // pot's noise is in the one conversion read (4 sigma)
  const double pot_counts = (config::kPotAtMax_mV - config::kPotAtMin_mV) * 1024.0 / config::kAdcRef_mV;
  const double noise_counts = 4 * plant::kPotNoiseMv * 1023 / plant::kAdcRefMv;
  const double dc_tolerance_counts = 0.2 + 1 + 0.95 + noise_counts;
  for (int j = 0; j < 6; ++j) {
    const double count_mrad = 1000 * (arm::q_max_rad(j) - arm::q_min_rad(j)) / pot_counts;
    const double tolerance_mrad = (j == 0 || j >= 4) ? 3.0 : dc_tolerance_counts * count_mrad;
    EXPECT_NEAR(s.q_mrad[j], q[j] * 1000.0, tolerance_mrad) << "joint " << j + 1;
  }
  // off the singular J5 = -90 deg, at the configured ready pose (70, 20, -70, 50, -30, 0 deg)
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0};
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(q[j] * 180 / M_PI, ready_deg[j], 1.5) << "joint " << j + 1;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].lost, 0);
  EXPECT_TRUE(rig.sim.measurements().sim_faults.empty());
}

// The safety button in the first milliseconds of the move to the ready pose (J5 just off its
// singular home, the steppers slow enough to keep their counts): the re-arm makes the move
// again, homing kept, and the arm runs from the ready pose, not from where the move stopped.
// The move's first step is found in a first run (the state frames come every 20 ms): J5, at
// rest after its homing, steps again.
TEST(FirmwareStartUp, AMoveToTheReadyPoseCutShortIsMadeAgainAfterTheRearm) {
  double t_reported = 0;
  {
    Rig first(kFirmware);
    ASSERT_GT(first.ask_home(12.0), 0);
    t_reported = first.run_until_state(core::ArmState::to_ready, 12.0);
    ASSERT_GT(t_reported, 0);
  }
  Rig rig(kFirmware);
  ASSERT_GT(rig.ask_home(12.0), 0);
  rig.run_to(t_reported - 0.05);
  const int64_t j5_at_rest = rig.sim.measurements().steps[1].commanded;
  double t_press = -1;
  while (t_press < 0 && rig.sim.time_s() < t_reported) {
    rig.run_to(rig.sim.time_s() + 0.0005);
    if (rig.sim.measurements().steps[1].commanded != j5_at_rest) t_press = rig.sim.time_s();
  }
  ASSERT_GT(t_press, t_reported - 0.045) << "J5 at rest before the move";
  rig.sim.set_estop(true);
  rig.run_to(t_press + 0.3);
  ASSERT_EQ(rig.state(), core::ArmState::stopped);
  const double q5_stopped_deg = rig.sim.q()[4] * 180 / M_PI;
  rig.sim.set_estop(false);
  rig.run_to(rig.sim.time_s() + 0.1);
  const size_t first = rig.telemetry.states().size();
  rig.sim.send_serial(command(protocol::MsgType::cmd_rearm, 1));
  ASSERT_GT(rig.run_until_state(core::ArmState::running, rig.sim.time_s() + 12.0), 0);
  bool homing = false, to_ready = false;
  for (size_t i = first; i < rig.telemetry.states().size(); ++i) {
    homing |= rig.telemetry.states()[i].state == (uint8_t)core::ArmState::homing;
    to_ready |= rig.telemetry.states()[i].state == (uint8_t)core::ArmState::to_ready;
  }
  std::printf("the safety button at J5's first step of the move (%.1f ms before to_ready was reported), J5 stopped at %.2f "
              "deg; after the re-arm: homing %d, to_ready %d\n",
              (t_reported - t_press) * 1e3, q5_stopped_deg, homing, to_ready);
  EXPECT_FALSE(homing) << "the steppers kept their counts";
  EXPECT_TRUE(to_ready) << "the move to the ready pose made again";
  rig.run_to(rig.sim.time_s() + 0.3);
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0};
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(rig.sim.q()[j] * 180 / M_PI, ready_deg[j], 1.5) << "joint " << j + 1;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].lost, 0);
}

// S5: the safety button's stop, from its interrupt. The bridges brake (duty 0) within
// 100 us; each stepper's train ends or slows down to an end (never faster after its first ms),
// its driver enabled: the arm holds where it stopped, the hand within 10 mm of where it was at
// the press; nothing moves while stopped and nothing is driven until the button is released and
// the arm re-armed. The drivers held the steppers, so their counts are their angles: the re-arm
// goes on without homing, and the firmware's stepper angles are the joints'.
TEST(FirmwareSafety, S5SafetyButtonHoldsTheArmUntilReleasedAndRearmed) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  rig.sim.set_joystick(-1.0, 0.0);
  rig.run_to(t_running + 0.8);
  const armsim::TrajectoryRow at_press = rig.pose();
  rig.sim.set_estop(true);
  double hand_mm = 0;
  for (double t = t_running + 0.8; t < t_running + 1.8; t += 0.002) {
    rig.run_to(t);
    hand_mm = std::max(hand_mm, distance_mm(rig.pose().p, at_press.p));
    EXPECT_TRUE(rig.sim.drivers_enabled()) << "the steppers' drivers stay enabled, at " << t;
  }
  const sim::Measurements m = rig.sim.measurements();
  ASSERT_EQ(m.estop.size(), 1u);
  ASSERT_GE(m.estop[0].bridges_off_s, 0) << "the bridges still driven";
  const double latency_s = m.estop[0].bridges_off_s - m.estop[0].pressed_s;
  EXPECT_LE(latency_s, 100e-6);  // from the button's interrupt, not the next control tick
  RecordProperty("estop_latency_us", std::to_string(latency_s * 1e6));
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(m.estop[0].trains[k].sped_up) << "stepper " << k;
  const double trains_ms = 1000 * (m.estop[0].trains_stopped_s() - m.estop[0].pressed_s);
  std::printf("S5: bridges braking after %.1f us, steppers at rest after %.1f ms (%lld, %lld, %lld steps), hand %.2f mm\n",
              latency_s * 1e6, trains_ms, (long long)m.estop[0].trains[0].steps, (long long)m.estop[0].trains[1].steps,
              (long long)m.estop[0].trains[2].steps, hand_mm);
  EXPECT_LE(trains_ms, 200.0);
  EXPECT_LE(hand_mm, 10.0);
  EXPECT_EQ(rig.state(), core::ArmState::stopped);
  const sim::Measurements at_stop = rig.sim.measurements();
  const armsim::TrajectoryRow held = rig.pose();
  rig.sim.set_estop(false);  // released, stick still deflected: nothing driven without a re-arm
  bool driven = false;
  double drift_mm = 0;
  for (double t = t_running + 1.8; t < t_running + 2.8; t += 0.01) {
    rig.run_to(t);
    driven |= !rig.sim.bridges_off();
    drift_mm = std::max(drift_mm, distance_mm(rig.pose().p, held.p));
  }
  EXPECT_FALSE(driven);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].commanded, at_stop.steps[k].commanded);
  std::printf("S5: standstill drift over 1 s after the stop: %.3f mm\n", drift_mm);
  EXPECT_LE(drift_mm, 1.0);
  EXPECT_EQ(rig.state(), core::ArmState::stopped);
  rig.sim.set_joystick(0.0, 0.0);
  rig.sim.send_serial(command(protocol::MsgType::cmd_rearm, 1));
  bool homed_again = false;
  for (double t = rig.sim.time_s(); t < t_running + 5.0 && rig.state() != core::ArmState::running; t += 0.02) {
    rig.run_to(t + 0.02);
    homed_again |= rig.state() == core::ArmState::homing;
  }
  EXPECT_EQ(rig.state(), core::ArmState::running) << "the re-arm did not bring it back";
  EXPECT_FALSE(homed_again) << "the held steppers kept their counts";
  rig.run_to(rig.sim.time_s() + 0.5);
  for (int j : {0, 4, 5}) EXPECT_NEAR(rig.last().q_mrad[j], rig.sim.q()[j] * 1000.0, 5.0) << "joint " << j + 1;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].lost, 0);
}

// The safety button's stop is "latched until released and re-armed", whatever the phase
// of the control loop the press lands in. A press while an iteration runs, after it has read the
// button and before its DC servos' run, must not let that run switch a bridge's PWM on again,
// nor its steppers' service start or speed up a train. The press swept over two ticks (a drives'
// slot and a motion pass) in 50 us steps, the hand driven along +x; each press watched every
// 10 us for 3 ms (the next iteration has entered stopped by then).
TEST(FirmwareSafety, SafetyButtonOutputsStayOffWhateverThePhaseOfTheLoop) {
  std::vector<std::string> redriven;
  for (int k = 0; k < 40; ++k) {
    Rig rig(kFirmware);
    const double t_running = rig.start(12.0);
    ASSERT_GT(t_running, 0);
    rig.sim.set_joystick(1.0, 0.0);
    const double t_press = std::floor((t_running + 0.5) * 1000.0) / 1000.0 + k * 50e-6;
    rig.run_to(t_press);
    rig.sim.set_estop(true);
    bool off = false;
    double on_again_s = -1, on_until_s = -1;
    for (double t = t_press + 10e-6; t < t_press + 3e-3; t += 10e-6) {
      rig.run_to(t);
      const bool now_off = rig.sim.bridges_off();
      if (off && !now_off) {
        if (on_again_s < 0) on_again_s = t;
        on_until_s = t;
      }
      off |= now_off;
    }
    ASSERT_TRUE(off) << "press at +" << k * 50 << " us: outputs never off";
    for (int i = 0; i < 3; ++i)
      EXPECT_FALSE(rig.sim.measurements().estop[0].trains[i].sped_up) << "press at +" << k * 50 << " us: stepper " << i;
    if (on_again_s >= 0)
      redriven.push_back("press at +" + std::to_string(k * 50) + " us into the ms: driven again " +
                         std::to_string((int)std::lround((on_again_s - t_press) * 1e6)) + " to " +
                         std::to_string((int)std::lround((on_until_s - t_press) * 1e6)) + " us after it");
  }
  for (const std::string& s : redriven) ADD_FAILURE() << s;
}

// S10: a hung main loop (test build) while the stick drives: every output off kStallCut_ms after
// the loop stopped taking its ticks (the tick's ISR, watchdog.h), where the watchdog alone left
// the steppers at their last speed and the bridges at their last duty for its 60 ms; then a
// watchdog reset, the outputs off up to it, and the cause reported.
TEST(FirmwareSafety, S10HangEndsInWatchdogResetReported) {
  Rig rig(kTestFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  rig.sim.set_joystick(1, 0);
  rig.run_to(t_running + 0.5);
  ASSERT_FALSE(rig.sim.outputs_off()) << "the arm driven when the loop hangs";
  const double t_hang_s = rig.sim.time_s();
  double off_s = -1;
  bool on_again = false;  // an output driven again after the cut, before the reset
  rig.sim.every(20e-6, [&](const sim::ArmSimulator& s) {
    if (!s.measurements().resets.empty()) return;
    const bool off = s.outputs_off();
    if (off && off_s < 0) off_s = s.time_s();
    if (!off && off_s >= 0) on_again = true;
  });
  rig.sim.send_serial(command((protocol::MsgType)0x7F, 1));
  rig.run_to(t_hang_s + 0.3);
  const sim::Measurements m = rig.sim.measurements();
  ASSERT_EQ(m.resets.size(), 1u);
  EXPECT_EQ(m.resets[0].cause, "watchdog");
  const double reset_s = m.resets[0].cycle / (double)board::kCpuHz;
  std::printf("hang command sent at %.4f s: outputs off %.2f ms after it, the reset %.2f ms after it\n", t_hang_s,
              (off_s - t_hang_s) * 1e3, (reset_s - t_hang_s) * 1e3);
  // the command's 8 bytes on the line (0.7 ms), the iteration before it is read (1 ms), and the
  // cut at the tick after kStallCut_ms ticks have passed since the hung iteration took its own
  ASSERT_GE(off_s, 0) << "outputs never off before the reset";
  EXPECT_LE(off_s - t_hang_s, (watchdog::kStallCut_ms + 1 + 0.7 + 1) / 1000.0);
  EXPECT_FALSE(on_again);
  EXPECT_TRUE(rig.sim.outputs_off());
  ASSERT_GE(rig.telemetry.boots().size(), 2u);
  EXPECT_NE(rig.telemetry.boots().back().reset_cause & 8, 0) << "the boot frame after the reset names the watchdog";
  EXPECT_NE(rig.state(), core::ArmState::running);
}

// S10 behind the Mega's stock bootloader, which clears MCUSR: the cause inferred from RAM
// (lib/drivers/watchdog.h), power-on at first, then the hang's watchdog reset
TEST(FirmwareSafety, S10BehindTheStockBootloaderTheCauseIsInferred) {
  Rig rig(kTestFirmware, test::kNearHome, true);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  ASSERT_GE(rig.telemetry.boots().size(), 1u);
  EXPECT_EQ(rig.telemetry.boots()[0].reset_cause, 0x80 | 1) << "inferred power-on: no trace in RAM";
  rig.run_to(t_running + 0.5);
  rig.sim.send_serial(command((protocol::MsgType)0x7F, 1));
  rig.run_to(rig.sim.time_s() + 0.3);
  const sim::Measurements m = rig.sim.measurements();
  ASSERT_EQ(m.resets.size(), 1u);
  EXPECT_EQ(m.resets[0].cause, "watchdog");
  ASSERT_GE(rig.telemetry.boots().size(), 2u);
  EXPECT_EQ(rig.telemetry.boots().back().reset_cause, 0x80 | 8) << "inferred watchdog: the stall mark";
  EXPECT_EQ(rig.last().reset_cause, 0x80 | 8);
}

// Sends a command, runs 50 ms and returns its reply's status (the one reply expected)
protocol::ReplyStatus ask_firmware(Rig& rig, uint8_t& seq, protocol::MsgType type, const std::vector<uint8_t>& payload) {
  const size_t replies = rig.telemetry.replies().size();
  rig.sim.send_serial(command(type, seq++, payload));
  rig.run_to(rig.sim.time_s() + 0.05);
  EXPECT_EQ(rig.telemetry.replies().size(), replies + 1);
  return (protocol::ReplyStatus)rig.telemetry.replies().back().status;
}

// A person's pot calibration (cmd_pot_calibration): refused while the drives are on, checked,
// applied at once to the joint's measured angle, kept over a reset, and undone by 0 0.
TEST(FirmwareCalibration, PotCalibrationByCommandIsCheckedKeptAndUndone) {
  using protocol::MsgType;
  using protocol::ReplyStatus;
  Rig rig(kTestFirmware);
  uint8_t seq = 1;
  // the command's reply and, if it was ok, the calibration frame that follows it
  const auto ask = [&](MsgType type, std::vector<uint8_t> payload) { return ask_firmware(rig, seq, type, payload); };
  const auto calibrate = [&](uint8_t joint, int16_t at_min, int16_t at_max) {
    return ask(MsgType::cmd_pot_calibration, {joint, (uint8_t)at_min, (uint8_t)(at_min >> 8), (uint8_t)at_max,
                                              (uint8_t)(at_max >> 8)});
  };
  const int16_t config_min = (int16_t)(config::kPotAtMin_mV * 1024L * 16 / config::kAdcRef_mV);
  const int16_t config_max = (int16_t)(config::kPotAtMax_mV * 1024L * 16 / config::kAdcRef_mV);

  ASSERT_GT(rig.start(12.0), 0);
  ASSERT_EQ(ask(MsgType::cmd_get_calibration, {}), ReplyStatus::ok);
  ASSERT_EQ(rig.telemetry.calibrations().size(), 1u);
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(rig.telemetry.calibrations()[0].at_min_counts_x16[d], config_min);
    EXPECT_EQ(rig.telemetry.calibrations()[0].at_max_counts_x16[d], config_max);
  }
  EXPECT_EQ(rig.telemetry.calibrations()[0].from_command, 0);

  const int16_t new_min = (int16_t)(config_min + 40 * 16);  // J3's lower limit 40 counts higher
  EXPECT_EQ(calibrate(3, new_min, config_max), ReplyStatus::refused) << "the drives are on";
  ASSERT_EQ(ask(MsgType::cmd_stop, {}), ReplyStatus::ok);
  rig.run_to(rig.sim.time_s() + 0.2);
  ASSERT_EQ(rig.state(), core::ArmState::stopped);
  const double q3_before_mrad = rig.last().q_mrad[2];
  EXPECT_EQ(calibrate(5, new_min, config_max), ReplyStatus::bad_argument) << "J5 has no pot";
  EXPECT_EQ(calibrate(3, config_min, (int16_t)(config_min + 599 * 16)), ReplyStatus::bad_argument)
      << "limits under 600 counts apart";
  EXPECT_EQ(calibrate(3, -16, config_max), ReplyStatus::bad_argument) << "below the ADC's range";
  EXPECT_EQ(calibrate(3, 10000, -30000), ReplyStatus::bad_argument) << "a span that overflows 16 bits";
  EXPECT_EQ(calibrate(3, config_min, (int16_t)(1024 * 16)), ReplyStatus::bad_argument) << "above the ADC's range";
  EXPECT_EQ(rig.telemetry.calibrations().size(), 1u) << "a refused change sends no calibration";

  ASSERT_EQ(calibrate(3, new_min, config_max), ReplyStatus::ok);
  ASSERT_EQ(rig.telemetry.calibrations().size(), 2u);
  const protocol::CalibrationMsg& c = rig.telemetry.calibrations().back();
  EXPECT_EQ(c.at_min_counts_x16[1], new_min);
  EXPECT_EQ(c.at_max_counts_x16[1], config_max);
  EXPECT_EQ(c.at_min_counts_x16[0], config_min) << "J2 untouched";
  EXPECT_EQ(c.from_command, 2);
  // J3's measured angle follows the new map from the same reading (J3 is stopped; its pot's
  // noise moves the reading by a count or two between frames)
  rig.run_to(rig.sim.time_s() + 0.05);
  const double q_min = arm::q_min_rad(2) * 1000, q_max = arm::q_max_rad(2) * 1000;
  const double expected_mrad = q_min + (c.reading_counts_x16[1] - new_min) * (q_max - q_min) / (config_max - new_min);
  const double count_mrad = (q_max - q_min) * 16 / (config_max - new_min);
  EXPECT_NEAR(rig.last().q_mrad[2], expected_mrad, 3 * count_mrad);
  EXPECT_GT(std::fabs(rig.last().q_mrad[2] - q3_before_mrad), 10 * count_mrad) << "the angle moved with the map";

  // kept in EEPROM over a reset (a hang: the watchdog), once its bytes are written
  rig.run_to(rig.sim.time_s() + 0.5);
  rig.sim.send_serial(command((MsgType)0x7F, seq++));
  rig.run_to(rig.sim.time_s() + 0.3);
  ASSERT_GE(rig.telemetry.boots().size(), 2u);
  EXPECT_EQ(rig.telemetry.boots().back().settings(), protocol::Calibration::eeprom);
  ASSERT_EQ(ask(MsgType::cmd_get_calibration, {}), ReplyStatus::ok);
  EXPECT_EQ(rig.telemetry.calibrations().back().at_min_counts_x16[1], new_min);
  EXPECT_EQ(rig.telemetry.calibrations().back().from_command, 2);

  // 0 0: back to joints_config.h
  ASSERT_EQ(calibrate(3, 0, 0), ReplyStatus::ok);
  EXPECT_EQ(rig.telemetry.calibrations().back().at_min_counts_x16[1], config_min);
  EXPECT_EQ(rig.telemetry.calibrations().back().from_command, 0);

  // A pot wired reversed (its reading falls as the angle rises): refused, the guide says to swap
  // its outer wires (the servo, its plausibility checks and its tracking work in pot units that
  // rise with the angle).
  EXPECT_EQ(calibrate(3, config_max, config_min), ReplyStatus::bad_argument) << "a reversed pot";
  // Limits that put J3's present reading beyond one of them by more than the pot rail check's
  // margin (kRailMargin_counts): refused; within it (a joint resting on its end stop): taken.
  // With a span of 600 counts only one side fits the ADC's range at a given reading.
  ASSERT_EQ(ask(MsgType::cmd_get_calibration, {}), ReplyStatus::ok);
  const size_t calibrations = rig.telemetry.calibrations().size();
  const int16_t reading = rig.telemetry.calibrations().back().reading_counts_x16[1];
  const int16_t span = 600 * 16, noise = 4 * 16, margin = config::kRailMargin_counts * 16;
  const bool limit_above = reading + margin + noise + span <= 1023 * 16;
  ASSERT_TRUE(limit_above || reading - margin - noise - span >= 0) << "J3 reads " << reading;
  const auto past_reading = [&](int16_t by) {  // limits with the reading `by` beyond the nearer one
    return limit_above ? calibrate(3, (int16_t)(reading + by), (int16_t)(reading + by + span))
                       : calibrate(3, (int16_t)(reading - by - span), (int16_t)(reading - by));
  };
  EXPECT_EQ(past_reading((int16_t)(margin + noise)), ReplyStatus::bad_argument) << "the reading beyond a limit";
  EXPECT_EQ(rig.telemetry.calibrations().size(), calibrations) << "nothing changed";
  EXPECT_EQ(past_reading((int16_t)(margin - noise)), ReplyStatus::ok) << "a joint resting on its end stop";
  EXPECT_EQ(rig.telemetry.calibrations().back().from_command, 2);
  ASSERT_EQ(calibrate(3, 0, 0), ReplyStatus::ok);
}

// Bytes the firmware never read (its 64-byte receive ring full) show in the state frame's
// rx_overruns. A loop that keeps its ticks reads 32 bytes a tick, 2.8 times the line's 11.5, so
// a flood at the full 115200 baud loses nothing; a loop that falls behind loses what arrives
// once the ring is full. Here a test build's command stalls the loop for 8 ms (under the stall
// cut's 10) with a flood of commands behind it: 8 ms of the line is 92 bytes, 63 fit the ring.
TEST(FirmwareLink, ReceiveOverrunsReportedWhenTheLoopFallsBehindAFlood) {
  using protocol::MsgType;
  constexpr int kCommands = 40;              // speed_scale, 8 bytes each
  constexpr double kCommandEvery_s = 0.75e-3;  // 0.69 ms of the line each: as fast as simavr takes them
  constexpr uint8_t kStall_ms = 8;
  Rig rig(kTestFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  const uint8_t pct = rig.last().speed_scale_pct;
  uint8_t seq = 0;
  // returns the commands answered
  const auto flood = [&](bool stall) {
    const size_t replies = rig.telemetry.replies().size();
    if (stall) rig.sim.send_serial(command((MsgType)0x7E, seq++, {kStall_ms}));
    const double t0 = rig.sim.time_s();
    for (int k = 0; k < kCommands; ++k) {
      rig.sim.send_serial(command(MsgType::cmd_speed_scale, seq++, {pct}));
      rig.run_to(t0 + (k + 1) * kCommandEvery_s);
    }
    rig.run_to(rig.sim.time_s() + 0.1);
    return (int)(rig.telemetry.replies().size() - replies) - (stall ? 1 : 0);
  };
  const uint64_t simavr_dropped = rig.sim.measurements().uart_rx_dropped;
  EXPECT_EQ(flood(false), kCommands) << "a flood at the line's rate: every command answered";
  EXPECT_EQ(rig.last().rx_overruns, 0);
  const int answered = flood(true);
  const int overruns = rig.last().rx_overruns;
  const double arrived_in_stall = kStall_ms * 1e-3 * 115200 / 10;
  std::printf("flood behind an %d ms stall: %d of %d commands answered, rx_overruns %d (%.0f bytes arrived in the "
              "stall, the ring holds 63)\n",
              kStall_ms, answered, kCommands, overruns, arrived_in_stall);
  EXPECT_EQ(rig.sim.measurements().uart_rx_dropped, simavr_dropped) << "every byte reached the firmware";
  // the stall counts kStall_ms ticks from within one: it lasts kStall_ms - 1 to kStall_ms ms
  constexpr double kBytesPerMs = 115200 / 10 / 1000.0;
  EXPECT_GE(overruns, (kStall_ms - 1) * kBytesPerMs - 63 - 1);
  EXPECT_LE(overruns, arrived_in_stall - 63 + 1);
  EXPECT_LE(answered, kCommands - overruns / 8) << "each lost byte costs the command it was in";
  EXPECT_EQ(rig.state(), core::ArmState::running);
  // the counter holds (nothing more lost), and the link answers every command again once the
  // replies no longer leave room for the state frames (5 s after the floods dropped one: link.cpp)
  rig.run_to(rig.sim.time_s() + 5.1);
  EXPECT_EQ(flood(false), kCommands);
  EXPECT_EQ(rig.last().rx_overruns, overruns);
}

// A settings block of version 1 (before pot_calibrated, when no command could set a
// calibration): its poses are kept, its calibration is joints_config.h's.
TEST(FirmwareCalibration, VersionOneSettingsKeepTheirPoses) {
  Rig rig(kFirmware);
  app::Settings settings{};
  for (int d = 0; d < 3; ++d) {
    settings.pot_at_min_counts_x16[d] = 1000;  // not the config's 819
    settings.pot_at_max_counts_x16[d] = 15000;
  }
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0}, slot1_deg[6] = {60, 25, -65, 45, -35, 10};
  for (int slot = 0; slot < 4; ++slot)
    for (int j = 0; j < 6; ++j)
      settings.pose_angle[slot][j] = (int32_t)std::llround((slot == 1 ? slot1_deg : ready_deg)[j] * M_PI / 180 * core::kAngleCountsPerRad);
  settings.pose_valid = 0x03;  // slots 0 (the ready pose) and 1
  const std::vector<uint8_t> block = test::settings_block(settings, 1);
  ASSERT_EQ(block.size(), 5u + 109u + 2u);
  rig.sim.set_eeprom(block);

  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  ASSERT_FALSE(rig.telemetry.boots().empty());
  EXPECT_EQ(rig.telemetry.boots()[0].calibration, (uint8_t)protocol::Calibration::eeprom);
  rig.sim.send_serial(command(protocol::MsgType::cmd_get_calibration, 1));
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 2, {1}));
  rig.run_to(t_running + 4.0);
  ASSERT_EQ(rig.telemetry.calibrations().size(), 1u);
  const int16_t config_min = (int16_t)(config::kPotAtMin_mV * 1024L * 16 / config::kAdcRef_mV);
  for (int d = 0; d < 3; ++d) EXPECT_EQ(rig.telemetry.calibrations()[0].at_min_counts_x16[d], config_min);
  ASSERT_EQ(rig.telemetry.replies().size(), 2u);
  EXPECT_EQ(rig.telemetry.replies()[1].status, (uint8_t)protocol::ReplyStatus::ok) << "slot 1 kept";
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(rig.sim.q()[j] * 180 / M_PI, slot1_deg[j], 1.5) << "joint " << j + 1;
}

// A block with a valid CRC whose poses lie beyond the soft stops (no store_pose wrote them):
// the block is kept, its ready pose falls back to the config's, a stored pose one Angle count past
// a soft stop is refused, and one exactly at the stop is kept.
TEST(FirmwareCalibration, PosesBeyondTheSoftStopsAreDropped) {
  Rig rig(kFirmware);
  app::Settings settings{};  // no joint calibrated by a person: joints_config.h's calibration
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0};
  for (int slot = 0; slot < 4; ++slot)
    for (int j = 0; j < 6; ++j) settings.pose_angle[slot][j] = (int32_t)std::llround(ready_deg[j] * M_PI / 180 * core::kAngleCountsPerRad);
  const int32_t j5_stop = core::joint_motion_limits(4).soft_max.raw;  // 3 deg inside J5's +90 deg switch
  settings.pose_angle[0][4] = (int32_t)std::llround(88.5 * M_PI / 180 * core::kAngleCountsPerRad);
  settings.pose_angle[1][4] = j5_stop + 1;
  settings.pose_angle[2][4] = j5_stop;
  settings.pose_valid = 0x07;
  rig.sim.set_eeprom(test::settings_block(settings));

  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  EXPECT_EQ(rig.telemetry.boots()[0].calibration, (uint8_t)protocol::Calibration::eeprom);
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(rig.sim.q()[j] * 180 / M_PI, ready_deg[j], 1.5) << "the config's ready pose: joint " << j + 1;
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));
  rig.run_to(t_running + 1.0);
  ASSERT_EQ(rig.telemetry.replies().size(), 1u);
  EXPECT_EQ(rig.telemetry.replies()[0].status, (uint8_t)protocol::ReplyStatus::refused) << "slot 1 dropped";
  EXPECT_NEAR(rig.sim.q()[4] * 180 / M_PI, ready_deg[4], 1.5) << "J5 did not move";
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 2, {2}));
  rig.run_to(t_running + 5.0);  // 117 deg at half of J5's 1.5 rad/s
  ASSERT_EQ(rig.telemetry.replies().size(), 2u);
  EXPECT_EQ(rig.telemetry.replies()[1].status, (uint8_t)protocol::ReplyStatus::ok) << "slot 2, at the stop, kept";
  EXPECT_NEAR(rig.sim.q()[4] * 180 / M_PI, 87.0, 0.5) << "J5 at its soft stop";
}

// The review's scenario (a hand resting on the stick 4 % off centre at power-up: 18 counts, inside
// the 30 of mid-scale a new board accepts) with the stick's released centre stored
// (cmd_stick_centre): the power-up centre is refused while the stick is held, nothing moves,
// and once it is let go the released centre is taken and the arm holds still. Without the
// stored centre the held stick became the centre and, released, drove the hand 27 mm in 3 s.
TEST(FirmwareStick, HeldAtPowerUpIsRefusedAgainstTheStoredCentre) {
  using protocol::MsgType;
  using protocol::ReplyStatus;
  Rig rig(kTestFirmware);
  uint8_t seq = 1;
  const auto ask = [&](MsgType type, std::vector<uint8_t> payload) { return ask_firmware(rig, seq, type, payload); };
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  rig.sim.set_joystick(0.5, 0.0);
  rig.run_to(t_running + 0.3);
  EXPECT_EQ(ask(MsgType::cmd_stick_centre, {1}), ReplyStatus::refused) << "the stick is pushed";
  rig.sim.set_joystick(0.0, 0.0);
  rig.run_to(rig.sim.time_s() + 1.0);
  ASSERT_EQ(ask(MsgType::cmd_stick_centre, {1}), ReplyStatus::ok) << "released: its centre stored";
  rig.run_to(rig.sim.time_s() + 1.0);  // the block written to EEPROM (3.4 ms a byte)

  // a reset (a hang: the watchdog) and a hand resting on the stick 4 % off centre from then on
  rig.sim.send_serial(command((MsgType)0x7F, seq++));
  rig.sim.set_joystick(0.04, 0.0);
  rig.run_to(rig.sim.time_s() + 0.3);
  ASSERT_GE(rig.telemetry.boots().size(), 2u);
  EXPECT_EQ(rig.telemetry.boots().back().settings(), protocol::Calibration::eeprom);
  const double t_release = rig.sim.time_s() + 5.0;
  bool moved = false, left_wait_neutral = false;
  for (double t = rig.sim.time_s(); t < t_release; t += 0.05) {
    rig.run_to(t);
    moved |= !rig.sim.outputs_off();
    left_wait_neutral |= rig.state() != core::ArmState::wait_neutral && rig.state() != core::ArmState::boot;
  }
  EXPECT_FALSE(moved) << "no output while the stick is held";
  EXPECT_FALSE(left_wait_neutral) << "calibration refused: no homing while the stick is held";

  rig.sim.set_joystick(0.0, 0.0);  // let go
  const double t_running_again = rig.start(t_release + 12.0);
  ASSERT_GT(t_running_again, 0) << "released: calibrated and on to running";
  rig.run_to(t_running_again + 0.5);
  const armsim::TrajectoryRow start = rig.pose();
  for (double t = t_running_again + 0.5; t < t_running_again + 3.5; t += 0.05) {
    rig.run_to(t);
    ASSERT_EQ(rig.last().stick_permille[0], 0) << "at " << t << " s";
    ASSERT_EQ(rig.last().stick_permille[1], 0) << "at " << t << " s";
  }
  EXPECT_LT(distance_mm(rig.pose().p, start.p), 1.0) << "the released stick drives nothing";

  // forgotten: a new board's check again (the held stick is within its 30 counts)
  ASSERT_EQ(ask(MsgType::cmd_stick_centre, {0}), ReplyStatus::ok);
}

// The stick's travel swings around its own centre. One whose centre sits at the tolerance a new
// board accepts, pushed full towards that side, reads inside the rail margins and drives the hand;
// one further off is not taken as a centre (before, 60 counts were: 45 counts off, a full push read
// at the rail, a rail fault in mid-motion).
TEST(FirmwareStick, AFullPushOfAnOffCentreStickIsNoRail) {
  const auto board_with_stick_off_by = [](double counts) {
    sim::SimConfig c = Rig::config(kFirmware, test::kNearHome, false);
    c.plant.stick_centre_offset_mv[0] = counts * plant::kAdcRefMv / 1024;
    return c;
  };
  {
    Rig rig(board_with_stick_off_by(config::kStickCentreTolerance_counts - 3));
    const double t_running = rig.start(12.0);
    ASSERT_GT(t_running, 0) << "a centre within the tolerance is taken";
    const armsim::TrajectoryRow start = rig.pose();
    rig.sim.set_joystick(1.0, 0.0);
    for (double t = t_running; t < t_running + 2.5; t += 0.02) {  // (J1 far out speeds up gently: stop_config.h)
      rig.run_to(t);
      ASSERT_EQ(rig.last().faults & core::fault_mask(core::kFaultBitStickInvalid), 0u) << "at " << t << " s";
    }
    EXPECT_EQ(rig.last().stick_permille[0], 1000) << "a full stick";
    EXPECT_GT(rig.pose().p[0] - start.p[0], 0.1) << "the hand driven along +x";
  }
  {
    Rig rig(board_with_stick_off_by(45));
    rig.run_to(6.0);
    EXPECT_EQ(rig.state(), core::ArmState::wait_neutral) << "a centre 45 counts off is not taken";
  }
}

// A board whose EEPROM has no stored centre (here a version 2 block, from before the stored
// centre: it keeps its calibration) checks the power-up centre against mid-scale as before: the
// stick held 4 % off centre is within the 30 counts, taken as the centre, and the arm runs.
TEST(FirmwareStick, WithoutAStoredCentreTheNominalCheckAsBefore) {
  Rig rig(kFirmware);
  app::Settings settings{};
  const int16_t config_min = (int16_t)(config::kPotAtMin_mV * 1024L * 16 / config::kAdcRef_mV);
  const int16_t config_max = (int16_t)(config::kPotAtMax_mV * 1024L * 16 / config::kAdcRef_mV);
  for (int d = 0; d < 3; ++d) {
    settings.pot_at_min_counts_x16[d] = config_min;
    settings.pot_at_max_counts_x16[d] = config_max;
  }
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0};
  for (int slot = 0; slot < 4; ++slot)
    for (int j = 0; j < 6; ++j) settings.pose_angle[slot][j] = (int32_t)std::llround(ready_deg[j] * M_PI / 180 * core::kAngleCountsPerRad);
  settings.pose_valid = 1;
  settings.pot_calibrated = 0x04;  // J4's set by a person: kept from the version 2 block
  const std::vector<uint8_t> block = test::settings_block(settings, 2);
  ASSERT_EQ(block.size(), 5u + 110u + 2u);
  rig.sim.set_eeprom(block);
  rig.sim.set_joystick(0.04, 0.0);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0) << "the held stick is taken as the centre, as before";
  EXPECT_EQ(rig.telemetry.boots()[0].calibration, (uint8_t)protocol::Calibration::eeprom);
  rig.sim.send_serial(command(protocol::MsgType::cmd_get_calibration, 1));
  rig.run_to(t_running + 0.1);
  ASSERT_EQ(rig.telemetry.calibrations().size(), 1u);
  EXPECT_EQ(rig.telemetry.calibrations()[0].from_command, 0x04);
}

// The ready pose and slot 1 stored (J1 40 deg from the ready pose's 70, J5 -70 from -30); the
// rig run until running, the time returned (-1: never)
double run_with_slot_1_stored(Rig& rig) {
  app::Settings settings{};
  const double ready_deg[6] = {70, 20, -70, 50, -30, 0}, slot1_deg[6] = {40, 20, -70, 50, -70, 0};
  for (int slot = 0; slot < 4; ++slot)
    for (int j = 0; j < 6; ++j)
      settings.pose_angle[slot][j] = (int32_t)std::llround((slot == 1 ? slot1_deg : ready_deg)[j] * M_PI / 180 * core::kAngleCountsPerRad);
  settings.pose_valid = 0x03;
  rig.sim.set_eeprom(test::settings_block(settings));
  return rig.start(12.0);
}

// A move to a stored pose that the person takes over with the stick: the move slows to rest
// along its line, then the stick drives; no step is lost.
TEST(FirmwarePoses, AMoveTakenOverByTheStickBrakesWithoutLosingSteps) {
  Rig rig(kFirmware);
  const double t_running = run_with_slot_1_stored(rig);
  ASSERT_GT(t_running, 0);
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));
  // J1 moving (at the move's pace: the hand at most at the stick's speed, J1 within its stop's
  // bound, ~0.1 rad/s), 0.2 rad to go
  const double t_takeover = t_running + 2.5;
  rig.run_to(t_takeover);
  const double q1_at_takeover = rig.sim.q()[0];
  ASSERT_LT(q1_at_takeover * 180 / M_PI, 65.0) << "J1 is moving";
  rig.sim.set_joystick(1.0, 0.0);
  rig.run_to(t_takeover + 1.0);
  const armsim::TrajectoryRow braked = rig.pose();
  rig.run_to(t_takeover + 2.0);
  EXPECT_EQ(rig.state(), core::ArmState::running);
  EXPECT_GT(distance_mm(rig.pose().p, braked.p), 50.0) << "the stick drives after the brake";
  rig.sim.set_joystick(0.0, 0.0);
  rig.run_to(t_takeover + 3.0);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].lost, 0) << "stepper " << k;
  EXPECT_GT(q1_at_takeover * 180 / M_PI, 40.0) << "taken over before the pose";
}

// A stick at a rail (unplugged, broken) moves nothing until it is valid again. A goto
// or a streamed velocity would move the arm where the person could not take it over (a
// deflection brakes a move, a stick at a rail reads 0): both refused, and a move under way when
// the stick is lost brakes as on a takeover.
TEST(FirmwarePoses, NoMoveNorStreamWithTheStickAtARail) {
  Rig rig(kFirmware);
  const double t_running = run_with_slot_1_stored(rig);
  ASSERT_GT(t_running, 0);
  rig.run_to(t_running + 1.0);  // J1's rotor settled on its last step of the move to the ready pose
  rig.sim.set_joystick_unplugged(true);
  rig.run_to(t_running + 1.1);
  const armsim::TrajectoryRow unplugged = rig.pose();
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));
  protocol::VelocityCmd v{};
  v.v_mm_s[0] = 100;
  for (int k = 0; k < 5; ++k) {
    rig.run_to(t_running + 1.15 + 0.05 * k);
    rig.sim.send_serial(test::message(v, (uint8_t)(2 + k)));
  }
  rig.run_to(t_running + 2.5);
  ASSERT_EQ(rig.telemetry.replies().size(), 6u);
  for (const protocol::ReplyMsg& r : rig.telemetry.replies())
    EXPECT_EQ(r.status, (uint8_t)protocol::ReplyStatus::refused) << "command seq " << (int)r.command_seq;
  EXPECT_LT(distance_mm(rig.pose().p, unplugged.p), 1.0) << "nothing moved";
  EXPECT_EQ(rig.state(), core::ArmState::running);

  // plugged in again: the goto runs; the stick lost on the way brakes it
  rig.sim.set_joystick_unplugged(false);
  rig.run_to(t_running + 3.0);
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 8, {1}));
  const double t_lost = t_running + 5.5;  // (the move at its pace: J1 ~0.1 rad/s)
  rig.run_to(t_lost);
  ASSERT_EQ(rig.telemetry.replies().back().status, (uint8_t)protocol::ReplyStatus::ok);
  const double q1_at_loss_deg = rig.sim.q()[0] * 180 / M_PI;
  ASSERT_LT(q1_at_loss_deg, 65.0) << "J1 is moving to the pose";
  rig.sim.set_joystick_unplugged(true);
  rig.run_to(t_lost + 1.5);
  const double q1_braked_deg = rig.sim.q()[0] * 180 / M_PI;
  rig.run_to(t_lost + 2.5);
  EXPECT_NEAR(rig.sim.q()[0] * 180 / M_PI, q1_braked_deg, 0.2) << "at rest";
  EXPECT_GT(q1_braked_deg, 45.0) << "stopped short of the pose's 40 deg";
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rig.sim.measurements().steps[k].lost, 0) << "stepper " << k;
}

int bytes_differing(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int n = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) n += a[i] != b[i];
  return n;
}

// A board powered up with this EEPROM: how its settings loaded (the boot frame) and where a move
// to slot 1 took the joints (deg); calibration -1 when it never ran
struct SlotOneAfterPowerUp {
  int calibration = -1;
  int goto_status = -1;
  std::array<double, 6> q_deg{};
};
SlotOneAfterPowerUp power_up_and_goto_slot_1(const std::vector<uint8_t>& eeprom) {
  Rig rig(kFirmware);
  rig.sim.set_eeprom(eeprom);
  const double t_running = rig.start(12.0);
  SlotOneAfterPowerUp r;
  if (t_running < 0 || rig.telemetry.boots().empty()) return r;
  r.calibration = (int)rig.telemetry.boots()[0].settings();
  rig.sim.send_serial(command(protocol::MsgType::cmd_goto_pose, 1, {1}));
  rig.run_to(t_running + 5.0);
  if (!rig.telemetry.replies().empty()) r.goto_status = rig.telemetry.replies()[0].status;
  for (int j = 0; j < 6; ++j) r.q_deg[j] = rig.sim.q()[j] * 180 / M_PI;
  return r;
}

// The person stores a pose and switches the chair off while its bytes are being written (3.4 ms
// a byte): the next power-up has the settings of before, the old pose; with the write complete,
// the new one. (With one copy rewritten in place its CRC failed: the defaults, calibration and
// poses lost.) The EEPROM starts as a single block of the firmware before the two copies.
TEST(FirmwareSettings, APowerLossDuringAWriteKeepsTheOldSettings) {
  Rig rig(kFirmware);
  const double t_running = run_with_slot_1_stored(rig);
  ASSERT_GT(t_running, 0);
  rig.run_to(t_running + 0.1);
  const std::vector<uint8_t> before = rig.sim.eeprom();
  rig.sim.send_serial(command(protocol::MsgType::cmd_store_pose, 1, {1}));  // slot 1: the ready pose, where the arm stands
  // the write's first byte, then 5 ms more (one or two bytes more)
  double t = rig.sim.time_s();
  while (bytes_differing(rig.sim.eeprom(), before) == 0 && t < t_running + 0.3) rig.run_to(t += 0.001);
  rig.run_to(t + 0.005);
  const std::vector<uint8_t> part = rig.sim.eeprom();
  rig.run_to(t + 1.0);
  ASSERT_EQ(rig.telemetry.replies().size(), 1u);
  ASSERT_EQ(rig.telemetry.replies()[0].status, (uint8_t)protocol::ReplyStatus::ok);
  const std::vector<uint8_t> whole = rig.sim.eeprom();
  const int written = bytes_differing(part, before), to_write = bytes_differing(whole, before);
  EXPECT_GE(written, 2);
  EXPECT_LT(written, to_write) << "the power lost in the middle of the write";

  const double old_deg[6] = {40, 20, -70, 50, -70, 0}, new_deg[6] = {70, 20, -70, 50, -30, 0};
  const SlotOneAfterPowerUp lost = power_up_and_goto_slot_1(part);
  EXPECT_EQ(lost.calibration, (int)protocol::Calibration::eeprom) << "not the defaults";
  EXPECT_EQ(lost.goto_status, (int)protocol::ReplyStatus::ok);
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(lost.q_deg[j], old_deg[j], 1.5) << "the old pose: joint " << j + 1;
  const SlotOneAfterPowerUp kept = power_up_and_goto_slot_1(whole);
  EXPECT_EQ(kept.calibration, (int)protocol::Calibration::eeprom);
  EXPECT_EQ(kept.goto_status, (int)protocol::ReplyStatus::ok);
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(kept.q_deg[j], new_deg[j], 1.5) << "the new pose: joint " << j + 1;
}

// A burst of saves (a pose stored every 25 ms while the stick drives the hand): each restarts the
// write. Powered off in the middle of a write of the burst the board keeps valid settings (not
// the defaults); after the last write, the newest pose.
TEST(FirmwareSettings, ABurstOfSavesEndsInTheNewestSettings) {
  Rig rig(kFirmware);
  const double t_running = run_with_slot_1_stored(rig);
  ASSERT_GT(t_running, 0);
  rig.sim.set_joystick(1.0, 0.0);
  constexpr int kStores = 60;
  std::vector<uint8_t> mid;
  std::array<double, 6> first_deg{}, last_deg{};
  for (int k = 0; k < kStores; ++k) {
    if (k == kStores - 20) rig.sim.set_joystick(0.0, 0.0);  // the last stores at rest: the pose sent is the one stored
    rig.run_to(t_running + 0.5 + 0.025 * k);
    std::array<double, 6>& q = k == 0 ? first_deg : last_deg;
    for (int j = 0; j < 6; ++j) q[j] = rig.last().q_mrad[j] * 0.180 / M_PI;  // the firmware's measured angles
    rig.sim.send_serial(command(protocol::MsgType::cmd_store_pose, (uint8_t)(k + 1), {1}));
    if (k == kStores / 2) {  // powered off 6 ms into this store's write
      const std::vector<uint8_t> before = rig.sim.eeprom();
      rig.run_to(rig.sim.time_s() + 0.006);
      mid = rig.sim.eeprom();
      ASSERT_GT(bytes_differing(mid, before), 0) << "the write under way";
    }
  }
  rig.sim.set_joystick(0.0, 0.0);
  rig.run_to(rig.sim.time_s() + 2.0);  // the last write complete (a whole copy: 122 bytes, 0.42 s)
  ASSERT_EQ(rig.telemetry.replies().size(), (size_t)kStores);
  for (const protocol::ReplyMsg& r : rig.telemetry.replies()) EXPECT_EQ(r.status, (uint8_t)protocol::ReplyStatus::ok);
  double differ_deg = 0;
  for (int j = 0; j < 6; ++j) differ_deg = std::max(differ_deg, std::fabs(last_deg[j] - first_deg[j]));
  ASSERT_GT(differ_deg, 5.0) << "the stored poses differ";

  const SlotOneAfterPowerUp mid_burst = power_up_and_goto_slot_1(mid);
  EXPECT_EQ(mid_burst.calibration, (int)protocol::Calibration::eeprom) << "not the defaults";
  EXPECT_EQ(mid_burst.goto_status, (int)protocol::ReplyStatus::ok);
  const SlotOneAfterPowerUp after = power_up_and_goto_slot_1(rig.sim.eeprom());
  EXPECT_EQ(after.calibration, (int)protocol::Calibration::eeprom);
  EXPECT_EQ(after.goto_status, (int)protocol::ReplyStatus::ok);
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(after.q_deg[j], last_deg[j], 1.5) << "the newest pose: joint " << j + 1;
}

// A streamed velocity that stops arriving stops the arm. The stream's command lapses
// kVelocityTimeout_ms after its last frame (the stream's 100 ms timeout); from there the joints'
// commanded velocities (the state frames') fall as the stick's do when it is let go, over
// kStickFall_ms (an instant stop would cost J1's stepper steps), to below the standing speed
// (what is left is the drift correction's trickle, a few mrad/s at most). The hand then swings
// a few mm on J1's stepper (the plant's rotor on its magnetic spring) and comes to rest.
TEST(FirmwareSafety, AStreamThatStopsArrivingStopsTheArm) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  protocol::VelocityCmd v{};
  v.v_mm_s[0] = -100;
  double t_last = 0;
  for (int k = 0; k < 20; ++k) {  // a frame every 50 ms for 1 s
    t_last = t_running + 0.5 + 0.05 * k;
    rig.run_to(t_last);
    rig.sim.send_serial(test::message(v, (uint8_t)(1 + k)));
  }
  auto fastest_mrad_s = [&] {
    int fastest = 0;
    for (int16_t qd : rig.last().qd_mrad_s) fastest = std::max(fastest, std::abs((int)qd));
    return fastest;
  };
  const double timeout_s = protocol::kVelocityTimeout_ms / 1000.0;
  rig.run_to(t_last + timeout_s - 0.02);  // (a state frame every 20 ms)
  const int streaming = fastest_mrad_s();
  rig.run_to(t_last + timeout_s);
  const armsim::TrajectoryRow lapsed = rig.pose();
  double t_zero = -1;
  for (double t = t_last + timeout_s; t < t_last + 1.0 && t_zero < 0; t += 0.02) {
    rig.run_to(t);
    if (fastest_mrad_s() < config::kDcStandingSpeed_mrad_s) t_zero = t - t_last;
  }
  rig.run_to(t_last + 2.0);
  const armsim::TrajectoryRow rest = rig.pose();
  rig.run_to(t_last + 2.1);
  std::printf("stream stopped: fastest joint %d mrad/s at the timeout, every joint below the standing speed %.2f s after the last frame; "
              "at rest %.1f mm from where the command lapsed\n",
              streaming, t_zero, distance_mm(rest.p, lapsed.p));
  EXPECT_GT(streaming, 50) << "the stream drove the arm until its timeout";
  EXPECT_GT(t_zero, 0) << "every commanded joint velocity down to the standing speed";
  EXPECT_LE(t_zero, timeout_s + config::kStickFall_ms / 1000.0 + 0.041) << "braking from the timeout on (state frames every 20 ms)";
  EXPECT_LT(distance_mm(rest.p, lapsed.p), 30.0);
  EXPECT_LT(distance_mm(rig.pose().p, rest.p), 0.5) << "at rest";
  EXPECT_EQ(rig.state(), core::ArmState::running);
}

// A streamed velocity is limited as a length, as the stick's disc limits it: (150, 0, 150) mm/s,
// each axis at the hand's top speed, moves the hand at most at that speed, in that direction.
// Clamped axis by axis (the image before), the hand went at 177.5 mm/s.
TEST(FirmwareSafety, AStreamedVelocityIsLimitedAsALength) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  protocol::VelocityCmd v{};
  v.v_mm_s[0] = v.v_mm_s[2] = 150;
  armsim::TrajectoryRow from{}, to{};
  for (int k = 0; k < 50; ++k) {  // a frame every 40 ms for 2 s
    rig.run_to(t_running + 0.04 * k);
    if (k == 15) from = rig.pose();  // (past the start's ramp)
    rig.sim.send_serial(test::message(v, (uint8_t)(1 + k)));
  }
  to = rig.pose();
  const double dx = to.p[0] - from.p[0], dy = to.p[1] - from.p[1], dz = to.p[2] - from.p[2];
  const double moved_m = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double speed_m_s = moved_m / (0.04 * 34);
  const double max_m_s = (double)config::kMaxHandSpeed_m_s.num / (double)config::kMaxHandSpeed_m_s.den;
  std::printf("stream (150, 0, 150) mm/s: the hand at %.1f mm/s, direction (%.3f, %.3f, %.3f)\n", speed_m_s * 1000,
              dx / moved_m, dy / moved_m, dz / moved_m);
  EXPECT_LE(speed_m_s, max_m_s * 1.03);
  EXPECT_GT(speed_m_s, max_m_s * 0.5);
  EXPECT_GT((dx + dz) / std::sqrt(2.0) / moved_m, 0.99) << "along (1, 0, 1)";
}

// A person's deflected stick takes a streamed velocity over, as it takes over a move to a pose
// (the rule "a stick the person can take them over with"): once the image let the stream win and
// the stick was ignored (review22: the hand went +x at the stream's 100 mm/s with the stick held
// at -x). Taken over, the stream ends: let go of the stick, the hand stays while the host goes on
// streaming (its commands refused), and a stream drives again only after a pause of the timeout.
TEST(FirmwareSafety, ADeflectedStickTakesAStreamOver) {
  Rig rig(kFirmware);
  const double t_running = rig.start(12.0);
  ASSERT_GT(t_running, 0);
  uint8_t seq = 1;
  protocol::VelocityCmd v{};
  v.v_mm_s[0] = 100;  // the host: +x
  const auto stream = [&](double from_s, double to_s) {
    for (double t = from_s; t < to_s; t += 0.04) {
      rig.run_to(t);
      rig.sim.send_serial(test::message(v, seq++));
    }
    rig.run_to(to_s);
  };
  const auto refused_since = [&](size_t first) {
    size_t n = 0;
    for (size_t i = first; i < rig.telemetry.replies().size(); ++i)
      n += rig.telemetry.replies()[i].status == (uint8_t)protocol::ReplyStatus::refused;
    return n;
  };
  rig.sim.set_joystick(-0.8, 0.0);  // XY: the hand towards -x
  rig.run_to(t_running + 0.5);
  const armsim::TrajectoryRow held = rig.pose();
  stream(t_running + 0.5, t_running + 1.5);
  const armsim::TrajectoryRow streamed = rig.pose();
  EXPECT_LT(streamed.p[0], held.p[0] - 0.05) << "the stick still drives the hand -x (m), the stream does not";
  // let go while the host streams on: the hand comes to rest and stays
  rig.sim.set_joystick(0.0, 0.0);
  const size_t replies_let_go = rig.telemetry.replies().size();
  stream(t_running + 1.5, t_running + 2.2);
  const armsim::TrajectoryRow rest = rig.pose();
  stream(t_running + 2.2, t_running + 3.2);
  const armsim::TrajectoryRow after = rig.pose();
  const size_t refused = refused_since(replies_let_go);
  // a pause of more than the timeout, then a new stream drives
  rig.run_to(t_running + 3.4);
  const size_t replies_new = rig.telemetry.replies().size();
  stream(t_running + 3.4, t_running + 4.4);
  std::printf("stick held -x: hand x %.1f -> %.1f mm with the stream +x; let go, streamed on 1.7 s: %.1f -> %.1f mm (%zu "
              "commands refused); a new stream after a pause: %.1f mm\n",
              held.p[0] * 1000, streamed.p[0] * 1000, rest.p[0] * 1000, after.p[0] * 1000, refused, rig.pose().p[0] * 1000);
  EXPECT_NEAR(after.p[0], rest.p[0], 0.003) << "the stream taken over drove the hand again when the stick was let go";
  EXPECT_GE(refused, 40u);
  EXPECT_EQ(refused_since(replies_new), 0u);
  EXPECT_GT(rig.pose().p[0], after.p[0] + 0.03) << "a stream after a pause drives";
}

// The peripherals as the firmware left them once running, read from simavr's register file and
// checked against the ATmega2560 datasheet's tables. simavr accepts settings the chip would run
// differently (it models only ADC0..7, not every PWM mode on the pins), so the registers
// themselves are the evidence for the real board.
namespace hw {
// data-space addresses (datasheet, Register Summary)
constexpr uint16_t kTccr0b = 0x45, kTccr2b = 0xB1, kOcr0a = 0x47, kOcr2a = 0xB3;
constexpr uint16_t kAdcsra = 0x7A, kAdcsrb = 0x7B, kAdmux = 0x7C, kDidr0 = 0x7E;
constexpr uint16_t kUcsr0a = 0xC0, kUcsr0c = 0xC2, kUbrr0 = 0xC4;
constexpr uint16_t kEicra = 0x69, kEicrb = 0x6A, kEimsk = 0x3D, kPcicr = 0x68, kPcmsk0 = 0x6B;
// clock select CSn2:0 -> prescaler (Tables 16-9 and 17-6; Timer2's own, Table 20-9); 0 = stopped
constexpr int kPrescaler[8] = {0, 1, 8, 64, 256, 1024, -1, -1};
constexpr int kPrescalerTimer2[8] = {0, 1, 8, 32, 64, 128, 256, 1024};
}  // namespace hw

TEST(FirmwareRegisters, TimersAdcUartAndInterruptsAsTheDatasheetWants) {
  Rig rig(kFirmware);
  rig.run_to(0.3);
  const uint8_t* d = rig.sim.core().avr()->data;
  const auto r16 = [d](uint16_t a) { return (uint16_t)(d[a] | d[a + 1] << 8); };
  const auto snapshot = [&](board::Timer t) {
    const m2560::TimerRegisters& r = m2560::timer_registers(t);
    m2560::TimerSnapshot s;
    s.tccra = d[r.tccra];
    s.tccrb = d[r.tccrb];
    for (int c = 0; c < (r.sixteen_bit ? 3 : 2); ++c) s.ocr[c] = r.sixteen_bit ? r16(r.ocr[c]) : d[r.ocr[c]];
    s.icr = r.icr ? r16(r.icr) : 0;
    s.sixteen_bit = r.sixteen_bit;
    return s;
  };
  const auto clock_hz = [&](board::Timer t) {
    const int cs = d[m2560::timer_registers(t).tccrb] & 7;
    const int n = t == board::Timer::t2 ? hw::kPrescalerTimer2[cs] : hw::kPrescaler[cs];
    return n > 0 ? (double)board::kCpuHz / n : 0.0;
  };
  // the bridges: fast PWM at 20..25 kHz (the BTS7960's range) on every timer they use
  for (board::Timer t : {board::Timer::t0, board::Timer::t2, board::Timer::t3, board::Timer::t4}) {
    const m2560::TimerMode m = m2560::timer_mode(snapshot(t));
    EXPECT_EQ(m.wave, m2560::Wave::fast_pwm) << "timer " << (int)t;
    const double f_hz = clock_hz(t) / (m.top + 1.0);
    EXPECT_GE(f_hz, 20000) << "timer " << (int)t;
    EXPECT_LE(f_hz, 25000) << "timer " << (int)t;
  }
  EXPECT_EQ(d[hw::kOcr0a], 99);
  EXPECT_EQ(d[hw::kOcr2a], 99);
  // OC0A shares PB7 with the servo's OC1C: COM0A off, or the output compare modulator mixes them
  EXPECT_EQ(d[m2560::timer_registers(board::Timer::t0).tccra] >> 6, 0);
  EXPECT_EQ(d[hw::kTccr0b] & 0x08, 0x08) << "WGM02: TOP = OCR0A";
  EXPECT_EQ(d[hw::kTccr2b] & 0x08, 0x08) << "WGM22: TOP = OCR2A";
  // Timer5 steps, Timer1 ticks: normal mode at the rates the drivers count in
  EXPECT_EQ(m2560::timer_mode(snapshot(board::Timer::t5)).wave, m2560::Wave::normal);
  EXPECT_EQ(clock_hz(board::Timer::t5), (double)steppers::kTickHz);
  EXPECT_EQ(m2560::timer_mode(snapshot(board::Timer::t1)).wave, m2560::Wave::normal);
  EXPECT_EQ(clock_hz(board::Timer::t1), 1e6 * tick::kCountsPerUs);
  // every compare output a driver uses is an output pin
  const board::ComparePin outputs[] = {board::kStepperJ1.step, board::kStepperJ5.step, board::kStepperJ6.step,
                                       board::kBridgeJ2.left,  board::kBridgeJ2.right, board::kBridgeJ3.left,
                                       board::kBridgeJ3.right, board::kBridgeJ4.left,  board::kBridgeJ4.right,
                                       board::kGripperServo};
  for (const board::ComparePin& p : outputs)
    EXPECT_TRUE(d[m2560::ddr_register(p.pin.port)] >> p.pin.bit & 1) << "D" << (int)p.pin.arduino;
  // ADC: AVcc reference (REFS1:0 = 01), ADC0..7 (MUX5 = 0), a 50..200 kHz clock for 10 bits, the
  // analog pins' digital buffers off
  EXPECT_EQ(d[hw::kAdmux] >> 6, 1);
  EXPECT_EQ(d[hw::kAdcsrb] & 0x08, 0);
  const double adc_hz = (double)board::kCpuHz / (1 << std::max(1, d[hw::kAdcsra] & 7));
  EXPECT_GE(adc_hz, 50e3);
  EXPECT_LE(adc_hz, 200e3);
  for (uint8_t ch : {board::kAdcJoystickX, board::kAdcJoystickY, board::kAdcPotJ2, board::kAdcPotJ3, board::kAdcPotJ4})
    EXPECT_TRUE(d[hw::kDidr0] >> ch & 1) << "DIDR0 ADC" << (int)ch << "D";
  // UART0: 115200 within 2.5 % (U2X: 16 MHz / 8 (UBRR + 1)), 8N1
  const bool u2x = d[hw::kUcsr0a] & 0x02;
  const double baud = (double)board::kCpuHz / ((u2x ? 8 : 16) * (r16(hw::kUbrr0) + 1.0));
  EXPECT_NEAR(baud / board::kSerialBaud, 1.0, 0.025) << baud << " baud";
  EXPECT_EQ(d[hw::kUcsr0c], 0x06) << "8N1: UCSZ01:0 = 11, no parity, one stop bit";
  // switches and buttons: INT0..4 on any edge (ISCn1:0 = 01), PCINT0..6 (port B, pull-ups on)
  EXPECT_EQ(d[hw::kEicra], 0x55);
  EXPECT_EQ(d[hw::kEicrb] & 0x03, 0x01);
  EXPECT_EQ(d[hw::kEimsk] & 0x1F, 0x1F);
  EXPECT_EQ(d[hw::kPcicr] & 1, 1);
  EXPECT_EQ(d[hw::kPcmsk0], 0x7F);
  const uint16_t portb = m2560::port_register(board::Port::B), ddrb = m2560::ddr_register(board::Port::B);
  EXPECT_EQ(d[portb] & 0x7F, 0x7F) << "pull-ups on PB0..6";
  EXPECT_EQ(d[ddrb] & 0x7F, 0) << "PB0..6 inputs";
}

}  // namespace
