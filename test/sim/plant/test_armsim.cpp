// armsim: the scenario format, the files it writes, its exit codes, determinism, and its
// decoder of the firmware's telemetry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "armsim/firmware_telemetry.h"
#include "armsim/run.h"
#include "armsim/scenario.h"
#include "protocol_frames.h"
#include "telemetry_json.h"

using namespace wmra;
using armsim::Event;
using armsim::parse_scenario;
using armsim::ScenarioError;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

int error_line(const std::string& text) {
  try {
    parse_scenario(text);
  } catch (const ScenarioError& e) {
    return e.line();
  }
  return 0;
}

const std::string kImage = std::string(SIM_IMAGES) + "/sim_bridges_avr.elf";
const std::string kLoopImage = std::string(SIM_IMAGES) + "/sim_loop_avr.elf";
const std::string kTelemetryImage = std::string(SIM_IMAGES) + "/sim_telemetry_avr.elf";

std::string frame_hex(protocol::MsgType type, uint8_t seq, const std::vector<uint8_t>& payload) {
  const std::vector<uint8_t> frame = protocol_frames::frame_bytes((uint8_t)type, seq, payload);
  return telemetry::to_hex(frame.data(), frame.size());
}

}  // namespace

TEST(Scenario, TheSpecExampleParses) {
  const auto s = parse_scenario(
      "init 0.1 0.2 0.3 0.4 0.5 0.6     # optional, first line\n"
      "0.0  joystick 0.5 -1          # stick deflection\n"
      "1.0  button press\n"
      "2.0  estop down\n"
      "2.5  pot_fault 3 open\n"
      "2.5  joystick_fault open\n"
      "3.0  serial 4f4b0a\n"
      "\n"
      "# a comment line\n"
      "9.0  end\n");
  ASSERT_TRUE(s.has_init);
  EXPECT_DOUBLE_EQ(s.init_q[5], 0.6);
  ASSERT_EQ(s.events.size(), 6u);
  EXPECT_EQ(s.events[0].kind, Event::Kind::joystick);
  EXPECT_DOUBLE_EQ(s.events[0].y, -1);
  EXPECT_EQ(s.events[1].kind, Event::Kind::button_press);
  EXPECT_EQ(s.events[2].kind, Event::Kind::estop_down);
  EXPECT_EQ(s.events[3].joint, 3);
  EXPECT_EQ(s.events[3].fault, 1);
  EXPECT_EQ(s.events[4].kind, Event::Kind::joystick_fault);
  EXPECT_EQ(s.events[5].bytes, (std::vector<uint8_t>{0x4f, 0x4b, 0x0a}));
  EXPECT_EQ(s.events[5].line, 7);
  EXPECT_DOUBLE_EQ(s.end_s, 9.0);
}

TEST(Scenario, BadLinesAreNamed) {
  EXPECT_EQ(error_line("0 joystick 0 0\n0.5 jump\n1 end\n"), 2);           // unknown event
  EXPECT_EQ(error_line("0 joystick 1.5 0\n1 end\n"), 1);                   // beyond full deflection
  EXPECT_EQ(error_line("0 joystick 0\n1 end\n"), 1);                       // missing Y
  EXPECT_EQ(error_line("0 joystick 0 0 0\n1 end\n"), 1);                   // one too many
  EXPECT_EQ(error_line("1 estop down\n0.5 estop up\n2 end\n"), 2);         // time goes back
  EXPECT_EQ(error_line("-1 estop down\n2 end\n"), 1);                      // negative time
  EXPECT_EQ(error_line("0 estop press\n1 end\n"), 1);
  EXPECT_EQ(error_line("0 button click\n1 end\n"), 1);
  EXPECT_EQ(error_line("0 pot_fault 5 open\n1 end\n"), 1);                 // J5 has no pot
  EXPECT_EQ(error_line("0 pot_fault 2 broken\n1 end\n"), 1);
  EXPECT_EQ(error_line("0 joystick_fault short\n1 end\n"), 1);
  EXPECT_EQ(error_line("0 serial 4f4\n1 end\n"), 1);                       // odd digits
  EXPECT_EQ(error_line("0 serial 4g\n1 end\n"), 1);
  EXPECT_EQ(error_line("# first\n0 joystick 0 0\ninit 0 0 0 0 0 0\n1 end\n"), 3);  // init not first
  EXPECT_EQ(error_line("init 0 0 3 0 0 0\n1 end\n"), 1);                   // q3 beyond 160 deg
  EXPECT_EQ(error_line("init 0 0 0 0 0\n1 end\n"), 1);
  EXPECT_EQ(error_line("x joystick 0 0\n1 end\n"), 1);
  EXPECT_EQ(error_line("0 joystick 0 0\n"), 1);                            // no end
  EXPECT_EQ(error_line("1 end\n2 estop down\n"), 2);                       // after the end
  EXPECT_EQ(error_line("# only comments\n\n2 end # done\n"), 0);
}

