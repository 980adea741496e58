// tools/telemetry: the JSON form of every frame, the stream's counts, and the wmra-telemetry
// command (encode -> decode through a pipe, exit codes of bad input, listen on a pseudo-terminal).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/faults.h"
#include "core/resolved_rate.h"
#include "protocol_frames.h"
#include "sim_run.h"
#include "telemetry_json.h"

using namespace wmra;
using namespace wmra::protocol;
using wmra::protocol_frames::frame_bytes;
using wmra::protocol_frames::message_bytes;
using telemetry::to_json;

namespace {

Frame parse_one(const std::vector<uint8_t>& bytes) {
  Parser p;
  for (uint8_t b : bytes) {
    p.push(b);
    if (p.next()) return p.frame();
  }
  ADD_FAILURE() << "no frame";
  return Frame{};
}

std::vector<uint8_t> from_hex(const std::string& hex) {
  std::vector<uint8_t> bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) bytes.push_back((uint8_t)std::stoul(hex.substr(i, 2), nullptr, 16));
  return bytes;
}

std::string frame_hex_of(const std::vector<uint8_t>& bytes) { return telemetry::to_hex(bytes.data(), bytes.size()); }

const std::string kOut = TELEMETRY_TEST_OUT;

struct CliRun {
  int status;
  std::string out, err;
};
// runs wmra-telemetry with args (and stdin from a file when given); ctest runs the tests in
// parallel, so each has a stderr file of its own
CliRun cli(const std::string& args, const std::string& stdin_path = "/dev/null") {
  const std::string err_path = kOut + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".stderr";
  const simrun::CommandRun r =
      simrun::run_command(std::string(TELEMETRY_BIN) + " " + args + " < " + stdin_path + " 2> " + err_path);
  std::ifstream e(err_path);
  std::stringstream ss;
  ss << e.rdbuf();
  return {r.status, r.out, ss.str()};
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write((const char*)bytes.data(), (std::streamsize)bytes.size());
}

}  // namespace

TEST(TelemetryJson, StateFrame) {
  StateMsg s{};
  s.t_ms = 1020;
  s.state = 4;
  s.mode = 0;
  s.faults = core::fault_mask(3) | core::fault_mask(core::kFaultBitStickInvalid) | core::fault_mask(20);
  s.slowed_by = core::kSlowSingular | core::kSlowJointSpeed;
  s.reset_cause = 1 << 3;
  s.switches = 1 << 0 | 1 << 10;
  s.q_mrad[1] = -785;
  s.qd_mrad_s[5] = 12;
  s.p_0p1mm[0] = 10770;
  s.stick_permille[1] = -1000;
  s.speed_scale_pct = 80;
  s.loop_cycles_max = 5123;
  s.rx_crc_errors = 1;
  s.rx_framing_errors = 2;
  s.rx_rejected = 3;
  s.rx_overruns = 4;
  EXPECT_EQ(to_json(parse_one(message_bytes(s, 12))),
            "{\"type\":\"state\",\"seq\":12,\"t_ms\":1020,\"state\":\"running\",\"mode\":\"xy\","
            "\"faults\":[\"j2_rail\",\"stick_invalid\",\"bit_20\"],\"slowed_by\":[\"singular\",\"joint_speed\"],"
            "\"reset_cause\":[\"watchdog\"],\"switches\":[\"j1_low\",\"j6_zero\"],\"q_mrad\":[0,-785,0,0,0,0],"
            "\"qd_mrad_s\":[0,0,0,0,0,12],\"p_0p1mm\":[10770,0,0],\"stick_permille\":[0,-1000],\"speed_scale_pct\":80,"
            "\"loop_cycles_max\":5123,\"rx_crc_errors\":1,\"rx_framing_errors\":2,\"rx_rejected\":3,"
            "\"rx_overruns\":4}");
  s.state = 9;
  s.mode = 7;
  const std::string unknown = to_json(parse_one(message_bytes(s, 12)));
  EXPECT_NE(unknown.find("\"state\":\"unknown_9\",\"mode\":\"unknown_7\""), std::string::npos) << unknown;
}

