// The bring-up chapter of docs/arm-guide.md (section 3) on the virtual arm, as a technician
// would do it on the real board: its `session` blocks typed into wmra-telemetry session, its
// `hands` blocks typed into armsim --live --stdin (what the person's hands do), its calibration
// step run with wmra-telemetry calibrate, in the chapter's order. The guide's commands are read
// from the guide itself, so the chapter cannot go stale; what each step says you should see is
// checked on the tools' output and, for the motion, on the plant's true joint angles
// (trajectory.csv).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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
#include <unistd.h>

#include "calibrate_driver.h"
#include "child_process.h"
#include "live_arm.h"
#include "config/version.h"

namespace {

using namespace wmra;
using Clock = std::chrono::steady_clock;

const std::string kFirmware = std::string(FIRMWARE_DIR) + "/wmra_firmware.elf";
const std::string kOut = ARMSIM_OUT;
const std::string kGuide = std::string(SOURCE_DIR) + "/docs/arm-guide.md";
const std::string kScenario = std::string(SOURCE_DIR) + "/scenarios/bring-up.txt";

using test::seconds_since;

// One fenced block of the chapter: session (lines for the session), hands (lines for armsim's
// stdin), calibrate (a ```sh block that runs wmra-telemetry calibrate: its command line)
struct Block {
  std::string kind;
  std::vector<std::string> lines;
};

std::vector<Block> chapter_blocks(const std::string& guide) {
  const size_t from = guide.find("### Bring-up, step by step");
  const size_t to = guide.find("\n## ", from);
  std::istringstream in(guide.substr(from, to == std::string::npos ? std::string::npos : to - from));
  std::vector<Block> blocks;
  std::string line;
  Block* open = nullptr;
  bool in_fence = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      in_fence = !in_fence;
      if (in_fence) {
        const std::string kind = line.substr(3);
        if (kind == "session" || kind == "hands" || kind == "sh") {
          blocks.push_back(Block{kind, {}});
          open = &blocks.back();
        }
      } else {
        if (open && open->kind == "sh") {
          const bool calibrate = !open->lines.empty() && open->lines[0].find("wmra-telemetry calibrate") != std::string::npos;
          if (calibrate) open->kind = "calibrate";
          else blocks.pop_back();
        }
        open = nullptr;
      }
      continue;
    }
    if (open) open->lines.push_back(line);
  }
  return blocks;
}

// A pipe whose read end becomes a child's stdin; the test writes the lines
struct Pipe {
  int fd[2] = {-1, -1};
  Pipe() { EXPECT_EQ(pipe2(fd, O_CLOEXEC), 0); }
  ~Pipe() {
    close_read();
    close_write();
  }
  void close_read() {
    if (fd[0] >= 0) close(fd[0]);
    fd[0] = -1;
  }
  void close_write() {
    if (fd[1] >= 0) close(fd[1]);
    fd[1] = -1;
  }
  void line(const std::string& text) {
    const std::string l = text + "\n";
    EXPECT_EQ(write(fd[1], l.data(), l.size()), (ssize_t)l.size());
  }
};

// a program with its stdin on a pipe of ours
struct Fed {
  Pipe in;
  std::unique_ptr<test::ChildProcess> process;
  Fed(const std::vector<std::string>& argv, const std::string& out_base) {
    process = std::make_unique<test::ChildProcess>(argv, out_base, "", in.fd[0]);
    in.close_read();
  }
};

int count_lines_starting(const std::string& text, const std::string& prefix) {
  int n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0;
  return n;
}

