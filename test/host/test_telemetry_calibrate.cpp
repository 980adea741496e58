// wmra-telemetry calibrate against a board the test plays on a pseudo-terminal, with J2..J4's
// pots (noisy, mounted off the config's line) and the jog, get_calibration and pot_calibration
// commands: the whole guided calibration answered as a person would, the jog's frames, the
// readings' medians, the limits pot_calibration_from gives, the frame stored; nothing stored on
// no, quit or the input's end; the states it refuses; its command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "child_process.h"
#include "commands.h"
#include "fake_board.h"
#include "kinematics/arm_model.h"
#include "protocol_frames.h"

using namespace wmra;
using namespace wmra::protocol;
using protocol_frames::message_bytes;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kOut = TELEMETRY_TEST_OUT;
constexpr int kJ3 = 1;  // J3's index among the DC joints J2..J4

std::string test_name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }

// wmra-telemetry with these arguments, stdin from a file or a descriptor, stdout and stderr
// into kOut/NAME.out and .err
struct Tool : test::ChildProcess {
  Tool(const std::vector<std::string>& options, const std::string& stdin_path, int stdin_fd = -1)
      : test::ChildProcess(test::argv_of(TELEMETRY_BIN, options), kOut + "/" + test_name(), stdin_path, stdin_fd) {}
};

// The fake board with J2..J4 as DC joints: each stands at a true angle; its pot reads on the
// line through pot_at_min/max (where a good calibration puts the limits), with a noise cycle
// whose median is 0 and whose mean is not; the firmware's angle goes through its calibration
// (at_min/at_max, the config's to begin with). Jogs turn a joint while they come, each within
// 100 ms of the last; get_calibration and pot_calibration answer as the firmware does.
struct PotBoard : test::FakeBoard {
  double angle_deg[3] = {45, 20, 0};
  double pot_at_min[3] = {819, 1459, 819}, pot_at_max[3] = {15564, 15564, 15564};
  int16_t at_min[3] = {819, 819, 819}, at_max[3] = {15564, 15564, 15564};
  uint8_t from_command = 0;
  static constexpr int kNoise[5] = {48, -32, 0, 960, -16};  // median 0; the first, last or mean reading is off
  int readings_sent = 0;
  std::vector<int> true_readings;  // J3's, at each calibration frame sent
  std::function<bool(const Frame&)> refuse_jog = [](const Frame&) { return false; };  // a test's refusal
  double jog_gain = 1;  // the joint turns this many times the speed asked: a quicker test
  int jog_joint = 0;
  int16_t jog_mrad_s = 0;
  double last_jog_s = -1, last_tick_s = 0, now_s = 0;

  PotBoard() {
    boot_delay_s = 0;
    reply_status = [this](const Frame& f) { return status_for(f); };
  }

  static double q_min(int d) { return arm::q_min_deg[d + 1]; }
  static double q_max(int d) { return arm::q_max_deg[d + 1]; }
  int true_reading(int d) const {
    return (int)std::lround(pot_at_min[d] + (angle_deg[d] - q_min(d)) / (q_max(d) - q_min(d)) * (pot_at_max[d] - pot_at_min[d]));
  }
  double firmware_angle_deg(int d) const {
    return q_min(d) + (double)(true_reading(d) - at_min[d]) * (q_max(d) - q_min(d)) / (at_max[d] - at_min[d]);
  }

  int status_for(const Frame& f) {
    switch ((MsgType)f.type) {
      case MsgType::cmd_jog:
        if (f.payload[0] < 1 || f.payload[0] > 6) return (int)ReplyStatus::bad_argument;
        if (refuse_jog(f)) return (int)ReplyStatus::refused;
        return state == 7 || (state == 8 && f.payload[0] == jog_joint) ? 0 : (int)ReplyStatus::refused;
      case MsgType::cmd_pot_calibration: {
        if (state == 2 || state == 3 || state == 4 || state == 8) return (int)ReplyStatus::refused;  // the drives on
        PotCalibrationCmd c{};
        decode(f, c);
        if (c.joint < 2 || c.joint > 4 || c.at_min_counts_x16 < 0 || c.at_max_counts_x16 > 16368 ||
            c.at_max_counts_x16 - c.at_min_counts_x16 < 9600)
          return (int)ReplyStatus::bad_argument;
        return 0;
      }
      default: return 0;
    }
  }