// every bit the firmware sets has its name (a count passed beside the table once left the last out)
TEST(TelemetryJson, EverySlowReasonHasItsName) {
  EXPECT_EQ(telemetry::slow_reason_names(core::kSlowTracking), std::vector<std::string>{"tracking"});
  EXPECT_EQ(telemetry::slow_reason_names(core::kSlowLimitSwitch | core::kSlowDriveLoad), (std::vector<std::string>{"drive_load", "limit_switch"}));
  EXPECT_EQ(telemetry::slow_reason_names(1 << 6), std::vector<std::string>{"bit_6"});
  EXPECT_EQ(telemetry::switch_names(1 << 10 | 1 << 11), (std::vector<std::string>{"j6_zero", "bit_11"}));
}

TEST(TelemetryJson, ReplyBootAndCommands) {
  EXPECT_EQ(to_json(parse_one(message_bytes(ReplyMsg{(uint8_t)MsgType::cmd_mode, 3, 0}, 40))),
            "{\"type\":\"reply\",\"seq\":40,\"command\":\"mode\",\"command_seq\":3,\"status\":\"ok\"}");
  EXPECT_EQ(to_json(parse_one(message_bytes(ReplyMsg{0x30, 4, 1}, 41))),
            "{\"type\":\"reply\",\"seq\":41,\"command\":\"unknown_48\",\"command_seq\":4,\"status\":\"unknown_command\"}");
  EXPECT_EQ(to_json(parse_one(message_bytes(BootMsg{1 << 3, 1, {}}, 0))),
            "{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"watchdog\"],\"calibration\":\"defaults_blank\",\"j6_angle\":\"none\",\"version\":\"0.0.0\",\"commit\":\"000000000000\",\"tree\":\"clean\",\"config_hash\":\"00000000\"}");
  EXPECT_EQ(to_json(parse_one(message_bytes(BootMsg{0x05, 0, {}}, 0))),
            "{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"power_on\",\"brown_out\"],\"calibration\":\"eeprom\",\"j6_angle\":\"none\",\"version\":\"0.0.0\",\"commit\":\"000000000000\",\"tree\":\"clean\",\"config_hash\":\"00000000\"}");
  EXPECT_EQ(to_json(parse_one(message_bytes(BootMsg{0x88, 0, {}}, 0))),
            "{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"watchdog\",\"inferred\"],\"calibration\":\"eeprom\",\"j6_angle\":\"none\",\"version\":\"0.0.0\",\"commit\":\"000000000000\",\"tree\":\"clean\",\"config_hash\":\"00000000\"}");
  EXPECT_EQ(to_json(parse_one(message_bytes(BootMsg{0x60, 0, {}}, 0))),
            "{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"bit_5\",\"bit_6\"],\"calibration\":\"eeprom\",\"j6_angle\":\"none\",\"version\":\"0.0.0\",\"commit\":\"000000000000\",\"tree\":\"clean\",\"config_hash\":\"00000000\"}");
  // bit 7 of the calibration byte: J6's angle at rest was recorded (the settings' source apart)
  EXPECT_EQ(to_json(parse_one(message_bytes(BootMsg{0x01, 0x82, {}}, 0))),
            "{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"power_on\"],\"calibration\":\"defaults_bad_crc\",\"j6_angle\":\"recorded\",\"version\":\"0.0.0\",\"commit\":\"000000000000\",\"tree\":\"clean\",\"config_hash\":\"00000000\"}");
  // the firmware's identity by name: its version, commit, whether the tree had changes, the configuration's hash
  EXPECT_EQ(to_json(parse_one(message_bytes(BootMsg{0x01, 0, Identity{{0, 7, 1}, {0x85, 0xe4, 0xee, 0x73, 0xd9, 0x0a}, 1, 0xdeadbeef}}, 0))),
            "{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"power_on\"],\"calibration\":\"eeprom\",\"j6_angle\":\"none\","
            "\"version\":\"0.7.1\",\"commit\":\"85e4ee73d90a\",\"tree\":\"changed\",\"config_hash\":\"deadbeef\"}");
  InfoMsg info{Identity{{1, 0, 0}, {0, 0, 0, 0, 0, 0}, kBuildCommitUnknown, 1}, 150, 800, {800, 1000, 1000, 1600, 1500, 1500},
               {-1518, -733, -2304, -2740, -1518, -6231}, {1518, 2304, 2740, 2740, 1518, 6231}, 1000};
  EXPECT_EQ(to_json(parse_one(message_bytes(info, 9))),
            "{\"type\":\"info\",\"seq\":9,\"version\":\"1.0.0\",\"commit\":\"000000000000\",\"tree\":\"unknown\","
            "\"config_hash\":\"00000001\",\"hand_speed_mm_s\":150,\"wrist_speed_mrad_s\":800,"
            "\"joint_speed_mrad_s\":[800,1000,1000,1600,1500,1500],\"soft_min_mrad\":[-1518,-733,-2304,-2740,-1518,-6231],"
            "\"soft_max_mrad\":[1518,2304,2740,2740,1518,6231],\"loop_hz\":1000}");
  EXPECT_EQ(to_json(parse_one(frame_bytes(0x1B, 8, {}))), "{\"type\":\"command\",\"command\":\"get_info\",\"seq\":8}");
  EXPECT_EQ(to_json(parse_one(message_bytes(CalibrationMsg{{819, 819, 819}, {15564, 15564, 15000}, {4000, 8000, -3}, 4}, 7))),
            "{\"type\":\"calibration\",\"seq\":7,\"at_min_counts_x16\":[819,819,819],\"at_max_counts_x16\":"
            "[15564,15564,15000],\"reading_counts_x16\":[4000,8000,-3],\"from_command\":4}");
  EXPECT_EQ(to_json(parse_one(frame_bytes(0x16, 5, {2}))),
            "{\"type\":\"command\",\"command\":\"store_pose\",\"seq\":5,\"slot\":2}");
  EXPECT_EQ(to_json(parse_one(message_bytes(VelocityCmd{{150, 0, -1}, {0, 800, 0}}, 6))),
            "{\"type\":\"command\",\"command\":\"velocity\",\"seq\":6,\"v_mm_s\":[150,0,-1],\"w_mrad_s\":[0,800,0]}");
}

