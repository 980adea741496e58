// wmra-telemetry calibrate against armsim --live: J3's pot calibrated by the firmware image in
// the virtual arm, answered as a person would who measures the angle the firmware shows (the
// simulator's pot lies on the config's line, so that angle is the true one within a count).
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include "calibrate_driver.h"
#include "live_arm.h"
#include "config/joints_config.h"
#include "protocol/parser.h"
#include "protocol_frames.h"

using namespace wmra;
using namespace wmra::protocol;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kOut = ARMSIM_OUT;


std::string test_name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }

// armsim --live with the stick centred until end_s (test/common/live_arm.h)
struct LiveArm : test::LiveArm {
  LiveArm(const std::string& test, double end_s) : test::LiveArm(ARMSIM, kFirmware, kOut, test, end_s) {}
};

// the frames that come on the port within max_s of sending `command` (none: nothing sent),
// until enough() says so
template <class Enough>
std::vector<Frame> exchange(const std::string& port, const std::vector<uint8_t>& command, double max_s, Enough enough) {
  test::Host host(port);
  if (host.fd < 0 || (!command.empty() && !host.send(command))) return {};
  return host.frames_until(max_s, enough);
}

// The config's pot line in the firmware's unit, as the simulator's ADC reads it
double config_counts_x16(int16_t mV) { return mV * 1023.0 / config::kAdcRef_mV * config::kPositionUnitsPerCount; }

}  // namespace

// Read, + 1.5, the angle shown, - 3, the angle shown, yes: stored (set), at the config's line
// within a few counts x 16; the arm still waiting before homing, no fault
TEST(CalibrateLive, J3AtTheAnglesTheFirmwareShows) {
  ASSERT_EQ(access(kFirmware.c_str(), R_OK), 0) << kFirmware << ": build the firmware (avr_images)";
  LiveArm arm(test_name(), 120.0);
  ASSERT_FALSE(arm.link.empty()) << arm.armsim->err();

  const test::CalibrateRun run =
      test::run_calibrate(TELEMETRY_BIN, arm.link, 3, {"+ 1.5", "=", "- 3", "=", "yes"}, kOut + "/" + test_name() + "_calibrate");
  const std::string& out = run.out;
  ASSERT_EQ(run.status, 0) << out << run.err;
  EXPECT_EQ(run.err, "");
  std::printf("%s", out.c_str());

  std::smatch stored;
  ASSERT_TRUE(std::regex_search(out, stored, std::regex("\nstored: J3 (\\d+)\\.\\.(\\d+) \\(set\\)\n"))) << out;
  // the firmware's own calibration frame: J3 set, at the config's line; J2 and J4 untouched
  CalibrationMsg calibration{};
  exchange(arm.link, protocol_frames::frame_bytes((uint8_t)MsgType::cmd_get_calibration, 77, {}), 2.0,
           [&](const std::vector<Frame>& f) { return !f.empty() && decode(f.back(), calibration); });
  EXPECT_EQ(calibration.from_command, 1 << 1);
  EXPECT_EQ(calibration.at_min_counts_x16[1], std::stoi(stored[1]));
  EXPECT_EQ(calibration.at_max_counts_x16[1], std::stoi(stored[2]));
  EXPECT_NEAR(calibration.at_min_counts_x16[1], config_counts_x16(config::kPotAtMin_mV), 16);
  EXPECT_NEAR(calibration.at_max_counts_x16[1], config_counts_x16(config::kPotAtMax_mV), 16);
  // the arm as it was: waiting before homing, no fault
  StateMsg state{};
  exchange(arm.link, {}, 1.0, [&](const std::vector<Frame>& f) { return !f.empty() && decode(f.back(), state); });
  EXPECT_EQ(state.state, 7) << "wait_home";
  EXPECT_EQ(state.faults, 0u);

  kill(arm.armsim->pid, SIGINT);
  EXPECT_EQ(arm.armsim->wait_s(10), 0) << arm.armsim->err();
}