  void tick(double t_s) override {
    now_s = t_s;
    if (state == 8) {
      angle_deg[jog_joint - 2] += jog_gain * jog_mrad_s / 1000.0 * (t_s - last_tick_s) * 180 / arm::kPi;
      if (t_s - last_jog_s > 0.1) state = 7;  // the jog's commands stopped: back to wait_home
    }
    last_tick_s = t_s;
  }

  void fill_state(StateMsg& s) override {
    s.switches = 1 << 10;
    for (int d = 0; d < 3; ++d) s.q_mrad[d + 1] = (int16_t)std::lround(firmware_angle_deg(d) * arm::kPi / 0.180);
  }

  void send_calibration() {
    CalibrationMsg m{};
    for (int d = 0; d < 3; ++d) {
      m.at_min_counts_x16[d] = at_min[d];
      m.at_max_counts_x16[d] = at_max[d];
      m.reading_counts_x16[d] = (int16_t)(true_reading(d) + kNoise[readings_sent % 5]);
    }
    m.from_command = from_command;
    ++readings_sent;
    true_readings.push_back(true_reading(kJ3));
    send(message_bytes(m, ++seq));
  }

  void obey(const Frame& f) override {
    switch ((MsgType)f.type) {
      case MsgType::cmd_jog: {
        JogCmd j{};
        decode(f, j);
        if (j.joint >= 2 && j.joint <= 4) {
          state = 8;
          jog_joint = j.joint;
          jog_mrad_s = j.speed_mrad_s;
          last_jog_s = now_s;
        }
        break;
      }
      case MsgType::cmd_get_calibration: send_calibration(); break;
      case MsgType::cmd_pot_calibration: {
        PotCalibrationCmd c{};
        decode(f, c);
        at_min[c.joint - 2] = c.at_min_counts_x16;
        at_max[c.joint - 2] = c.at_max_counts_x16;
        from_command |= (uint8_t)(1 << (c.joint - 2));
        send_calibration();
        break;
      }
      default: FakeBoard::obey(f);
    }
  }

  std::vector<Frame> sent_of(MsgType type) const {
    std::vector<Frame> out;
    for (const Frame& f : commands) {
      if (f.type == (uint8_t)type) out.push_back(f);
    }
    return out;
  }
};

std::string write_answers(const std::string& text) {
  const std::string path = kOut + "/" + test_name() + ".in";
  std::ofstream(path) << text;
  return path;
}

// How many prompts the tool has shown: it reads one answer after each
int prompts(const std::string& out) {
  int n = 0;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    n += line.rfind("point 1: + / - ", 0) == 0 || line.rfind("point 2 (at least ", 0) == 0 || line == "store? (yes/no)";
  }
  return n;
}

// Plays the board and answers the tool's prompts as they come, the k-th prompt with answers[k]()
// (a person looking at the arm); the tool's input closes after the last answer. Its exit status.
int converse(PotBoard& board, Tool& tool, int input_fd, const std::vector<std::function<std::string()>>& answers, double max_s) {
  signal(SIGPIPE, SIG_IGN);  // a tool that ended early: a failed write, not the test's end
  size_t next = 0;
  const auto start = Clock::now();
  while (test::FakeBoard::seconds_since(start) < max_s) {
    const int status = board.serve(tool, 0.02);
    if (status >= 0) return status;
    if (next < answers.size() && prompts(tool.out()) > (int)next) {
      const std::string line = answers[next++]() + "\n";
      EXPECT_EQ(write(input_fd, line.data(), line.size()), (ssize_t)line.size());
      if (next == answers.size()) close(input_fd);
    }
  }
  return -1;
}