// every status the firmware replies with has its name; a newer one reads unknown_N
TEST(TelemetryJson, EveryReplyStatusHasItsName) {
  const char* const names[] = {"ok", "unknown_command", "bad_length", "bad_argument", "refused", "safety_held"};
  for (uint8_t status = 0; status < 6; ++status) EXPECT_EQ(telemetry::status_name(status), names[status]);
  EXPECT_EQ(telemetry::status_name((uint8_t)ReplyStatus::safety_held), "safety_held");
  EXPECT_EQ(telemetry::status_name(6), "unknown_6");
  EXPECT_EQ(to_json(parse_one(message_bytes(ReplyMsg{(uint8_t)MsgType::cmd_rearm, 9, (uint8_t)ReplyStatus::safety_held}, 42))),
            "{\"type\":\"reply\",\"seq\":42,\"command\":\"rearm\",\"command_seq\":9,\"status\":\"safety_held\"}");
}

TEST(TelemetryJson, FramesThatDoNotFitTheirType) {
  EXPECT_EQ(to_json(parse_one(frame_bytes(0x13, 1, {101}))),
            "{\"type\":\"command\",\"command\":\"speed_scale\",\"seq\":1,\"error\":\"bad_argument\",\"payload\":\"65\"}");
  EXPECT_EQ(to_json(parse_one(frame_bytes(0x10, 2, {0xAB}))),
            "{\"type\":\"command\",\"command\":\"stop\",\"seq\":2,\"error\":\"bad_length\",\"payload\":\"ab\"}");
  EXPECT_EQ(to_json(parse_one(frame_bytes(0x01, 3, {1, 2}))),
            "{\"type\":\"state\",\"seq\":3,\"error\":\"bad_length\",\"payload\":\"0102\"}");
  EXPECT_EQ(to_json(parse_one(frame_bytes(0x42, 4, {0xFF}))),
            "{\"type\":\"unknown\",\"type_id\":66,\"seq\":4,\"payload\":\"ff\"}");
}

TEST(FrameStream, CountsSeqGapsAndTheFramesMissingOfTheFirmwareOnly) {
  telemetry::FrameStream s;
  std::vector<uint8_t> bytes;
  auto add = [&](const std::vector<uint8_t>& b) { bytes.insert(bytes.end(), b.begin(), b.end()); };
  add(message_bytes(BootMsg{1, 0, {}}, 0));
  add(message_bytes(StateMsg{}, 1));
  add(frame_bytes(0x10, 77, {}));                  // a host command: its own numbers
  add(message_bytes(ReplyMsg{0x10, 77, 0}, 2));
  add(message_bytes(StateMsg{}, 5));               // 3 and 4 lost: one gap
  add({0xA5, kVersion, 0x01, 0x06, 0x00, 0x00, 0x00});  // a bad CRC
  add(message_bytes(StateMsg{}, 7));               // 6 lost with it: a second gap
  add(message_bytes(BootMsg{8, 0, {}}, 0));            // a reset: no gap
  add(message_bytes(StateMsg{}, 1));
  int frames = 0;
  for (uint8_t b : bytes) {
    s.push(b);
    while (s.next()) ++frames;
  }
  EXPECT_EQ(frames, 8);
  EXPECT_EQ(s.frames(), 8u);
  EXPECT_EQ(s.seq_gaps(), 2u);
  EXPECT_EQ(s.missing_frames(), 3u);
  // the bad frame's bytes after its sync, looked at again, are skipped
  EXPECT_EQ(s.summary(), "frames 8, crc errors 1, framing errors 0, skipped bytes 6, seq gaps 2");
}

