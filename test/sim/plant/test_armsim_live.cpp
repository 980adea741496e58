// armsim --live: the firmware image in real time with its UART on a pseudo-terminal (a host's
// frames answered, hosts opening and closing the port, the run's end in real time, SIGTERM and
// SIGINT writing the files), wmra-telemetry session against it, and armsim's command line
// (--help, --version, usage errors, --out's parents, --elf on a file that is no ELF).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include "child_process.h"
#include "live_arm.h"
#include "protocol/parser.h"
#include "protocol_frames.h"
#include "telemetry_json.h"

using namespace wmra;
using namespace wmra::protocol;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kOut = ARMSIM_OUT;

using test::read_file;

using test::seconds_since;

std::string test_name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }

// A program run with stdin from a file, stdout and stderr into files of the test's
struct Process : test::ChildProcess {
  Process(const std::string& name, const std::vector<std::string>& args, const std::string& stdin_path = "/dev/null")
      : test::ChildProcess(args, kOut + "/" + name, stdin_path) {}
};

// armsim --live with a scenario that holds the stick centred until end_s (test/common/live_arm.h)
struct LiveArm : test::LiveArm {
  LiveArm(const std::string& test, double end_s) : test::LiveArm(ARMSIM, kFirmware, kOut, test, end_s) {}
};
using test::Host;

const ReplyMsg* reply_to(const std::vector<Frame>& frames, uint8_t command_seq, ReplyMsg& reply) {
  for (const Frame& f : frames) {
    if (decode(f, reply) && reply.command_seq == command_seq) return &reply;
  }
  return nullptr;
}

int data_rows(const std::string& csv) {
  int rows = -1;  // the header
  for (char c : csv) rows += c == '\n';
  return rows;
}

// the last row's time
double last_t(const std::string& csv) {
  const size_t at = csv.rfind('\n', csv.size() - 2);
  return at == std::string::npos ? -1 : std::atof(csv.c_str() + at + 1);
}

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = kOut + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

// The run: "pty: PATH" and the link at once; a host's get_info answered with its reply and
// the info frame, by a host that opens the port again and again; state frames whose clock
// keeps to the wall clock's; the end at the scenario's 6 s in real time, the files written
TEST(ArmsimLive, RunsInRealTimeWithItsUartOnAPseudoTerminal) {
  ASSERT_EQ(access(kFirmware.c_str(), R_OK), 0) << kFirmware << ": build the firmware (avr_images)";
  LiveArm arm(test_name(), 6.0);
  ASSERT_FALSE(arm.pty.empty()) << arm.armsim->err();
  const auto pty_at = Clock::now();
  char target[256] = {};
  ASSERT_GT(readlink(arm.link.c_str(), target, sizeof target - 1), 0) << arm.link;
  EXPECT_EQ(std::string(target), arm.pty);

  uint8_t seq = 10;
  for (int open = 0; open < 4; ++open) {
    Host host(arm.link);
    ASSERT_GE(host.fd, 0) << open;
    // a state frame first: the firmware's UART takes bytes once it has booted, as on the board
    StateMsg state{};
    host.frames_until(1.0, [&](const std::vector<Frame>& f) { return !f.empty() && decode(f.back(), state); });
    const uint8_t info_seq = seq++;
    ASSERT_TRUE(host.send(protocol_frames::frame_bytes((uint8_t)MsgType::cmd_info, info_seq, {})));
    ReplyMsg reply{};
    InfoMsg info{};
    const auto frames = host.frames_until(1.0, [&](const std::vector<Frame>& f) {
      for (const Frame& x : f) {
        if (decode(x, info)) return reply_to(f, info_seq, reply) != nullptr;
      }
      return false;
    });
    ASSERT_NE(reply_to(frames, info_seq, reply), nullptr) << "open " << open << ": " << frames.size() << " frames";
    EXPECT_EQ(reply.command_type, (uint8_t)MsgType::cmd_info);
    EXPECT_EQ(reply.status, (uint8_t)ReplyStatus::ok);
    EXPECT_EQ(info.loop_hz, 1000);
    host.hang_up();
    usleep(50000);  // no host on the port for a while: the run goes on
  }
  {  // a host that opens the port, sends nothing, reads nothing and goes
    Host idle(arm.link);
    ASSERT_GE(idle.fd, 0);
    usleep(300000);
  }
  usleep(50000);
  // the firmware's clock in its state frames against the wall clock, over 1 s
  StateMsg first{}, last{};
  Clock::time_point first_at, last_at;
  Host(arm.link).frames_until(1.5, [&](const std::vector<Frame>& f) {
    if (f.empty() || !decode(f.back(), last)) return false;
    last_at = Clock::now();
    if (first.t_ms == 0) {
      first = last;
      first_at = last_at;
    }
    return std::chrono::duration<double>(last_at - first_at).count() >= 1.0;
  });
  const double wall_s = std::chrono::duration<double>(last_at - first_at).count();
  const double firmware_s = (last.t_ms - first.t_ms) / 1000.0;
  EXPECT_GT(wall_s, 0.9);
  EXPECT_NEAR(firmware_s, wall_s, 0.1) << "the firmware's clock against the wall clock";
  EXPECT_EQ(telemetry::state_name(last.state).rfind("wait_", 0), 0u) << (int)last.state;

  const int status = arm.armsim->wait_s(10);
  const double run_s = seconds_since(pty_at);
  EXPECT_EQ(status, 0) << arm.armsim->err();
  std::printf("6 s of simulated time in %.2f s after 'pty:'\n", run_s);
  EXPECT_GT(run_s, 5.5);
  EXPECT_LT(run_s, 7.0);
  struct stat st;
  EXPECT_NE(lstat(arm.link.c_str(), &st), 0) << "the link is removed at the end";
  const std::string csv = read_file(arm.dir + "/trajectory.csv");
  EXPECT_GE(data_rows(csv), 600);  // 100 a second (the row at the end itself when the core is awake then)
  EXPECT_LE(data_rows(csv), 601);
  const std::string summary = read_file(arm.dir + "/summary.json");
  EXPECT_NE(summary.find("\"completed\": true,\n  \"interrupted\": false,"), std::string::npos) << summary.substr(0, 200);
  EXPECT_NE(arm.armsim->err().find("armsim: live: opens of the port: 6; "), std::string::npos) << arm.armsim->err();
}