// The session's block: its lines typed, then the replies awaited (a jog gives two "> " lines:
// its first reply and its count) and the sleeps' time let pass
void type_session_block(Fed& session, const Block& b) {
  int replies = 0;
  double sleeps_s = 0;
  for (const std::string& l : b.lines) {
    if (l.empty() || l[0] == '#') continue;
    if (l.rfind("sleep ", 0) == 0) sleeps_s += std::atof(l.c_str() + 6);
    else replies += l.rfind("jog ", 0) == 0 ? 2 : 1;
  }
  const int before = count_lines_starting(session.process->out(), "> ");
  for (const std::string& l : b.lines) session.in.line(l);
  const auto start = Clock::now();
  while (count_lines_starting(session.process->out(), "> ") < before + replies && seconds_since(start) < 30) usleep(20000);
  EXPECT_GE(count_lines_starting(session.process->out(), "> "), before + replies) << "the session's replies did not come";
  usleep((useconds_t)((sleeps_s + 0.3) * 1e6));
}

// the last status line (a line with "faults:") of the output
std::string last_status(const std::string& out) {
  const size_t at = out.rfind("faults:");
  if (at == std::string::npos) return "";
  const size_t begin = out.rfind('\n', at);
  return out.substr(begin == std::string::npos ? 0 : begin + 1, out.find('\n', at) - (begin == std::string::npos ? 0 : begin + 1));
}