TEST(WmraTelemetryCli, EncodeThenDecodeThroughAPipe) {
  struct Case {
    std::string args, json;
  };
  const Case cases[] = {
      {"stop", "{\"type\":\"command\",\"command\":\"stop\",\"seq\":0}"},
      {"rearm --seq 255", "{\"type\":\"command\",\"command\":\"rearm\",\"seq\":255}"},
      {"home", "{\"type\":\"command\",\"command\":\"home\",\"seq\":0}"},
      {"--seq 3 mode xz", "{\"type\":\"command\",\"command\":\"mode\",\"seq\":3,\"mode\":\"xz\"}"},
      {"mode gripper", "{\"type\":\"command\",\"command\":\"mode\",\"seq\":0,\"mode\":\"gripper\"}"},
      {"speed 50", "{\"type\":\"command\",\"command\":\"speed_scale\",\"seq\":0,\"speed_scale_pct\":50}"},
      {"goto 1", "{\"type\":\"command\",\"command\":\"goto_pose\",\"seq\":0,\"slot\":1}"},
      {"store 3", "{\"type\":\"command\",\"command\":\"store_pose\",\"seq\":0,\"slot\":3}"},
      {"velocity 0.15 -0.0504 0 0 -0.8 32.767",
       "{\"type\":\"command\",\"command\":\"velocity\",\"seq\":0,\"v_mm_s\":[150,-50,0],\"w_mrad_s\":[0,-800,32767]}"},
      {"calibration", "{\"type\":\"command\",\"command\":\"get_calibration\",\"seq\":0}"},
      {"calibrate 3 1459 15564",
       "{\"type\":\"command\",\"command\":\"pot_calibration\",\"seq\":0,\"joint\":3,\"at_min_counts_x16\":1459,"
       "\"at_max_counts_x16\":15564}"},
      // J3 (-135..160 deg) read 6000 at 0 deg and 8000 at 60: 33.3 a degree
      {"calibrate-from 3 6000 0 8000 60",
       "{\"type\":\"command\",\"command\":\"pot_calibration\",\"seq\":0,\"joint\":3,\"at_min_counts_x16\":1500,"
       "\"at_max_counts_x16\":11333}"},
      {"stick-centre store", "{\"type\":\"command\",\"command\":\"stick_centre\",\"seq\":0,\"stick_centre\":\"store\"}"},
      {"stick-centre forget", "{\"type\":\"command\",\"command\":\"stick_centre\",\"seq\":0,\"stick_centre\":\"forget\"}"},
  };
  std::vector<uint8_t> all;
  std::string expected;
  for (const Case& c : cases) {
    const CliRun r = cli("encode " + c.args);
    ASSERT_EQ(r.status, 0) << c.args << ": " << r.err;
    ASSERT_EQ(r.out.back(), '\n');
    const std::string hex = r.out.substr(0, r.out.size() - 1);
    EXPECT_EQ(hex.find_first_not_of("0123456789abcdef"), std::string::npos) << hex;
    const auto bytes = from_hex(hex);
    EXPECT_EQ(to_json(parse_one(bytes)), c.json) << c.args;
    all.insert(all.end(), bytes.begin(), bytes.end());
    expected += c.json + "\n";
  }
  // calibrate-from shows the limits it computed, for the person to check before sending them
  EXPECT_EQ(cli("encode calibrate-from 3 6000 0 8000 60").err,
            "calibrate-from: J3 reads 1500 at -135 deg and 11333 at 160 deg (its limits, pot counts x 16)\n");
  all.push_back(0x00);  // a byte outside any frame
  const std::string path = kOut + "/commands.bin";
  write_bytes(path, all);
  CliRun r = cli("decode", path);  // stdin
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, expected);
  EXPECT_EQ(r.err, "wmra-telemetry: frames 14, crc errors 0, framing errors 0, skipped bytes 1, seq gaps 0\n");
  r = cli("decode " + path);  // a file
  EXPECT_EQ(r.out, expected);
  EXPECT_EQ(cli("encode stop").out, "a5031000007f5c\n");  // the CRC by hand: docs/telemetry.md
}