TEST(Armsim, WritesTheSpecsFiles) {
  const std::string dir = std::string(ARMSIM_OUT) + "/files";
  armsim::RunOptions options;
  options.elf = kImage;
  options.out_dir = dir;
  options.vcd = true;
  const auto scenario = parse_scenario("init 0 0.5 1.0 -2.7 0.3 0\n0 joystick 0.2 0\n0.3 button press\n0.5 serial 4f4b\n0.85 estop down\n1.0 end\n");
  const auto result = armsim::run_scenario(scenario, options);
  EXPECT_TRUE(result.completed);

  const std::string csv = read_file(dir + "/trajectory.csv");
  std::istringstream lines(csv);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header, "t,q1,q2,q3,q4,q5,q6,x,y,z,r11,r12,r13,r21,r22,r23,r31,r32,r33,mode,state");
  int rows = 0;
  double first_t = -1, last_t = -1, x0 = 0, q1 = 0, q2 = 0, q3 = 0, q4 = 0;
  for (std::string line; std::getline(lines, line); ++rows) {
    double t;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,", &t), 1);
    if (rows == 0) {
      first_t = t;
      std::sscanf(line.c_str(), "%*f,%lf,%lf,%lf,%lf,%*f,%*f,%lf", &q1, &q2, &q3, &q4, &x0);
    }
    last_t = t;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 20);
  }
  EXPECT_EQ(rows, 101);  // 100 a second, both ends
  EXPECT_DOUBLE_EQ(first_t, 0.0);
  EXPECT_DOUBLE_EQ(last_t, 1.0);
  EXPECT_DOUBLE_EQ(q2, 0.5);  // the init line
  EXPECT_DOUBLE_EQ(q4, -2.7);
  EXPECT_NEAR(x0, result.trajectory[0].p[0], 1e-7);
  EXPECT_EQ(result.trajectory.back().mode, -1);  // the image sends no telemetry frames

  const std::string json = read_file(dir + "/summary.json");
  for (const char* field : {"\"sim_time_s\": 1.000000", "\"control_loop_cycles\": {\"mean\":", "\"control_rate_hz\":",
                            "\"cpu_load\":", "\"steps\": {", "\"J1\": {\"commanded\":", "\"J5\":", "\"J6\":", "\"lost\":",
                            "\"ram_high_water_bytes\":", "\"faults\": [", "\"resets\": 0", "\"reaction_s\":"}) {
    EXPECT_NE(json.find(field), std::string::npos) << field;
  }
  const std::string vcd = read_file(dir + "/trace.vcd");
  EXPECT_EQ(vcd.rfind("$timescale 1ns $end", 0), 0u);
  // runs to the end: the last time stamp (ns) is 1 s, or a few cycles past it when the
  // last instruction before the end is a multi-cycle one
  const size_t last = vcd.rfind("\n#");
  ASSERT_NE(last, std::string::npos);
  const double end_ns = std::stod(vcd.substr(last + 2));
  EXPECT_GE(end_ns, 1e9);
  EXPECT_LT(end_ns, 1e9 + 1000);
}

