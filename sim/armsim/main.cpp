// armsim: run the firmware ELF at 16 MHz against the virtual arm through a scenario.
//
//   armsim --scenario FILE --out DIR [--elf FIRMWARE.elf] [--vcd] [--profile] [--profile-over CYCLES]
//          [--seed N] [--rate HZ] [--no-payload]
//
// Writes DIR/trajectory.csv, DIR/summary.json and DIR/report.html (and DIR/trace.vcd with
// --vcd, DIR/profile.txt with --profile, DIR/profile-over-{even,odd}.txt with --profile-over);
// see run.h.
// The firmware's telemetry is decoded on the way (FirmwareTelemetry): mode, state and faults
// in those files, its counts on stderr.
// Without --elf it runs the firmware image of this build (ARMSIM_DEFAULT_ELF, set by CMake).
// Exit status: 0 the scenario ran to its end; 1 the simulated core crashed before it;
// 2 a bad command line or scenario (the message names the line); 3 the ELF or the output
// could not be read or written.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <unistd.h>

#include "armsim/run.h"
#include "armsim/scenario.h"

#ifndef ARMSIM_DEFAULT_ELF
#define ARMSIM_DEFAULT_ELF ""
#endif

namespace {

int usage(const char* why) {
  if (why) std::fprintf(stderr, "armsim: %s\n", why);
  std::fprintf(stderr,
               "usage: armsim --scenario FILE --out DIR [--elf FIRMWARE.elf] [--vcd] [--profile] [--profile-over CYCLES]\n"
               "              [--seed N] [--rate HZ] [--no-payload]\n"
               "  --elf   firmware image (default: %s)\n"
               "  --vcd   also write DIR/trace.vcd (pins, PWM duties, joint angles)\n"
               "  --profile  also write DIR/profile.txt (cycles per instruction, for scripts/profile-firmware)\n"
               "  --profile-over CYCLES  also write DIR/profile-over-even.txt and -odd.txt: the same of the\n"
               "             control iterations longer than CYCLES, by the iteration's parity\n"
               "  --seed  noise seed (default 1); --rate  trajectory rows per second (default 100)\n"
               "  --no-payload  the hand empty (default: the 1.2 kg load case)\n",
               ARMSIM_DEFAULT_ELF[0] ? ARMSIM_DEFAULT_ELF : "none built: pass --elf");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_path, out_dir, elf = ARMSIM_DEFAULT_ELF;
  bool elf_given = false;
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
      if (*end || options.profile_over_cycles == 0) return usage("--profile-over wants a number of cycles above 0");
    } else if (a == "--no-payload") {
      options.plant.payload = false;
    } else if (a == "--seed" && has_value) {
      char* end = nullptr;
      options.plant.seed = std::strtoull(argv[++i], &end, 10);
      if (*end) return usage("--seed wants a whole number");
    } else if (a == "--rate" && has_value) {
      char* end = nullptr;
      options.sample_hz = std::strtod(argv[++i], &end);
      if (*end || options.sample_hz < 100 || options.sample_hz > 50000) return usage("--rate wants 100 to 50000 rows per second");
    } else if (a == "-h" || a == "--help") {
      usage(nullptr);
      return 0;
    } else {
      return usage(("unknown or incomplete option " + a).c_str());
    }
  }
  if (scenario_path.empty() || out_dir.empty()) return usage("--scenario and --out are required");

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
  if (elf.empty() || access(elf.c_str(), R_OK) != 0) {
    std::fprintf(stderr, "armsim: no firmware image at '%s'%s\n", elf.c_str(),
                 elf_given ? "" : " (the default): build the firmware or pass --elf");
    return 3;
  }
  options.elf = elf;
  options.out_dir = out_dir;
  options.title = scenario_path.substr(scenario_path.find_last_of('/') + 1);

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
  std::fprintf(stderr, "armsim: %.3f s simulated in %.3f s (%.1fx real time); %s/trajectory.csv, summary.json, report.html\n",
               simulated, wall, wall > 0 ? simulated / wall : 0.0, out_dir.c_str());
  const wmra::armsim::TelemetrySummary& t = result.telemetry;
  std::fprintf(stderr, "armsim: telemetry: %llu frames, %llu CRC errors, %llu seq gaps, %llu replies\n",
               (unsigned long long)t.frames, (unsigned long long)t.crc_errors, (unsigned long long)t.seq_gaps,
               (unsigned long long)t.replies);
  for (const auto& f : result.measurements.sim_faults) std::fprintf(stderr, "armsim: %s\n", f.c_str());
  return result.completed ? 0 : 1;
}
