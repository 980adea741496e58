// The motion sweep (S15, docs/design.md): the firmware in the simulator driven by the stick
// from seeded poses, in every mode and stick direction, each test judged on the plant's true
// joint angles against an ideal resolved-rate arm fed the same stick (sweep_figures.h). Writes
// one CSV row per test; scripts/motion-sweep runs the poses side by side and prints the tables.
//   motion_sweep --elf FIRMWARE.elf --poses FIRST:COUNT [--seed N] [--modes XY,XZ,R1,R2] [--tests N] > out.csv
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "sweep_runner.h"

namespace {

using namespace wmra;
using namespace wmra::sweep;

void usage(FILE* f) {
  std::fprintf(f,
               "usage: motion_sweep --elf FIRMWARE.elf --poses FIRST:COUNT [--seed N] [--modes XY,XZ,R1,R2] [--tests N]\n"
               "  one CSV row per stick test on stdout; --tests N: the first N tests of each mode only\n");
}

void print_header() {
  std::printf("pose,mode,test,reached,ineligible,steady_ratio,off_axis_mm,orientation_deg,origin_mm,peak_100ms,peak_20ms,"
              "release,ideal_release,rebound_mm,settle_s,elbow_crossings,elbow_flipped,stuck,lost_steps,spec_pass\n");
}

void print_row(const TestResult& r) {
  const Figures& f = r.figures;
  std::printf("%d,%s,%s,%d,%u,%.4f,%.3f,%.3f,%.3f,%.4f,%.4f,%.3f,%.3f,%.3f,%.2f,%d,%d,%d,%lld,%d\n", r.pose, mode_name(r.test.mode),
              r.test.name.c_str(), r.reached, f.ineligible, f.steady_ratio, f.off_axis_mm, f.orientation_deg, f.origin_mm, f.peak_100ms,
              f.peak_20ms, f.release, f.ideal_release, f.rebound_mm, f.settle_s, f.elbow_crossings, f.elbow_flipped, f.stuck,
              f.lost_steps, f.spec_pass);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string elf, modes = "XY,XZ,R1,R2";
  int first = 0, count = 0, tests = 1000;
  uint32_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--help" || a == "-h") {
      usage(stdout);
      return 0;
    } else if (a == "--elf" && has_value) {
      elf = argv[++i];
    } else if (a == "--poses" && has_value && std::sscanf(argv[i + 1], "%d:%d", &first, &count) == 2) {
      ++i;
    } else if (a == "--seed" && has_value) {
      seed = (uint32_t)std::strtoul(argv[++i], nullptr, 10);
    } else if (a == "--modes" && has_value) {
      modes = argv[++i];
    } else if (a == "--tests" && has_value) {
      tests = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "motion_sweep: unexpected argument '%s'\n", a.c_str());
      usage(stderr);
      return 2;
    }
  }
  if (elf.empty() || count <= 0 || first < 0) {
    usage(stderr);
    return 2;
  }
  print_header();
  for (int k = first; k < first + count; ++k) {
    const Joints q = pose(seed, k);
    PoseRun run(elf, seed, k, q);
    if (!run.start()) {
      std::fprintf(stderr, "motion_sweep: pose %d: the arm did not start\n", k);
      continue;
    }
    for (config::Mode mode : kModes) {
      if (modes.find(mode_name(mode)) == std::string::npos) continue;
      const std::vector<StickTest> list = stick_tests(mode);
      for (int t = 0; t < (int)list.size() && t < tests; ++t) print_row(run.run(list[t]));
    }
  }
  return 0;
}
