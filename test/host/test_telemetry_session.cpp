// wmra-telemetry session against a board the test plays on a pseudo-terminal (boot frame,
// state frames, replies), and the command line's conventions: decode of hex text, --help,
// --version, usage errors, a device that cannot be opened.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include "child_process.h"
#include "fake_board.h"
#include "protocol/parser.h"
#include "protocol_frames.h"

using namespace wmra;
using namespace wmra::protocol;
using protocol_frames::frame_bytes;
using protocol_frames::message_bytes;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kOut = TELEMETRY_TEST_OUT;

using test::FakeBoard;
using test::read_file;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string test_name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }

// wmra-telemetry with these arguments, stdin from a file (or the fd given), stdout and stderr
// into kOut/NAME.out and .err
struct Tool : test::ChildProcess {
  Tool(const std::vector<std::string>& options, const std::string& stdin_path, int stdin_fd = -1)
      : test::ChildProcess(test::argv_of(TELEMETRY_BIN, options), kOut + "/" + test_name(), stdin_path, stdin_fd) {}
};

std::string write_commands(const std::string& text) {
  const std::string path = kOut + "/" + test_name() + ".in";
  std::ofstream(path) << text;
  return path;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace

// The whole conversation: the boot frame waited for before the first command, each command's
// reply, the info frame's lines, status lines when the state or mode changes, exit 0
TEST(TelemetrySession, SendsEachLineAndShowsItsReply) {
  FakeBoard board;
  ASSERT_FALSE(board.port.empty());
  board.reply_status = [](const Frame& f) { return f.type == (uint8_t)MsgType::cmd_home ? 4 : 0; };  // home: refused
  Tool tool({"session", board.port}, write_commands("info\nmode xz\n# a comment\n\n  home  # refused here\nsleep 0.3\nstop\nsleep 0.1\nrearm\nsleep 0.1\n"));
  ASSERT_NE(tool.pid, 0);
  const int status = board.serve(tool, 20);
  const std::string out = tool.out(), err = tool.err();
  EXPECT_EQ(status, 0) << err;

  // the commands, in order, with their seq counting up; the first after the boot frame
  ASSERT_EQ(board.commands.size(), 5u) << out;
  const MsgType sent[] = {MsgType::cmd_info, MsgType::cmd_mode, MsgType::cmd_home, MsgType::cmd_stop, MsgType::cmd_rearm};
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(board.commands[i].type, (uint8_t)sent[i]) << i;
    EXPECT_EQ((uint8_t)(board.commands[i].seq - board.commands[0].seq), i) << i;
  }
  EXPECT_GE(board.command_at_s[0], board.booted_at_s);
  EXPECT_GE(board.command_at_s[3] - board.command_at_s[2], 0.295);  // sleep 0.3 (the board's own clock reads +-2 ms)

  EXPECT_NE(out.find("boot: firmware 1.2.3, commit 85e4ee73d90a (clean), config f67e1bfa; reset: power_on; settings: eeprom; j6 angle: none\n"),
            std::string::npos)
      << out;
  const std::string info = "> info: ok\ninfo: firmware 1.2.3, commit 85e4ee73d90a (clean), config f67e1bfa; loop 1000 Hz\n"
                           "info: hand 150 mm/s, wrist 45.8 deg/s at full stick\n"
                           "info: joint speed limits deg/s: 45.8 57.3 57.3 91.7 85.9 85.9\n"
                           "info: soft limits deg:  J1 -87.0..87.0  J2 -42.0..132.0  J3 -132.0..157.0  J4 -157.0..157.0  J5 -87.0..87.0  J6 -357.0..357.0\n";
  EXPECT_NE(out.find(info), std::string::npos) << out;
  for (const char* reply : {"> mode xz: ok\n", "> home: refused\n", "> stop: ok\n", "> rearm: ok\n"}) {
    EXPECT_NE(out.find(reply), std::string::npos) << reply << "\n" << out;
  }
  // a status line at the first state frame and at every change, with the fields in their order
  std::vector<std::string> status_lines;
  for (const std::string& line : lines_of(out)) {
    if (line.find("  faults: ") != std::string::npos) status_lines.push_back(line);
  }
  ASSERT_GE(status_lines.size(), 3u) << out;
  EXPECT_NE(status_lines[0].find(" s  wait_home    x"), std::string::npos) << status_lines[0];
  EXPECT_NE(status_lines[0].find("       faults: none  switches: j6_zero  q deg: 0.0 45.0 0.0 0.0 0.0 0.0"), std::string::npos)
      << status_lines[0];
  std::string states;  // "state mode|" at each change (the lines once a second left out)
  for (const std::string& line : status_lines) {
    const std::string now = line.substr(11, 20) + "|";
    if (states.size() < now.size() || states.compare(states.size() - now.size(), now.size(), now) != 0) states += now;
  }
  EXPECT_NE(states.find("wait_home    xz     |stopped      xz     |running      xz     |"), std::string::npos) << states << "\n" << out;
  EXPECT_NE(err.find("A Mega resets when its port is first opened"), std::string::npos) << err;
  EXPECT_NE(err.find("commands: 5 sent, 5 replied; lines not used: 0\n"), std::string::npos) << err;
  // the lines in order: each reply after its command's, the info frame's after its reply
  EXPECT_LT(out.find("boot: "), out.find("> info: ok\n"));
  EXPECT_LT(out.find("> mode xz: ok\n"), out.find("> home: refused\n"));
  EXPECT_LT(out.find("> home: refused\n"), out.find("> stop: ok\n"));
  EXPECT_LT(out.find("> stop: ok\n"), out.find("> rearm: ok\n"));
}