// SIGTERM midway: the run ends at once and its files hold the run up to then
TEST(ArmsimLive, SigtermEndsTheRunAndWritesItsFiles) {
  ASSERT_EQ(access(kFirmware.c_str(), R_OK), 0) << kFirmware << ": build the firmware (avr_images)";
  LiveArm arm(test_name(), 60.0);
  ASSERT_FALSE(arm.pty.empty()) << arm.armsim->err();
  usleep(2000000);
  const auto signalled = Clock::now();
  kill(arm.armsim->pid, SIGTERM);
  EXPECT_EQ(arm.armsim->wait_s(10), 0) << arm.armsim->err();
  EXPECT_LT(seconds_since(signalled), 1.0);
  const std::string csv = read_file(arm.dir + "/trajectory.csv");
  EXPECT_GE(data_rows(csv), 190);  // 100 a second over about 2 s
  EXPECT_LE(data_rows(csv), 300);
  EXPECT_NEAR(last_t(csv), 2.0, 0.5);
  const std::string summary = read_file(arm.dir + "/summary.json");
  EXPECT_NE(summary.find("\"completed\": false,\n  \"interrupted\": true,"), std::string::npos) << summary.substr(0, 200);
  const size_t at = summary.find("\"sim_time_s\": ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_NEAR(std::atof(summary.c_str() + at + 14), last_t(csv), 0.02);
  EXPECT_GT(read_file(arm.dir + "/report.html").size(), 1000u);
  EXPECT_NE(arm.armsim->err().find("armsim: ended by a signal at "), std::string::npos) << arm.armsim->err();
  struct stat st;
  EXPECT_NE(lstat(arm.link.c_str(), &st), 0) << "the link is removed at the end";
}

// wmra-telemetry session on the live arm's port: the replies and the status lines by name;
// then a second session (the port opened again) with a bad line: the rest still sent, a
// non-zero exit. SIGINT then ends armsim, its files written.
TEST(ArmsimLive, TelemetrySessionAgainstTheLiveArm) {
  ASSERT_EQ(access(kFirmware.c_str(), R_OK), 0) << kFirmware << ": build the firmware (avr_images)";
  LiveArm arm(test_name(), 60.0);
  ASSERT_FALSE(arm.pty.empty()) << arm.armsim->err();

  Process session(test_name() + "_session", {TELEMETRY_BIN, "session", arm.link},
                  write_text(test_name() + "_session.in", "info\nmode xz\nsleep 0.5\nstop\nsleep 0.3\nrearm\nsleep 0.3\n"));
  EXPECT_EQ(session.wait_s(15), 0) << session.err();
  const std::string out = session.out();
  for (const char* line : {"> info: ok\ninfo: firmware ", "> mode xz: ", "> stop: ok\n", "> rearm: ok\n"}) {
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
  }
  EXPECT_NE(out.find("info: soft limits deg:  J1 "), std::string::npos) << out;
  // a status line at the start and at each change of state, by name
  EXPECT_NE(out.find(" s  wait_"), std::string::npos) << out;
  const size_t stopped = out.find(" s  stopped ");
  ASSERT_NE(stopped, std::string::npos) << out;
  EXPECT_LT(out.find("> stop: ok\n"), stopped);
  const std::string line = out.substr(stopped, out.find('\n', stopped) - stopped);
  EXPECT_LT(line.find("  faults: none  switches: "), line.find("  q deg: ")) << line;
  EXPECT_EQ(std::count(line.begin(), line.end(), '.'), 6) << line;  // six angles, one decimal each

  Process bad(test_name() + "_bad", {TELEMETRY_BIN, "session", arm.link}, write_text(test_name() + "_bad.in", "frobnicate 1\nstop\n"));
  EXPECT_EQ(bad.wait_s(15), 2) << bad.err();
  EXPECT_NE(bad.out().find("> stop: ok\n"), std::string::npos) << bad.out();
  EXPECT_NE(bad.err().find("wmra-telemetry: line 1: unknown command 'frobnicate'\n"), std::string::npos) << bad.err();

  kill(arm.armsim->pid, SIGINT);
  EXPECT_EQ(arm.armsim->wait_s(10), 0) << arm.armsim->err();
  const std::string summary = read_file(arm.dir + "/summary.json");
  EXPECT_NE(summary.find("\"interrupted\": true,"), std::string::npos);
  const size_t at = summary.find("\"replies\": ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(std::atoi(summary.c_str() + at + 11), 5);  // info, mode, stop, rearm, stop
}

// --help and --version on stdout with exit 0; usage errors on stderr with exit 2; an ELF that
// is none, a link that would replace a file and an --out that cannot be made: exit 3
// --stdin, the person's hands from the keyboard: `estop down` typed into armsim stops the arm at
// once (the firmware reports it), a line that is no event is named on stderr and changes
// nothing, and the end of stdin ends nothing but the console
TEST(ArmsimLive, StdinEventsApplyAsTheyArrive) {
  ASSERT_EQ(access(kFirmware.c_str(), R_OK), 0) << kFirmware << ": build the firmware (avr_images)";
  const std::string scenario = write_text(test_name() + ".txt", "0 joystick 0 0\n8 end\n");
  const std::string link = kOut + "/" + test_name() + ".pty", dir = kOut + "/" + test_name();
  int keys[2];
  ASSERT_EQ(pipe2(keys, O_CLOEXEC), 0);
  test::ChildProcess armsim({ARMSIM, "--scenario", scenario, "--out", dir, "--elf", kFirmware, "--live", "--pty", link, "--stdin"},
                            kOut + "/" + test_name() + "_armsim", "", keys[0]);
  close(keys[0]);
  for (auto start = Clock::now(); seconds_since(start) < 20 && armsim.out().find("pty: ") != 0;) usleep(10000);
  ASSERT_EQ(armsim.out().find("pty: "), 0u) << armsim.err();
  Host host(link);
  ASSERT_GE(host.fd, 0);
  auto state_within = [&](double max_s, const char* name) {
    StateMsg m{};
    host.frames_until(max_s, [&](const std::vector<Frame>& f) {
      return !f.empty() && decode(f.back(), m) && telemetry::state_name(m.state) == name;
    });
    return telemetry::state_name(m.state);
  };
  EXPECT_EQ(state_within(5.0, "wait_home"), "wait_home");
  const std::string typed = "bogus 1\njoystick 2 0\nestop down\n";
  ASSERT_EQ(write(keys[1], typed.data(), typed.size()), (ssize_t)typed.size());
  const auto pressed = Clock::now();
  EXPECT_EQ(state_within(1.0, "stopped"), "stopped");
  EXPECT_LT(seconds_since(pressed), 0.3) << "the safety button typed in took effect late";
  ASSERT_EQ(write(keys[1], "estop up\n", 9), 9);
  close(keys[1]);  // the end of stdin: the run goes on
  usleep(300000);
  EXPECT_EQ(armsim.exit_status(false), -1) << "the run ended with stdin";
  kill(armsim.pid, SIGTERM);
  EXPECT_EQ(armsim.wait_s(10), 0) << armsim.err();
  const std::string err = armsim.err();
  EXPECT_NE(err.find("stdin: 'bogus 1'"), std::string::npos) << err;
  EXPECT_NE(err.find("stdin: 'joystick 2 0'"), std::string::npos) << err;  // out of [-1, 1]
  EXPECT_NE(err.find("estop down"), std::string::npos) << err;
}

TEST(ArmsimCommandLine, Conventions) {
  auto run = [](const std::vector<std::string>& args) {
    std::vector<std::string> argv = {ARMSIM};
    argv.insert(argv.end(), args.begin(), args.end());
    Process p(test_name(), argv);
    const int status = p.wait_s(30);
    return std::array<std::string, 3>{std::to_string(status), p.out(), p.err()};
  };
  auto r = run({"--help"});
  EXPECT_EQ(r[0], "0");
  EXPECT_EQ(r[1].rfind("usage: armsim --scenario FILE --out DIR", 0), 0u) << r[1];
  EXPECT_NE(r[1].find("the virtual arm does not\n          reset when the port is opened"), std::string::npos) << r[1];
  EXPECT_EQ(r[2], "");
  r = run({"--version"});
  EXPECT_EQ(r[0], "0");
  EXPECT_EQ(r[1].rfind("armsim ", 0), 0u) << r[1];
  EXPECT_EQ(r[1].substr(r[1].size() - 2), ")\n") << r[1];  // (commit ...) or (not built from a git checkout)
  EXPECT_EQ(r[2], "");

  const std::string scenario = write_text("conventions.txt", "0 joystick 0 0\n0.1 end\n");
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"--bogus"}, {"--scenario", scenario}, {"--scenario", scenario, "--out", kOut + "/x", "--pty", kOut + "/x.pty"},
           {"--scenario", scenario, "--out", kOut + "/x", "--rate", "5"}, {"--scenario", scenario, "--out"}}) {
    r = run(args);
    EXPECT_EQ(r[0], "2") << args.back();
    EXPECT_EQ(r[1], "") << args.back();
    EXPECT_EQ(r[2].rfind("armsim: ", 0), 0u) << r[2];
    EXPECT_NE(r[2].find("\nusage: armsim"), std::string::npos) << r[2];
  }

  const std::string not_elf = write_text("not_an_elf.md", "# A README, not a firmware image\n");
  r = run({"--scenario", scenario, "--out", kOut + "/not_elf", "--elf", not_elf});
  EXPECT_EQ(r[0], "3");
  EXPECT_EQ(r[2], "armsim: " + not_elf + " is not an ELF file: pass the firmware image the AVR build writes (wmra_firmware.elf)\n");

  const std::string file = write_text("in_the_way", "a file\n");
  r = run({"--scenario", scenario, "--out", file + "/out", "--elf", kFirmware});
  EXPECT_EQ(r[0], "3");
  EXPECT_EQ(r[2].rfind("armsim: cannot create " + file + "/out: ", 0), 0u) << r[2];
  r = run({"--scenario", scenario, "--out", kOut + "/link_over_file", "--elf", kFirmware, "--live", "--pty", file});
  EXPECT_EQ(r[0], "3");
  EXPECT_EQ(r[2], "armsim: " + file + " exists and is not a symbolic link: not replaced\n");
  EXPECT_EQ(read_file(file), "a file\n");

  // --out a/b/c: made with its parents
  std::filesystem::remove_all(kOut + "/a");
  r = run({"--scenario", scenario, "--out", kOut + "/a/b/c", "--elf", kFirmware});
  EXPECT_EQ(r[0], "0") << r[2];
  for (const char* name : {"trajectory.csv", "summary.json", "report.html"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(kOut + "/a/b/c/" + name)) << name;
  }
}
