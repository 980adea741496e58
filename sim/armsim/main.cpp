// armsim: run the firmware ELF at 16 MHz against the virtual arm through a scenario.
//
//   armsim --scenario FILE --out DIR [--elf FIRMWARE.elf] [--vcd] [--profile] [--profile-over CYCLES]
//          [--seed N] [--rate HZ] [--no-payload] [--live [--pty LINK] [--stdin]]
//   armsim --help | --version
//
// Writes DIR/trajectory.csv, DIR/summary.json and DIR/report.html (and DIR/trace.vcd with
// --vcd, DIR/profile.txt with --profile, DIR/profile-over-{even,odd}.txt with --profile-over);
// see run.h. DIR and its parents are created.
// The firmware's telemetry is decoded on the way (FirmwareTelemetry): mode, state and faults
// in those files, its counts on stderr.
// --live paces the run to the wall clock and puts the firmware's UART on a pseudo-terminal
// (live_pty.h): "pty: PATH" on stdout at the start; SIGINT or SIGTERM ends the run early and
// the files are written as at the scenario's end.
// Without --elf it runs the firmware image of this build (ARMSIM_DEFAULT_ELF, set by CMake).
// Exit status: 0 the scenario ran to its end (or --live's run was ended by a signal); 1 the
// simulated core crashed before it; 2 a bad command line or scenario (the message names the
// line); 3 the ELF, the pseudo-terminal or the output could not be read, made or written.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

#include "armsim/live_console.h"
#include "armsim/live_pty.h"
#include "armsim/run.h"
#include "armsim/scenario.h"
#include "version_text.h"

#ifndef ARMSIM_DEFAULT_ELF
#define ARMSIM_DEFAULT_ELF ""
#endif

namespace {

void print_usage(FILE* to) {
  std::fprintf(to,
               "usage: armsim --scenario FILE --out DIR [--elf FIRMWARE.elf] [--vcd] [--profile] [--profile-over CYCLES]\n"
               "              [--seed N] [--rate HZ] [--no-payload] [--live [--pty LINK] [--stdin]]\n"
               "       armsim --help | --version\n"
               "  writes DIR/trajectory.csv, summary.json, report.html (DIR and its parents are created)\n"
               "  --elf   firmware image (default: %s)\n"
               "  --vcd   also write DIR/trace.vcd (pins, PWM duties, joint angles)\n"
               "  --profile  also write DIR/profile.txt (cycles per instruction, for scripts/profile-firmware)\n"
               "  --profile-over CYCLES  also write DIR/profile-over-even.txt and -odd.txt: the same of the\n"
               "             control iterations longer than CYCLES, by the iteration's parity\n"
               "  --seed  noise seed (default 1); --rate  trajectory rows per second (default 100)\n"
               "  --no-payload  the hand empty (default: the 1.2 kg load case)\n"
               "  --live  runs in real time with the firmware's UART on a pseudo-terminal, printing\n"
               "          'pty: PATH' on stdout at the start: open PATH with any host tool as the board's\n"
               "          port (wmra-telemetry session PATH). The baud rate is not enforced, but the bytes\n"
               "          reach the firmware at 115200 baud's pace. Unlike a Mega, the virtual arm does not\n"
               "          reset when the port is opened: its boot frame comes only at the run's start.\n"
               "          Hosts may open and close the port any number of times. The scenario's events\n"
               "          still apply at their times; Ctrl-C (SIGINT) or SIGTERM ends the run and writes\n"
               "          the files as the scenario's end does.\n"
               "  --pty LINK  with --live: LINK becomes a symbolic link to the pseudo-terminal (an older\n"
               "          link there is replaced), removed at the end\n"
               "  --stdin  with --live: the person's hands from the keyboard: events in the scenario's\n"
               "          words without a time, one a line (joystick X Y, button press, estop down, ...),\n"
               "          applied as they arrive\n",
               ARMSIM_DEFAULT_ELF[0] ? ARMSIM_DEFAULT_ELF : "none built: pass --elf");
}

int usage_error(const std::string& why) {
  std::fprintf(stderr, "armsim: %s\n", why.c_str());
  print_usage(stderr);
  return 2;
}

// Why the file at path is no firmware image to run, or "" when it is one (an ELF file)
std::string elf_problem(const std::string& path, bool is_default) {
  if (path.empty() || access(path.c_str(), R_OK) != 0) {
    return "no firmware image at '" + path + "'" + (is_default ? " (the default): build the firmware or pass --elf" : "");
  }
  char magic[4] = {};
  std::ifstream(path, std::ios::binary).read(magic, sizeof magic);
  if (std::memcmp(magic, "\x7f" "ELF", 4) != 0) {
    return path + " is not an ELF file: pass the firmware image the AVR build writes (wmra_firmware.elf)";
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_path, out_dir, elf = ARMSIM_DEFAULT_ELF, pty_link;
  bool elf_given = false, live = false, pty_given = false, console = false;
  wmra::armsim::RunOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--scenario" && has_value) {
      scenario_path = argv[++i];
    } else if (a == "--out" && has_value) {
      out_dir = argv[++i];
    } else if (a == "--elf" && has_value) {
      elf = argv[++i];
      elf_given = true;
    } else if (a == "--vcd") {
      options.vcd = true;
    } else if (a == "--profile") {
      options.profile = true;
    } else if (a == "--profile-over" && has_value) {
      char* end = nullptr;
      options.profile_over_cycles = std::strtoull(argv[++i], &end, 10);
      if (*end || options.profile_over_cycles == 0) return usage_error("--profile-over wants a number of cycles above 0");
    } else if (a == "--no-payload") {
      options.plant.payload = false;
    } else if (a == "--seed" && has_value) {
      char* end = nullptr;
      options.plant.seed = std::strtoull(argv[++i], &end, 10);
      if (*end) return usage_error("--seed wants a whole number");
    } else if (a == "--rate" && has_value) {
      char* end = nullptr;
      options.sample_hz = std::strtod(argv[++i], &end);
      if (*end || options.sample_hz < 100 || options.sample_hz > 50000) return usage_error("--rate wants 100 to 50000 rows per second");
    } else if (a == "--live") {
      live = true;
    } else if (a == "--stdin") {
      console = true;
    } else if (a == "--pty" && has_value) {
      pty_link = argv[++i];
      pty_given = true;
    } else if (a == "-h" || a == "--help") {
      print_usage(stdout);
      return 0;
    } else if (a == "--version") {
      std::printf("%s\n", wmra::version_text("armsim").c_str());
      return 0;
    } else {
      return usage_error("unknown or incomplete option " + a);
    }
  }
  if (scenario_path.empty() || out_dir.empty()) return usage_error("--scenario and --out are required");
  if (pty_given && !live) return usage_error("--pty goes with --live");
  if (console && !live) return usage_error("--stdin goes with --live");
  if (pty_given && pty_link.empty()) return usage_error("--pty wants a path for the link");