struct Row {
  double t_s;
  double q[6], p[3];
  int state;
};
// trajectory.csv's rows: t, q1..q6, x, y, z, the rotation's 9, mode, state
std::vector<Row> trajectory(const std::string& path) {
  std::vector<Row> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::atof(cell.c_str()));
    if (v.size() != 21) continue;
    Row r{v[0], {v[1], v[2], v[3], v[4], v[5], v[6]}, {v[7], v[8], v[9]}, (int)v[20]};
    rows.push_back(r);
  }
  return rows;
}
double distance_mm(const double* a, const double* b) {
  return 1000 * std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(BringUpChapter, RunsOnTheVirtualArm) {
  std::ifstream guide_file(kGuide);
  std::stringstream guide;
  guide << guide_file.rdbuf();
  const std::vector<Block> blocks = chapter_blocks(guide.str());
  int sessions_blocks = 0, hands_blocks = 0, calibrate_blocks = 0;
  for (const Block& b : blocks) {
    sessions_blocks += b.kind == "session";
    hands_blocks += b.kind == "hands";
    calibrate_blocks += b.kind == "calibrate";
  }
  std::printf("the chapter: %d session blocks, %d hands blocks, %d calibration\n", sessions_blocks, hands_blocks, calibrate_blocks);
  ASSERT_GE(sessions_blocks, 8);
  ASSERT_GE(hands_blocks, 6);
  ASSERT_EQ(calibrate_blocks, 1);

  test::LiveArm arm(ARMSIM, kFirmware, kOut, "bring_up_chapter", 0, kScenario, true);
  ASSERT_FALSE(arm.pty.empty()) << arm.armsim->err();
  const std::string& link = arm.link;
  usleep(1500000);  // the firmware boots (as the Mega after power-up)

  int sessions = 0;
  std::unique_ptr<Fed> session;
  std::string all_sessions_out;
  auto open_session = [&] {
    session = std::make_unique<Fed>(std::vector<std::string>{TELEMETRY_BIN, "session", link},
                                    kOut + "/bring_up_chapter_session" + std::to_string(++sessions));
    for (auto start = Clock::now(); seconds_since(start) < 10 && session->process->out().find("faults:") == std::string::npos;)
      usleep(20000);
  };
  auto end_session = [&] {
    session->in.close_write();  // Ctrl-D
    EXPECT_EQ(session->process->wait_s(10), 0) << session->process->err();
    all_sessions_out += session->process->out();
    session.reset();
  };
  open_session();
  int calibrations = 0;
  for (const Block& b : blocks) {
    if (b.kind == "hands") {
      for (const std::string& l : b.lines) EXPECT_TRUE(arm.type(l)) << l;
      usleep(300000);
    } else if (b.kind == "session") {
      if (!session) open_session();
      type_session_block(*session, b);
    } else if (b.kind == "calibrate") {
      end_session();
      ++calibrations;
      // the guide's command line, its port the virtual arm's
      std::istringstream words(b.lines[0]);
      std::vector<std::string> argv;
      for (std::string w; words >> w;) argv.push_back(w);
      ASSERT_EQ(argv.size(), 4u) << b.lines[0];
      EXPECT_EQ(argv[0] + " " + argv[1], "wmra-telemetry calibrate");
      for (int j = 2; j <= 4; ++j) {
        // a jog each way and the angles as measured (the virtual arm's are the firmware's)
        const test::CalibrateRun run = test::run_calibrate(TELEMETRY_BIN, link, j, {"+ 1.5", "=", "- 3", "=", "yes"},
                                                           kOut + "/bring_up_chapter_calibrate" + std::to_string(j));
        EXPECT_EQ(run.status, 0) << "calibrate J" << j << "\n" << run.out << run.err;
        EXPECT_NE(run.out.find("stored: J" + std::to_string(j)), std::string::npos) << run.out;
      }
    }
  }
  const std::string final_status = session ? last_status(session->process->out()) : "";
  end_session();
  kill(arm.armsim->pid, SIGINT);
  EXPECT_EQ(arm.armsim->wait_s(15), 0) << arm.armsim->err();
  const std::string& out = all_sessions_out;
  std::printf("%s\n", out.c_str());

  // 3: which firmware
  const config::Version v = config::kProductVersion;
  const std::string version = std::to_string(v.major) + "." + std::to_string(v.minor) + "." + std::to_string(v.patch);
  EXPECT_NE(out.find("info: firmware " + version + ", commit "), std::string::npos);
  // 5, 6: re-armed, waiting; each joint jogged each way
  EXPECT_NE(out.find("> rearm: ok"), std::string::npos);
  EXPECT_EQ(count_lines_starting(out, "> jog "), 24);
  EXPECT_EQ(out.find("refused"), std::string::npos) << "a command was refused";
  EXPECT_EQ(calibrations, 1);
  // 8, 9, 11
  EXPECT_NE(out.find("> stick-centre store: ok"), std::string::npos);
  EXPECT_NE(out.find("> home: ok"), std::string::npos);
  EXPECT_NE(final_status.find("running"), std::string::npos) << final_status;
  EXPECT_NE(final_status.find("faults: none"), std::string::npos) << final_status;

  // on the plant's true angles: every joint turned in the jogs (state 8), the stick moved the
  // hand once running (state 4), and nothing moved while the safety button held it (state 5
  // after running)
  const std::vector<Row> rows = trajectory(arm.dir + "/trajectory.csv");
  ASSERT_GT(rows.size(), 1000u);
  for (int j = 0; j < 6; ++j) {
    double lo = 1e9, hi = -1e9;
    for (const Row& r : rows)
      if (r.state == 8) lo = std::min(lo, r.q[j]), hi = std::max(hi, r.q[j]);
    std::printf("J%d jogged over %.1f mrad\n", j + 1, 1000 * (hi - lo));
    EXPECT_GT(hi - lo, 0.03) << "J" << j + 1 << " did not turn in its jogs";
  }
  const Row* first_running = nullptr;
  double stick_mm = 0, while_stopped_mm = 0;
  const Row* stopped_at = nullptr;
  for (const Row& r : rows) {
    if (r.state == 4 && !first_running) first_running = &r;
    if (first_running && !stopped_at) stick_mm = std::max(stick_mm, distance_mm(r.p, first_running->p));
    if (first_running && r.state == 5 && !stopped_at) stopped_at = &r;
    if (stopped_at && r.state == 5) while_stopped_mm = std::max(while_stopped_mm, distance_mm(r.p, stopped_at->p));
  }
  ASSERT_NE(first_running, nullptr);
  ASSERT_NE(stopped_at, nullptr) << "the safety button did not stop the running arm";
  std::printf("running from %.1f s; the stick moved the hand %.1f mm; stopped at %.1f s, the hand then %.2f mm\n", first_running->t_s,
              stick_mm, stopped_at->t_s, while_stopped_mm);
  EXPECT_GT(stick_mm, 10.0);
  EXPECT_LT(while_stopped_mm, 1.0);
  EXPECT_EQ(rows.back().state, 4);
}

}  // namespace