TEST(Armsim, SameElfAndScenarioSameFiles) {
  const auto scenario = parse_scenario("init 0 0.5 1.0 -2.7 0.3 0\n0 joystick 0.3 -0.4\n0.85 estop down\n1.0 end\n");
  std::string csv[2], json[2], report[2];
  for (int k = 0; k < 2; ++k) {
    armsim::RunOptions options;
    options.elf = kImage;
    options.out_dir = std::string(ARMSIM_OUT) + "/same" + std::to_string(k);
    armsim::run_scenario(scenario, options);
    csv[k] = read_file(options.out_dir + "/trajectory.csv");
    json[k] = read_file(options.out_dir + "/summary.json");
    report[k] = read_file(options.out_dir + "/report.html");
  }
  EXPECT_EQ(csv[0], csv[1]);
  EXPECT_FALSE(report[0].empty());
  EXPECT_EQ(report[0], report[1]);
  EXPECT_EQ(json[0].substr(json[0].find("\"completed\"")), json[1].substr(json[1].find("\"completed\"")));
}

TEST(Armsim, CommandLineExitCodes) {
  const std::string dir = std::string(ARMSIM_OUT) + "/cli";
  const std::string bad = dir + "_bad.txt", good = dir + "_good.txt";
  std::ofstream(bad) << "# header\n0 joystick 0 0\n0.5 joystick 2 0\n1 end\n";
  std::ofstream(good) << "0 joystick 0 0\n0.2 end\n";
  const std::string armsim = ARMSIM;
  auto run = [&](const std::string& args) {
    const int status = std::system((armsim + " " + args + " 2> " + dir + "_stderr.txt").c_str());
    return WEXITSTATUS(status);
  };
  EXPECT_EQ(run("--scenario " + bad + " --out " + dir + " --elf " + kLoopImage), 2);
  EXPECT_NE(read_file(dir + "_stderr.txt").find(bad + ":3: joystick X and Y must be within [-1, 1]"), std::string::npos)
      << read_file(dir + "_stderr.txt");
  EXPECT_EQ(run("--scenario " + good + " --out " + dir + " --elf /nonexistent.elf"), 3);
  EXPECT_EQ(run("--scenario " + good), 2);  // no --out
  EXPECT_EQ(run("--scenario " + good + " --out " + dir + " --elf " + kLoopImage), 0);
  EXPECT_NE(read_file(dir + "/summary.json").find("\"control_rate_hz\": 1000.000"), std::string::npos);
  EXPECT_EQ(run("--scenario " + good + " --out " + dir + " --elf " + kLoopImage + " --profile-over 0"), 2);
  EXPECT_EQ(run("--scenario " + good + " --out " + dir + " --elf " + kLoopImage + " --profile-over 4k"), 2);
  // the loop image's iterations are 4,000-odd cycles: all of them over 1, half of them in each file
  EXPECT_EQ(run("--scenario " + good + " --out " + dir + " --elf " + kLoopImage + " --profile-over 1"), 0);
  const std::string summary = read_file(dir + "/summary.json");
  const size_t count_at = summary.find("\"count\": ", summary.find("\"control_loop_cycles\""));
  ASSERT_NE(count_at, std::string::npos);
  const int iterations = std::atoi(summary.c_str() + count_at + 9);
  EXPECT_GT(iterations, 190);  // 0.2 s at 1 kHz
  int in_files = 0;
  for (const char* name : {"/profile-over-even.txt", "/profile-over-odd.txt"}) {
    const std::string profile = read_file(dir + name);
    int n = -1;
    ASSERT_EQ(std::sscanf(profile.c_str(), "# %d iterations\n0x", &n), 1) << name << ": " << profile.substr(0, 40);
    EXPECT_NEAR(n, iterations / 2.0, 0.5) << name;
    EXPECT_NE(profile.find("\n0x"), std::string::npos) << name;
    in_files += n;
  }
  EXPECT_EQ(in_files, iterations);
}