std::string text(double v, const char* f = "%.2f") {
  char s[32];
  std::snprintf(s, sizeof s, f, v);
  return s;
}

// The numbers of every line that matches: "J3 reads (\d+) ..." -> each match's groups
std::vector<std::smatch> matches(const std::string& out, const std::string& pattern) {
  std::vector<std::smatch> found;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator(); ++it) found.push_back(*it);
  return found;
}

int16_t payload_int16(const Frame& f, int at) { return (int16_t)(f.payload[at] | f.payload[at + 1] << 8); }

}  // namespace

// The whole calibration, answered with the true angles of a J3 whose pot is mounted off the
// config's line: the readings are the medians, the limits pot_calibration_from's for the points
// shown (and the pot's true ones within rounding), the pot_calibration frame carries them, and
// the firmware's angle afterwards is the angle typed
TEST(TelemetryCalibrate, StoresTheLimitsTheTwoMeasuredPointsGive) {
  PotBoard board;
  ASSERT_FALSE(board.port.empty());
  int in[2];
  ASSERT_EQ(pipe2(in, O_CLOEXEC), 0);  // the tool holds no write end: the input can end
  Tool tool({"calibrate", board.port, "3"}, "", in[0]);
  close(in[0]);
  ASSERT_NE(tool.pid, 0);
  auto true_angle = [&] { return text(board.angle_deg[kJ3]); };
  const int status = converse(board, tool, in[1], {[] { return "+ 2"; }, true_angle, [] { return "- 4"; }, true_angle, [] { return "yes"; }}, 30);
  const std::string out = tool.out();
  ASSERT_EQ(status, 0) << out << tool.err();

  // every reading shown is the joint's true reading there (the median of the noisy five), and
  // the firmware's angle the one its calibration gives that reading
  const std::set<int> true_readings(board.true_readings.begin(), board.true_readings.end());
  const auto reads = matches(out, "J3 reads (\\d+) \\(counts x 16\\), the firmware's angle (-?[0-9.]+) deg\n");
  ASSERT_EQ(reads.size(), 4u) << out;  // at the start, after each jog, after storing
  for (size_t i = 0; i < reads.size(); ++i) {
    const int r = std::stoi(reads[i][1]);
    EXPECT_EQ(true_readings.count(r), 1u) << r << "\n" << out;
    const int16_t lo = i < 3 ? 819 : board.at_min[kJ3], hi = i < 3 ? 15564 : board.at_max[kJ3];
    EXPECT_EQ(reads[i][2], text(-135 + (r - lo) * 295.0 / (hi - lo))) << out;
  }
  EXPECT_EQ(board.readings_sent, 5 * 6 + 1);  // five at the start, after each jog, at each point, after storing; the store's

  // the points: a fresh reading at each typed angle; the limits are pot_calibration_from's
  const auto points = matches(out, "point ([12]): (\\d+) at (-?[0-9.]+) deg \\(the firmware's angle (-?[0-9.]+) deg\\)\n");
  ASSERT_EQ(points.size(), 2u) << out;
  const int r1 = std::stoi(points[0][2]), r2 = std::stoi(points[1][2]);
  const double a1 = std::stod(points[0][3]), a2 = std::stod(points[1][3]);
  EXPECT_EQ(true_readings.count(r1), 1u);
  EXPECT_GT(a1, 20 + 10);  // 2 s at 0.1 rad/s: 11.5 deg and the slowing
  EXPECT_LT(a2, a1 - 20);
  const PotCalibrationCmd expected = telemetry_cli::pot_calibration_from(3, r1, a1, r2, a2);
  EXPECT_NEAR(expected.at_min_counts_x16, 1459, 16);  // the pot's own line, to the count and the typed angles' 0.01 deg
  EXPECT_NEAR(expected.at_max_counts_x16, 15564, 16);
  const std::string limits = std::to_string(expected.at_min_counts_x16) + ".." + std::to_string(expected.at_max_counts_x16);
  EXPECT_NE(out.find("limits: J3 " + limits + " (counts x 16 at -135..160 deg), now 819..15564 (config)\n"), std::string::npos) << out;
  const auto then = matches(out, "with it the firmware reads (-?[0-9.]+) deg here \\(now (-?[0-9.]+) deg\\)\nstore\\? \\(yes/no\\)\n");
  ASSERT_EQ(then.size(), 1u) << out;
  EXPECT_NEAR(std::stod(then[0][1]), a2, 0.021);  // the limits' readings rounded to the count
  EXPECT_EQ(then[0][2], points[1][4]);

  // the frame stored, and the firmware's angle with it
  const std::vector<Frame> stored = board.sent_of(MsgType::cmd_pot_calibration);
  ASSERT_EQ(stored.size(), 1u);
  ASSERT_EQ(stored[0].len, 5);
  EXPECT_EQ(stored[0].payload[0], 3);
  EXPECT_EQ(payload_int16(stored[0], 1), expected.at_min_counts_x16);
  EXPECT_EQ(payload_int16(stored[0], 3), expected.at_max_counts_x16);
  EXPECT_NE(out.find("> yes\nstored: J3 " + limits + " (set)\nJ3 reads " + std::to_string(r2) + " (counts x 16)"), std::string::npos) << out;
  EXPECT_NEAR(std::stod(reads[3][2]), a2, 0.021);
  EXPECT_EQ(tool.err(), "");
  // nothing but these commands, and no status lines
  for (const Frame& f : board.commands) {
    EXPECT_TRUE(f.type == (uint8_t)MsgType::cmd_jog || f.type == (uint8_t)MsgType::cmd_get_calibration ||
                f.type == (uint8_t)MsgType::cmd_pot_calibration)
        << (int)f.type;
  }
  EXPECT_EQ(out.find(" faults: "), std::string::npos) << out;
}