// A board that does not answer: "no reply" after 1 s, the next line then sent. A line that
// cannot be used: a message, the others still sent, a non-zero exit at the end.
TEST(TelemetrySession, NoReplyAndBadLines) {
  FakeBoard board;
  ASSERT_FALSE(board.port.empty());
  board.boot_delay_s = 0;
  board.reply_status = [](const Frame& f) { return f.type == (uint8_t)MsgType::cmd_goto_pose ? -1 : 0; };
  Tool tool({"session", board.port}, write_commands("goto 1\nfrobnicate 3\nspeed 500\njog 2\nsleep x\nstop\n"));
  ASSERT_NE(tool.pid, 0);
  const auto start = Clock::now();
  const int status = board.serve(tool, 20);
  const std::string out = tool.out(), err = tool.err();
  EXPECT_EQ(status, 2) << err;
  ASSERT_EQ(board.commands.size(), 2u) << out;
  EXPECT_EQ(board.commands[1].type, (uint8_t)MsgType::cmd_stop);
  EXPECT_NEAR(board.command_at_s[1] - board.command_at_s[0], 1.0, 0.3);  // the wait for goto's reply
  EXPECT_LT(seconds_since(start), 5);
  EXPECT_NE(out.find("> goto 1: no reply\n"), std::string::npos) << out;
  EXPECT_NE(out.find("> stop: ok\n"), std::string::npos) << out;
  EXPECT_NE(err.find("wmra-telemetry: line 2: unknown command 'frobnicate'\n"), std::string::npos) << err;
  EXPECT_NE(err.find("wmra-telemetry: line 3: speed (percent) must be a whole number from 0 to 100, not '500'\n"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("wmra-telemetry: line 4: jog takes J RAD_S [SECONDS]\n"), std::string::npos) << err;
  EXPECT_NE(err.find("wmra-telemetry: line 5: sleep (seconds) must be a number"), std::string::npos) << err;
  EXPECT_NE(err.find("lines not used: 4\n"), std::string::npos) << err;
}

// jog J RAD_S SECONDS: the frame every 40 ms for SECONDS, each with its own seq, the first reply
// and a summary of them all
TEST(TelemetrySession, JogRepeatsItsFrameEvery40ms) {
  FakeBoard board;
  ASSERT_FALSE(board.port.empty());
  board.boot_delay_s = 0;
  board.reply_status = [](const Frame& f) { return f.type == (uint8_t)MsgType::cmd_jog && f.seq % 2 ? 4 : 0; };
  Tool tool({"session", board.port}, write_commands("jog 2 -0.05 0.6\n"));
  ASSERT_NE(tool.pid, 0);
  const int status = board.serve(tool, 20);
  const std::string out = tool.out();
  EXPECT_EQ(status, 0) << tool.err();
  ASSERT_GE(board.commands.size(), 12u) << out;  // 0.6 s / 40 ms: 15, fewer on a loaded machine
  EXPECT_LE(board.commands.size(), 16u) << out;
  for (size_t i = 0; i < board.commands.size(); ++i) {
    EXPECT_EQ(board.commands[i].type, (uint8_t)MsgType::cmd_jog);
    EXPECT_EQ(board.commands[i].payload[0], 2);
    EXPECT_EQ((int16_t)(board.commands[i].payload[1] | board.commands[i].payload[2] << 8), -50);
    if (i > 0) {
      EXPECT_EQ((uint8_t)(board.commands[i].seq - board.commands[i - 1].seq), 1);
    }
  }
  const double span_s = board.command_at_s.back() - board.command_at_s.front();
  EXPECT_GE(span_s, 0.039 * (board.commands.size() - 1));
  EXPECT_LE(span_s, 0.7);
  const int n = (int)board.commands.size();
  int odd = 0;
  for (const Frame& f : board.commands) odd += f.seq % 2;
  const std::string first = board.commands[0].seq % 2 ? "refused" : "ok";
  EXPECT_NE(out.find("> jog 2 -0.05 0.6: " + first + "\n"), std::string::npos) << out;
  EXPECT_NE(out.find("> jog 2 -0.05 0.6: " + std::to_string(n) + " frames: " + std::to_string(n - odd) + " ok, " +
                     std::to_string(odd) + " refused\n"),
            std::string::npos)
      << out;
}

// --json: every frame as decode prints it, one a line, stdout nothing else
TEST(TelemetrySession, JsonPrintsEveryFrame) {
  FakeBoard board;
  ASSERT_FALSE(board.port.empty());
  board.boot_delay_s = 0;
  Tool tool({"session", board.port, "--json"}, write_commands("mode r1\nsleep 0.2\n"));
  ASSERT_NE(tool.pid, 0);
  EXPECT_EQ(board.serve(tool, 20), 0) << tool.err();
  const std::vector<std::string> lines = lines_of(tool.out());
  ASSERT_GE(lines.size(), 10u);  // 0.2 s of state frames and more
  for (const std::string& line : lines) EXPECT_EQ(line.rfind("{\"type\":\"", 0), 0u) << line;
  EXPECT_EQ(lines[0].rfind("{\"type\":\"boot\",\"seq\":0,\"reset_cause\":[\"power_on\"]", 0), 0u) << lines[0];
  EXPECT_NE(tool.out().find("{\"type\":\"reply\",\"seq\":"), std::string::npos);
  EXPECT_NE(tool.out().find(",\"command\":\"mode\",\"command_seq\":1,\"status\":\"ok\"}\n"), std::string::npos) << tool.out();
  EXPECT_NE(tool.out().find("\"state\":\"wait_home\",\"mode\":\"r1\""), std::string::npos);
  EXPECT_NE(tool.err().find("> mode r1: ok\n"), std::string::npos) << tool.err();
}

// SIGINT while it waits for the person's next line: it ends at once, with its summary
TEST(TelemetrySession, SigintEndsItPromptly) {
  FakeBoard board;
  ASSERT_FALSE(board.port.empty());
  board.boot_delay_s = 0;
  int in[2];
  ASSERT_EQ(pipe(in), 0);
  Tool tool({"session", board.port}, "", in[0]);
  close(in[0]);
  ASSERT_NE(tool.pid, 0);
  const std::string line = "stop\n";
  ASSERT_EQ(write(in[1], line.data(), line.size()), (ssize_t)line.size());
  EXPECT_EQ(board.serve(tool, 1.0), -1);  // still running: stdin is open
  const auto signalled = Clock::now();
  kill(tool.pid, SIGINT);
  EXPECT_EQ(board.serve(tool, 5), 0);
  EXPECT_LT(seconds_since(signalled), 0.5);
  close(in[1]);
  EXPECT_NE(tool.out().find("> stop: ok\n"), std::string::npos) << tool.out();
  EXPECT_NE(tool.out().find("stopped"), std::string::npos) << tool.out();  // status lines went on meanwhile
  EXPECT_NE(tool.err().find("commands: 1 sent, 1 replied"), std::string::npos) << tool.err();
}

TEST(TelemetrySession, AMissingDeviceExitsWithThreeAtOnce) {
  const auto start = Clock::now();
  Tool tool({"session", "/nonexistent/ttyACM9"}, "/dev/null");
  EXPECT_EQ(tool.exit_status(true), 3);
  EXPECT_LT(seconds_since(start), 2);
  EXPECT_EQ(tool.err(), "wmra-telemetry: /nonexistent/ttyACM9: No such file or directory\n");
  Tool not_a_port({"session", "/dev/null"}, "/dev/null");
  EXPECT_EQ(not_a_port.exit_status(true), 3);
  EXPECT_NE(not_a_port.err().find("/dev/null: not a serial port"), std::string::npos) << not_a_port.err();
}

// `encode ... | decode`: hex text decodes as the bytes it spells, spaces and lines anywhere
TEST(TelemetryCommandLine, DecodeTakesHexText) {
  const std::string bin = TELEMETRY_BIN;
  auto run = [&](const std::string& command) {
    const std::string err_path = kOut + "/" + test_name() + ".err";
    FILE* p = popen((command + " 2> " + err_path).c_str(), "r");
    std::string out;
    char buf[4096];
    for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    const int status = pclose(p);
    return std::array<std::string, 3>{std::to_string(WEXITSTATUS(status)), out, read_file(err_path)};
  };
  auto r = run(bin + " encode stop | " + bin + " decode");
  EXPECT_EQ(r[0], "0") << r[2];
  EXPECT_EQ(r[1], "{\"type\":\"command\",\"command\":\"stop\",\"seq\":0}\n");
  EXPECT_EQ(r[2], "wmra-telemetry: frames 1, crc errors 0, framing errors 0, skipped bytes 0, seq gaps 0\n");
  r = run("(" + bin + " encode mode xz --seq 3; " + bin + " encode speed 50 --seq 4) | " + bin + " decode");
  EXPECT_EQ(r[1], "{\"type\":\"command\",\"command\":\"mode\",\"seq\":3,\"mode\":\"xz\"}\n"
                  "{\"type\":\"command\",\"command\":\"speed_scale\",\"seq\":4,\"speed_scale_pct\":50}\n");
  r = run("printf 'A5 03 10 00 00\\n7F 5C\\n' | " + bin + " decode");  // upper case, spaced, over lines
  EXPECT_EQ(r[1], "{\"type\":\"command\",\"command\":\"stop\",\"seq\":0}\n");
  r = run("printf 'a5031000007f5' | " + bin + " decode");
  EXPECT_EQ(r[0], "2");
  EXPECT_NE(r[2].find("the hex text ends in half a byte"), std::string::npos) << r[2];
  r = run("printf 'a5031000007f5c0000 zz' | " + bin + " decode");
  EXPECT_EQ(r[0], "2");
  EXPECT_NE(r[2].find("the input began as hex text, but byte 19 is not a hex digit ('z')"), std::string::npos) << r[2];
  // raw bytes stay raw
  std::vector<uint8_t> raw = message_bytes(ReplyMsg{0x10, 0x30, 0}, 0x31);
  const std::vector<uint8_t> stop = frame_bytes(0x10, 0x61, {});
  raw.insert(raw.end(), stop.begin(), stop.end());
  const std::string raw_path = kOut + "/" + test_name() + ".bin";
  std::ofstream(raw_path, std::ios::binary).write((const char*)raw.data(), (std::streamsize)raw.size());
  r = run(bin + " decode " + raw_path);
  EXPECT_EQ(r[1], "{\"type\":\"reply\",\"seq\":49,\"command\":\"stop\",\"command_seq\":48,\"status\":\"ok\"}\n"
                  "{\"type\":\"command\",\"command\":\"stop\",\"seq\":97}\n");
}

// --help and --version on stdout with exit 0; a usage error on stderr with exit 2
TEST(TelemetryCommandLine, HelpVersionAndUsageErrors) {
  Tool help({"--help"}, "/dev/null");
  EXPECT_EQ(help.exit_status(true), 0);
  EXPECT_EQ(help.out().rfind("usage: wmra-telemetry decode", 0), 0u) << help.out();
  EXPECT_NE(help.out().find("wmra-telemetry session DEVICE [--json]"), std::string::npos);
  EXPECT_EQ(help.err(), "");
  Tool version({"--version"}, "/dev/null");
  EXPECT_EQ(version.exit_status(true), 0);
  EXPECT_EQ(version.out().rfind("wmra-telemetry ", 0), 0u) << version.out();
  EXPECT_EQ(version.out().substr(version.out().size() - 2), ")\n") << version.out();  // (commit ...) or (not built from git)
  EXPECT_EQ(version.err(), "");
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"session"}, {"session", "/dev/ttyACM0", "--jsn"}, {"session", "--json"}, {"session", "a", "b", "c"}}) {
    Tool bad(args, "/dev/null");
    EXPECT_EQ(bad.exit_status(true), 2) << args.size();
    EXPECT_EQ(bad.out(), "");
    EXPECT_EQ(bad.err().rfind("wmra-telemetry: session takes DEVICE [--json]\nusage:", 0), 0u) << bad.err();
  }
}