// The protocol end to end: an image that speaks it over UART0, commands from the scenario's
// serial lines, armsim's own decoder (mode and state in the trajectory, summary.json) and one
// of the test's (every message).
TEST(Armsim, DecodesTheFirmwaresTelemetry) {
  using protocol::MsgType;
  const std::string scenario_text =
      "0 joystick 0 0\n"
      "0.3 serial " + frame_hex(MsgType::cmd_mode, 3, {1}) + "\n" +
      "0.5 serial 00ff" + frame_hex(MsgType::cmd_speed_scale, 4, {150}) + "a50301000000ffff\n" +
      "0.7 serial " + frame_hex(MsgType::cmd_speed_scale, 5, {40}) + "\n" +
      "1.0 end\n";
  const auto scenario = parse_scenario(scenario_text);
  armsim::RunOptions options;
  options.elf = kTelemetryImage;
  options.out_dir = std::string(ARMSIM_OUT) + "/telemetry";
  const auto own = armsim::run_scenario(scenario, options);  // armsim's default decoder
  EXPECT_TRUE(own.completed);
  EXPECT_EQ(own.trajectory[0].mode, -1);  // no state frame before 20 ms
  EXPECT_EQ(own.trajectory[20].mode, 0);
  EXPECT_EQ(own.trajectory[20].state, 4);
  EXPECT_EQ(own.trajectory[29].mode, 0);
  EXPECT_EQ(own.trajectory[40].mode, 1);  // after the mode command
  EXPECT_EQ(own.telemetry.replies, 3u);
  EXPECT_EQ(own.telemetry.crc_errors, 0u);
  EXPECT_EQ(own.telemetry.seq_gaps, 0u);
  EXPECT_EQ(own.telemetry.boot_reset_causes, std::vector<std::string>{"power_on"});
  const std::string json = read_file(options.out_dir + "/summary.json");
  EXPECT_NE(json.find("\"telemetry\": {\"frames\": " + std::to_string(own.telemetry.frames) +
                      ", \"crc_errors\": 0, \"seq_gaps\": 0, \"replies\": 3}"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"boot_reset_causes\": [\"power_on\"]"), std::string::npos);

  armsim::FirmwareTelemetry mine;
  options.telemetry = &mine;
  options.out_dir.clear();
  const auto result = armsim::run_scenario(scenario, options);
  EXPECT_EQ(result.telemetry.frames, own.telemetry.frames);
  // a boot frame, a state frame every 20 ms (the last one still on the line at the end), 3 replies
  EXPECT_GE(result.telemetry.frames, 1u + 49u + 3u);
  EXPECT_LE(result.telemetry.frames, 1u + 50u + 3u);
  ASSERT_EQ(mine.boots().size(), 1u);
  EXPECT_EQ(mine.boots()[0].reset_cause, 1);
  EXPECT_EQ(mine.boots()[0].calibration, (uint8_t)protocol::Calibration::defaults_blank);
  ASSERT_EQ(mine.replies().size(), 3u);
  EXPECT_EQ(mine.replies()[0].command_type, (uint8_t)MsgType::cmd_mode);
  EXPECT_EQ(mine.replies()[0].command_seq, 3);
  EXPECT_EQ(mine.replies()[0].status, (uint8_t)protocol::ReplyStatus::ok);
  EXPECT_EQ(mine.replies()[1].command_seq, 4);
  EXPECT_EQ(mine.replies()[1].status, (uint8_t)protocol::ReplyStatus::bad_argument);
  EXPECT_EQ(mine.replies()[2].status, (uint8_t)protocol::ReplyStatus::ok);
  const protocol::StateMsg* last = mine.last_state();
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(last->t_ms, 20u * mine.states().size());
  EXPECT_EQ(last->mode, 1);
  EXPECT_EQ(last->speed_scale_pct, 40);
  EXPECT_EQ(last->reset_cause, 1);
  EXPECT_EQ(last->rx_crc_errors, 1);  // the garbage frame
  EXPECT_EQ(last->rx_rejected, 1);    // speed 150
  EXPECT_TRUE(result.faults.empty());
}