// + SECONDS and - SECONDS: a jog frame of J3 at +-0.1 rad/s every 40 ms for that long, each under
// a seq of its own; the joint at rest (the jog over) before it is read
TEST(TelemetryCalibrate, JogsSendAFrameEvery40msForTheSecondsAsked) {
  PotBoard board;
  ASSERT_FALSE(board.port.empty());
  Tool tool({"calibrate", board.port, "3"}, write_answers("+ 1.5\n-\t0.5 # back a little\nq\n"));
  ASSERT_NE(tool.pid, 0);
  EXPECT_EQ(board.serve(tool, 20), 1) << tool.err();
  const std::string out = tool.out();
  const std::vector<Frame> jogs = board.sent_of(MsgType::cmd_jog);
  std::vector<double> at_s;
  for (size_t i = 0; i < board.commands.size(); ++i) {
    if (board.commands[i].type == (uint8_t)MsgType::cmd_jog) at_s.push_back(board.command_at_s[i]);
  }
  size_t up = 0;
  while (up < jogs.size() && payload_int16(jogs[up], 1) == 100) ++up;
  const size_t down = jogs.size() - up;
  EXPECT_GE(up, 34u) << out;  // 1.5 s / 40 ms: 38, fewer on a loaded machine
  EXPECT_LE(up, 38u) << out;
  EXPECT_GE(down, 11u) << out;  // 0.5 s: 13
  EXPECT_LE(down, 13u) << out;
  for (size_t i = 0; i < jogs.size(); ++i) {
    EXPECT_EQ(jogs[i].payload[0], 3);
    EXPECT_EQ(payload_int16(jogs[i], 1), i < up ? 100 : -100) << i;
    if (i > 0 && i != up) {
      EXPECT_EQ((uint8_t)(jogs[i].seq - jogs[i - 1].seq), 1);
    }
  }
  ASSERT_EQ(at_s.size(), up + down);
  EXPECT_GE(at_s[up - 1] - at_s[0], 0.039 * (up - 1));
  EXPECT_LE(at_s[up - 1] - at_s[0], 1.5);
  // the joint read once the jog is over: the firmware ends it 100 ms after its last frame
  size_t read = 0;
  while (read < board.commands.size() && board.command_at_s[read] <= at_s[up - 1]) ++read;
  ASSERT_LT(read, board.commands.size());
  EXPECT_EQ(board.commands[read].type, (uint8_t)MsgType::cmd_get_calibration);
  EXPECT_GE(board.command_at_s[read] - at_s[up - 1], 0.1);
  EXPECT_NE(out.find("> + 1.5\njog J3 at +0.1 rad/s for 1.5 s: " + std::to_string(up) + " frames: " + std::to_string(up) + " ok\nJ3 reads "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("> -\t0.5 # back a little\njog J3 at -0.1 rad/s for 0.5 s: " + std::to_string(down) + " frames: " +
                     std::to_string(down) + " ok\nJ3 reads "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("> q\nnot stored (quit)\n"), std::string::npos) << out;
  EXPECT_TRUE(board.sent_of(MsgType::cmd_pot_calibration).empty());
}

// no, quit and the input's end store nothing (exit 1); nor does the firmware's refusal
TEST(TelemetryCalibrate, NothingIsStoredWithoutYes) {
  struct Case {
    std::vector<const char*> answers;  // "=": the joint's true angle
    const char* ends_with;
    int refuse_store;  // the board's reply to pot_calibration: 0 ok
  };
  const Case cases[] = {
      {{"+ 0.3", "=", "- 0.6", "=", "no"}, "> no\nnot stored\n", 0},
      {{"+ 0.3", "=", "- 0.6"}, "not stored: the input ended before yes\n", 0},
      {{"+ 0.3", "quit"}, "> quit\nnot stored (quit)\n", 0},
      {{"+ 0.3", "=", "- 0.6", "=", "yes"}, "> yes\nnot stored: the firmware answers bad_argument: it takes readings within "
                                           "0..16368, at least 9600 apart, the joint's reading now within 320 of them\n", 3},
  };
  for (const Case& c : cases) {
    PotBoard board;
    ASSERT_FALSE(board.port.empty());
    board.jog_gain = 5;
    const int refuse = c.refuse_store;
    board.reply_status = [&board, refuse](const Frame& f) {
      return f.type == (uint8_t)MsgType::cmd_pot_calibration && refuse ? refuse : board.status_for(f);
    };
    int in[2];
    ASSERT_EQ(pipe2(in, O_CLOEXEC), 0);  // the tool holds no write end: the input can end
    Tool tool({"calibrate", board.port, "3"}, "", in[0]);
    close(in[0]);
    ASSERT_NE(tool.pid, 0);
    std::vector<std::function<std::string()>> answers;
    for (const std::string a : c.answers) {
      answers.push_back([&board, a] { return a == "=" ? text(board.angle_deg[kJ3]) : a; });
    }
    EXPECT_EQ(converse(board, tool, in[1], answers, 20), 1) << c.ends_with << tool.err();
    const std::string out = tool.out();
    EXPECT_EQ(out.substr(out.size() - std::min(out.size(), std::strlen(c.ends_with))), c.ends_with) << out;
    EXPECT_EQ(board.sent_of(MsgType::cmd_pot_calibration).size(), refuse ? 1u : 0u) << c.ends_with;
    EXPECT_EQ(board.from_command, 0);
    EXPECT_FALSE(board.sent_of(MsgType::cmd_jog).empty());
  }
}

// A pot whose reading falls as the angle rises: pot_calibration_from's message, and both points
// asked again; points under 10 deg apart: said, and point 2 asked again
TEST(TelemetryCalibrate, PointsThatMakeNoCalibrationAreAskedAgain) {
  PotBoard board;  // J3 at 20 deg; a jog of 1 s turns it about 6 deg, 0.5 s 3 deg
  ASSERT_FALSE(board.port.empty());
  Tool tool({"calibrate", board.port, "3"}, write_answers("+ 1\n10\n- 2\n30\n+ 1\n30\n- 0.5\n25\n- 2\n10\nno\n"));
  ASSERT_NE(tool.pid, 0);
  EXPECT_EQ(board.serve(tool, 30), 1) << tool.err();
  const std::string out = tool.out();
  EXPECT_NE(out.find("> 30\npoint 2: "), std::string::npos) << out;
  EXPECT_NE(out.find("these points make no calibration: the pot's reading falls as the joint's angle rises: it is wired "
                     "reversed, swap its two outer wires (docs/arm-guide.md) and read it again\ntake the two points again\n"
                     "point 1: + / - [SECONDS] jogs J3"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find(" at 25 deg (the firmware's angle "), std::string::npos) << out;
  EXPECT_NE(out.find("point 2 is 5.0 deg from point 1: the points must be at least 10 deg apart; jog further and type the "
                     "angle there\npoint 2 (at least 10 deg from 30): "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find(" at 10 deg (the firmware's angle "), std::string::npos) << out;
  EXPECT_NE(out.find("store? (yes/no)\n> no\nnot stored\n"), std::string::npos) << out;
  EXPECT_EQ(tool.err(), "");
  EXPECT_TRUE(board.sent_of(MsgType::cmd_pot_calibration).empty());
}

// A point pairs the typed angle with the reading shown, where the person measured; a joint that
// has moved since by more than the pot's noise (a hand on the arm) is read again and its angle
// asked again
TEST(TelemetryCalibrate, APointTakesTheReadingShownUnlessTheJointHasMoved) {
  for (const double moved_deg : {0.2, 2.0}) {  // 10 counts x 16, within a count's noise; 96
    PotBoard board;
    ASSERT_FALSE(board.port.empty());
    const int shown = board.true_reading(kJ3);
    int in[2];
    ASSERT_EQ(pipe2(in, O_CLOEXEC), 0);
    Tool tool({"calibrate", board.port, "3"}, "", in[0]);
    close(in[0]);
    ASSERT_NE(tool.pid, 0);
    const auto hand_and_angle = [&] {
      board.angle_deg[kJ3] += moved_deg;
      return std::string("20");
    };
    EXPECT_EQ(converse(board, tool, in[1], {hand_and_angle, [] { return "q"; }}, 20), 1) << tool.err();
    const std::string out = tool.out();
    const std::string read_again = "> 20\nJ3 has moved since it was read:\nJ3 reads " + std::to_string(board.true_reading(kJ3)) +
                                   " (counts x 16), the firmware's angle " + text(board.firmware_angle_deg(kJ3)) +
                                   " deg\nmeasure its angle there and type it again\npoint 1: + / - ";
    if (moved_deg < 1) {
      EXPECT_NE(out.find("> 20\npoint 1: " + std::to_string(shown) + " at 20 deg"), std::string::npos) << out;
      EXPECT_NE(board.true_reading(kJ3), shown);
    } else {
      EXPECT_NE(out.find(read_again), std::string::npos) << out;
      EXPECT_EQ(out.find(" at 20 deg"), std::string::npos) << out;
    }
  }
}

// Lines that are none of the answers: a message naming the line, the prompt again, the rest
// still used; exit 2 at the end even though it stored
TEST(TelemetryCalibrate, BadLinesAreAskedAgainAndExitTwo) {
  PotBoard board;
  ASSERT_FALSE(board.port.empty());
  Tool tool({"calibrate", board.port, "3"},
            write_answers("# J3, a script\n\nhello there\n+ 50\n+1\n+ 1\n400\n26\n- 2\n14\nmaybe\nyes\n"));
  ASSERT_NE(tool.pid, 0);
  EXPECT_EQ(board.serve(tool, 30), 2) << tool.err();
  const std::string out = tool.out(), err = tool.err();
  EXPECT_EQ(err, "wmra-telemetry: line 3: type + or - [SECONDS] to jog J3, the angle you measure in deg, or q to quit; not 'hello there'\n"
                 "wmra-telemetry: line 4: SECONDS (of the jog) must be a number from 0.1 to 20, not '50'\n"
                 "wmra-telemetry: line 5: '+1': a jog is + or - with a space before SECONDS, an angle has no + sign\n"
                 "wmra-telemetry: line 7: the angle (deg, within J3's limits) must be a number from -135 to 160, not '400'\n"
                 "wmra-telemetry: line 11: type yes or no (q quits)\n"
                 "wmra-telemetry: lines not used: 5\n");
  EXPECT_NE(out.find("> hello there\npoint 1: + / - [SECONDS] jogs J3"), std::string::npos) << out;
  EXPECT_NE(out.find("> maybe\nstore? (yes/no)\n> yes\nstored: J3 "), std::string::npos) << out;
  EXPECT_EQ(board.sent_of(MsgType::cmd_pot_calibration).size(), 1u);
  const size_t jogs = board.sent_of(MsgType::cmd_jog).size();  // 1 s and 2 s: 75 frames; none for 50 s
  EXPECT_GE(jogs, 68u);
  EXPECT_LE(jogs, 75u);
}

// A jog the firmware refuses: its reply and what it means; a fault while calibrating: shown
TEST(TelemetryCalibrate, RefusedJogsAndFaultsAreShown) {
  PotBoard board;
  ASSERT_FALSE(board.port.empty());
  int jogs = 0;
  board.refuse_jog = [&](const Frame&) {
    if (++jogs == 5) {  // J3's motor stalls: a latched fault, the arm held
      board.state = 6;
      board.faults = 1u << 4;
    }
    return board.state == 6;
  };
  Tool tool({"calibrate", board.port, "3"}, write_answers("+ 1\nq\n"));
  ASSERT_NE(tool.pid, 0);
  EXPECT_EQ(board.serve(tool, 20), 1) << tool.err();
  const std::string out = tool.out();
  const std::string frames = std::to_string(board.sent_of(MsgType::cmd_jog).size());
  EXPECT_NE(out.find("faults: j3_stall\nthe arm is now fault\n"), std::string::npos) << out;
  EXPECT_NE(out.find("jog J3 at +0.1 rad/s for 1 s: " + frames + " frames: 4 ok, " + std::to_string(jogs - 4) + " refused\n"
                     "  refused: the firmware jogs a joint only while the arm waits before homing (wait_home) or runs "
                     "with the stick neutral; it is fault now, faults: j3_stall\nJ3 reads "),
            std::string::npos)
      << out;
  EXPECT_TRUE(board.sent_of(MsgType::cmd_pot_calibration).empty());
}

// The arm not waiting before homing: what to do, exit 1, and nothing sent at all
TEST(TelemetryCalibrate, OtherStatesAreRefusedWithWhatToDo) {
  struct Case {
    uint8_t state;
    uint32_t faults;
    const char* message;
  };
  const Case cases[] = {
      {4, 0, "the arm is homed (running): switch it off and on (or reset it) and run calibrate again; a pot is calibrated before homing"},
      {5, 0, "the arm is stopped: release the safety button and re-arm it (a long press), then run calibrate again"},
      {6, 1u << 4 | 1u << 14, "the arm is faulted (j3_stall, tracking): deal with the cause (docs/arm-guide.md), re-arm it"},
      {2, 0, "the arm is homing (homing): a pot is calibrated before homing, with the drives off"},
  };
  for (const Case& c : cases) {
    PotBoard board;
    ASSERT_FALSE(board.port.empty());
    board.state = c.state;
    board.faults = c.faults;
    Tool tool({"calibrate", board.port, "3"}, write_answers("+ 1\n30\n- 2\n10\nyes\n"));
    ASSERT_NE(tool.pid, 0);
    EXPECT_EQ(board.serve(tool, 20), 1) << tool.err();
    EXPECT_EQ(tool.err().rfind(std::string("wmra-telemetry: ") + c.message, 0), 0u) << tool.err();
    EXPECT_NE(tool.err().find("; nothing sent\n"), std::string::npos) << tool.err();
    EXPECT_TRUE(board.commands.empty()) << (int)c.state << ": " << board.commands.size() << " commands";
    EXPECT_EQ(tool.out().find("J3 reads"), std::string::npos) << tool.out();
  }
}

// A Mega just reset: the boot frame after its bootloader, then wait_neutral until the stick has
// been neutral; the calibration begins once it waits before homing
TEST(TelemetryCalibrate, WaitsWhileTheArmArms) {
  PotBoard board;
  ASSERT_FALSE(board.port.empty());
  board.boot_delay_s = 1.0;
  board.state = 1;
  Tool tool({"calibrate", board.port, "4"}, write_answers("q\n"));
  ASSERT_NE(tool.pid, 0);
  int status = -1;
  while (status < 0 && (!board.open || test::FakeBoard::seconds_since(board.opened) < 3.5)) status = board.serve(tool, 0.05);
  board.state = 7;  // the stick neutral long enough
  if (status < 0) status = board.serve(tool, 20);
  EXPECT_EQ(status, 1) << tool.err();
  const std::string out = tool.out();
  EXPECT_NE(out.find("the arm is in wait_neutral: waiting up to 8 s for it to wait before homing (release the joystick)\n"
                     "the arm waits before homing (wait_home): J4 may be jogged and its pot calibrated\nJ4 reads " +
                     std::to_string(board.true_reading(2)) + " (counts x 16), the firmware's angle " + text(board.firmware_angle_deg(2)) + " deg\n"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("calibration now: J4 819..15564 (config)\n"), std::string::npos) << out;
  EXPECT_GE(board.command_at_s.at(0), 3.5);
}

// calibrate's command line: J 2..4, DEVICE J, --help; a port that cannot be opened or that
// says nothing: exit 3
TEST(TelemetryCalibrate, CommandLine) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"calibrate"}, {"calibrate", "/dev/ttyACM0"}, {"calibrate", "--help", "3"}, {"calibrate", "/dev/ttyACM0", "3", "4"}}) {
    Tool bad(args, "/dev/null");
    EXPECT_EQ(bad.exit_status(true), 2) << args.size();
    EXPECT_EQ(bad.out(), "");
    EXPECT_EQ(bad.err().rfind("wmra-telemetry: calibrate takes DEVICE J\nusage:", 0), 0u) << bad.err();
  }
  for (const char* j : {"1", "5", "x"}) {
    Tool bad({"calibrate", "/dev/ttyACM0", j}, "/dev/null");
    EXPECT_EQ(bad.exit_status(true), 2);
    EXPECT_EQ(bad.err().rfind(std::string("wmra-telemetry: J (the DC joint: 2, 3 or 4) must be a whole number from 2 to 4, not '") +
                                  j + "'\nusage:",
                              0),
              0u)
        << bad.err();
  }
  Tool help({"--help"}, "/dev/null");
  EXPECT_EQ(help.exit_status(true), 0);
  EXPECT_NE(help.out().find("       wmra-telemetry calibrate DEVICE J\n"), std::string::npos) << help.out();

  const auto start = Clock::now();
  Tool missing({"calibrate", "/nonexistent/ttyACM9", "3"}, "/dev/null");
  EXPECT_EQ(missing.exit_status(true), 3);
  EXPECT_LT(test::FakeBoard::seconds_since(start), 2);
  EXPECT_EQ(missing.err(), "wmra-telemetry: /nonexistent/ttyACM9: No such file or directory\n");

  PotBoard silent;
  ASSERT_FALSE(silent.port.empty());
  silent.boot_delay_s = 100;
  Tool quiet({"calibrate", silent.port, "3"}, "/dev/null");
  EXPECT_EQ(silent.serve(quiet, 10), 3);
  EXPECT_EQ(quiet.err(), "wmra-telemetry: " + silent.port + ": no state frame in 4 s (the firmware running? the right port?)\n");
  EXPECT_TRUE(silent.commands.empty());
}