  wmra::armsim::Scenario scenario;
  try {
    scenario = wmra::armsim::load_scenario(scenario_path);
  } catch (const wmra::armsim::ScenarioError& e) {
    std::fprintf(stderr, "armsim: %s:%d: %s\n", scenario_path.c_str(), e.line(),
                 std::strchr(e.what(), ':') ? std::strchr(e.what(), ':') + 2 : e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "armsim: %s\n", e.what());
    return 3;
  }
  const std::string problem = elf_problem(elf, !elf_given);
  if (!problem.empty()) {
    std::fprintf(stderr, "armsim: %s\n", problem.c_str());
    return 3;
  }
  options.elf = elf;
  options.out_dir = out_dir;
  options.title = scenario_path.substr(scenario_path.find_last_of('/') + 1);

  std::unique_ptr<wmra::armsim::LivePty> live_pty;
  std::unique_ptr<wmra::armsim::LiveConsole> live_console;
  try {
    wmra::armsim::make_directories(out_dir);  // before a live run: its files must not be lost at its end
    if (live) {
      live_pty = std::make_unique<wmra::armsim::LivePty>(pty_link);
      options.live = live_pty.get();
      if (console) {
        live_console = std::make_unique<wmra::armsim::LiveConsole>(*live_pty, STDIN_FILENO);
        options.live = live_console.get();
      }
      std::printf("pty: %s\n", live_pty->path().c_str());
      std::fflush(stdout);
      std::fprintf(stderr, "armsim: live until %.1f s of the scenario; the firmware's UART on %s%s%s; Ctrl-C ends the run\n",
                   scenario.end_s, live_pty->path().c_str(), pty_link.empty() ? "" : ", linked from ", pty_link.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "armsim: %s\n", e.what());
    return 3;
  }

  const auto start = std::chrono::steady_clock::now();
  wmra::armsim::RunResult result;
  try {
    result = wmra::armsim::run_scenario(scenario, options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "armsim: %s\n", e.what());
    return 3;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double simulated = result.measurements.sim_time_s;
  if (result.interrupted) std::fprintf(stderr, "armsim: ended by a signal at %.3f s\n", simulated);
  std::fprintf(stderr, "armsim: %.3f s simulated in %.3f s (%.1fx real time); %s/trajectory.csv, summary.json, report.html\n",
               simulated, wall, wall > 0 ? simulated / wall : 0.0, out_dir.c_str());
  const wmra::armsim::TelemetrySummary& t = result.telemetry;
  std::fprintf(stderr, "armsim: telemetry: %llu frames, %llu CRC errors, %llu seq gaps, %llu replies\n",
               (unsigned long long)t.frames, (unsigned long long)t.crc_errors, (unsigned long long)t.seq_gaps,
               (unsigned long long)t.replies);
  if (live_pty) {
    const wmra::armsim::LivePty::Counts& c = live_pty->counts();
    std::fprintf(stderr,
                 "armsim: live: opens of the port: %d; %llu bytes to hosts, %llu dropped (no host reading), %llu from "
                 "hosts; %.3f s behind the wall clock in all\n",
                 c.host_opens, (unsigned long long)c.to_host_bytes, (unsigned long long)c.dropped_bytes,
                 (unsigned long long)c.from_host_bytes, c.behind_s);
  }
  for (const auto& f : result.measurements.sim_faults) std::fprintf(stderr, "armsim: %s\n", f.c_str());
  return result.completed || result.interrupted ? 0 : 1;
}