TEST(WmraTelemetryCli, DecodeCountsWhatWentWrong) {
  std::vector<uint8_t> bytes = message_bytes(BootMsg{1, 0, {}}, 0);
  const auto state = message_bytes(StateMsg{}, 2);  // seq 1 missing
  bytes.insert(bytes.end(), state.begin(), state.end());
  auto bad = message_bytes(StateMsg{}, 3);
  bad[10] ^= 1;
  bytes.insert(bytes.end(), bad.begin(), bad.end());
  for (uint8_t b : {0xA5, 0x07, 0x33}) bytes.push_back(b);  // version 7, then a stray byte
  const std::string path = kOut + "/faulty.bin";
  write_bytes(path, bytes);
  const CliRun r = cli("decode " + path);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2);
  // skipped: the bad frame's 65 bytes after its sync, looked at again, then 07 and 33
  EXPECT_EQ(r.err, "wmra-telemetry: frames 2, crc errors 1, framing errors 1, skipped bytes 67, seq gaps 1\n");
}

TEST(WmraTelemetryCli, BadInputExitsWithTwo) {
  const char* bad[] = {
      "",
      "frobnicate",
      "encode",
      "encode jump",
      "encode stop now",
      "encode mode",
      "encode mode xw",
      "encode mode 1",
      "encode speed 101",
      "encode speed -1",
      "encode speed 5.5",
      "encode goto 4",
      "encode store x",
      "encode velocity 0.1 0 0 0 0",
      "encode velocity 32.768 0 0 0 0 0",
      "encode velocity 0 0 0 0 0 -40",
      "encode velocity nan 0 0 0 0 0",
      "encode calibrate 5 800 15000",
      "encode calibrate 3 800",
      "encode calibrate 3 -1 15000",
      "encode calibrate 3 800 16369",
      "encode calibrate-from 3 6000 0 8000 5",
      "encode calibrate-from 3 5000 -30 12000 90",
      "encode calibrate-from 3 8000 0 6000 60",
      "encode calibrate-from 3 6000 x 8000 60",
      "encode calibrate-from 3 6000 0 8000",
      "encode stick-centre 1",
      "encode stick-centre",
      "encode stop --seq 256",
      "encode stop --seq",
      "decode a b",
      "listen",
      "listen /dev/ttyUSB0 --send",
      "listen /dev/ttyUSB0 --send a5f",
      "listen /dev/ttyUSB0 --send zz",
      "listen /dev/ttyUSB0 --send a5 --every 5",
      "listen /dev/ttyUSB0 --send a5 --each 50",
      "listen /dev/ttyUSB0 --every 50",
  };
  for (const char* args : bad) {
    const CliRun r = cli(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_EQ(r.err.rfind("wmra-telemetry: ", 0), 0u) << args << ": " << r.err;
    EXPECT_NE(r.err.find("usage:"), std::string::npos) << args;
  }
  EXPECT_NE(cli("encode speed 101").err.find("from 0 to 100, not '101'"), std::string::npos);
  EXPECT_NE(cli("encode mode xw").err.find("xy, xz, r1, r2 or gripper"), std::string::npos);
  EXPECT_NE(cli("encode calibrate-from 3 8000 0 6000 60").err.find("wired reversed, swap its two outer wires"),
            std::string::npos);
}

TEST(WmraTelemetryCli, UnopenableInputExitsWithThree) {
  CliRun r = cli("decode /nonexistent/serial.bin");
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.err.find("/nonexistent/serial.bin"), std::string::npos);
  r = cli("listen /dev/null");  // not a serial port
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.err.find("not a serial port"), std::string::npos) << r.err;
}

// listen on a pseudo-terminal: the port is set up, frames are decoded as they come, --send
// goes out once the first frame has arrived, and Ctrl-C ends it with the summary
// wmra-telemetry listen on a pseudo-terminal (the test holds its master side), stdout and
// stderr into kOut/NAME.out and .err
struct Listener {
  int master = -1;
  pid_t pid = 0;
  std::string out_path, err_path;
  Listener(const std::string& name, std::vector<std::string> options) {
    master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return;
    out_path = kOut + "/" + name + ".out";
    err_path = kOut + "/" + name + ".err";
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> args = {TELEMETRY_BIN, "listen", ptsname(master)};
    args.insert(args.end(), options.begin(), options.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(&a[0]);
    argv.push_back(nullptr);
    if (posix_spawn(&pid, TELEMETRY_BIN, &files, nullptr, argv.data(), environ) != 0) pid = 0;
    posix_spawn_file_actions_destroy(&files);
  }
  // what the tool wrote to the port within ms milliseconds, as hex
  std::string read_for(int ms) {
    std::string received;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
      pollfd p{master, POLLIN, 0};
      if (poll(&p, 1, 10) == 1) {
        uint8_t buf[256];
        const ssize_t n = read(master, buf, sizeof buf);
        if (n > 0) received += frame_hex_of(std::vector<uint8_t>(buf, buf + n));
      }
    }
    return received;
  }
  // boot frames until `command` comes back: the first ones may go before the port is open
  std::string boot_until(const std::string& command) {
    const auto boot = message_bytes(BootMsg{1, 0, {}}, 0);
    std::string received;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (received.find(command) == std::string::npos && std::chrono::steady_clock::now() < deadline) {
      if (write(master, boot.data(), boot.size()) != (ssize_t)boot.size()) break;
      received += read_for(50);
    }
    return received;
  }
  int stop() {
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    close(master);
    return status;
  }
};

TEST(WmraTelemetryCli, ListenOnAPseudoTerminal) {
  const std::string command = frame_hex_of(frame_bytes((uint8_t)MsgType::cmd_stop, 9, {}));
  Listener listen("listen", {"--send", command});
  ASSERT_GE(listen.master, 0);
  ASSERT_NE(listen.pid, 0);
  const int master = listen.master;
  const std::string out_path = listen.out_path, err_path = listen.err_path;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  const std::string received = listen.boot_until(command);
  EXPECT_NE(received.find(command), std::string::npos) << received;
  const auto reply = message_bytes(ReplyMsg{(uint8_t)MsgType::cmd_stop, 9, 0}, 1);
  ASSERT_EQ(write(master, reply.data(), reply.size()), (ssize_t)reply.size());
  std::string out;
  while (out.find("\"type\":\"reply\"") == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    usleep(20000);
    std::ifstream f(out_path);
    std::stringstream ss;
    ss << f.rdbuf();
    out = ss.str();
  }
  const int status = listen.stop();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_NE(out.find("{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"power_on\"],\"calibration\":\"eeprom\",\"j6_angle\":\"none\",\"version\":\"0.0.0\",\"commit\":\"000000000000\",\"tree\":\"clean\",\"config_hash\":\"00000000\"}\n"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("{\"type\":\"reply\",\"seq\":1,\"command\":\"stop\",\"command_seq\":9,\"status\":\"ok\"}\n"),
            std::string::npos)
      << out;
  std::ifstream e(err_path);
  std::stringstream err;
  err << e.rdbuf();
  EXPECT_NE(err.str().find("wmra-telemetry: frames "), std::string::npos) << err.str();
  EXPECT_NE(err.str().find(", seq gaps 0\n"), std::string::npos) << err.str();
}

namespace {

// --every: the command again every interval after the first frame (a velocity stream, which
// the firmware drops 100 ms after the last command): over 500 ms at 50 ms, about ten copies.
TEST(WmraTelemetryCli, ListenRepeatsTheCommandEveryInterval) {
  const std::string command =
      frame_hex_of(message_bytes(VelocityCmd{{50, 0, 0}, {0, 0, 0}}, 3));
  Listener listen("listen_every", {"--send", command, "--every", "50"});
  ASSERT_GE(listen.master, 0);
  ASSERT_NE(listen.pid, 0);
  ASSERT_NE(listen.boot_until(command).find(command), std::string::npos);
  const std::string received = listen.read_for(500);
  size_t copies = 0;
  for (size_t at = received.find(command); at != std::string::npos; at = received.find(command, at + 1)) ++copies;
  std::printf("listen --every 50: %zu copies in 500 ms\n", copies);
  EXPECT_GE(copies, 4u);  // a loaded machine may stretch the intervals, never shorten them
  EXPECT_LE(copies, 11u);
  const int status = listen.stop();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

}  // namespace
