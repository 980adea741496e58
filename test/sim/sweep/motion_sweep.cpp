// The motion sweep (S15, docs/design.md): the firmware in the simulator driven by the stick
// from seeded poses, in every mode and stick direction, each test judged on the plant's true
// joint angles against an ideal resolved-rate arm fed the same stick (sweep_figures.h). Writes
// one CSV row per test; scripts/motion-sweep runs the poses side by side and prints the tables.
//   motion_sweep --elf FIRMWARE.elf --poses FIRST:COUNT [--seed N] [--modes XY,XZ,R1,R2] [--tests N]
//                [--trace "MODE:TEST"] [--at Q1,Q2,Q3,Q4,Q5,Q6] > out.csv
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
               "                    [--trace \"MODE:TEST\"] [--at Q1,Q2,Q3,Q4,Q5,Q6]\n"
               "  one CSV row per stick test on stdout; --tests N: the first N tests of each mode only;\n"
               "  --trace \"XY:+x 0.6\": that test alone, its row and then its samples as '#' lines (time, hand\n"
               "  progress along the command and distance off it in mm, speed over 10 ms in mm/s or deg/s, q in rad, the firmware's slowed_by);\n"
               "  --at: that pose (rad) instead of the seeded ones (with --poses N:1, N names it)\n");
}

void print_header() {
  std::printf("pose,mode,test,reached,ineligible,steady_ratio,off_axis_mm,orientation_deg,origin_mm,peak_100ms,peak_20ms,"
              "release,ideal_release,rebound_mm,settle_s,elbow_crossings,elbow_flipped,stuck,lost_steps,spec_pass,move_lost_steps\n");
}

void print_row(const TestResult& r) {
  const Figures& f = r.figures;
  std::printf("%d,%s,%s,%d,%u,%.4f,%.3f,%.3f,%.3f,%.4f,%.4f,%.3f,%.3f,%.3f,%.2f,%d,%d,%d,%lld,%d,%lld\n", r.pose, mode_name(r.test.mode),
              r.test.name.c_str(), r.reached, f.ineligible, f.steady_ratio, f.off_axis_mm, f.orientation_deg, f.origin_mm, f.peak_100ms,
              f.peak_20ms, f.release, f.ideal_release, f.rebound_mm, f.settle_s, f.elbow_crossings, f.elbow_flipped, f.stuck,
              f.lost_steps, f.spec_pass, r.move_lost_steps);
  std::fflush(stdout);
}

// a test's samples: the hand's progress along the command and off its line (linear modes) or
// the angle turned (rotation), and the joints
void print_trace(const StickTest& test, const std::vector<plant::Joints>& samples, const std::vector<uint8_t>& slowed_by) {
  if (samples.empty()) return;
  const bool linear = test.mode == config::Mode::xy || test.mode == config::Mode::xz;
  Eigen::Vector3d u;
  commanded_speed(test.mode, test.x, test.y, samples[0], &u);
  const Pose p0 = pose_of(samples[0]);
  Pose previous = p0;
  double turned = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const Pose p = pose_of(samples[i]);
    const Eigen::Vector3d d = p.p - p0.p;
    const double step = linear ? (p.p - previous.p).norm() * 1000 : angle_between(previous.r, p.r) * 180 / arm::kPi;
    turned += linear ? 0 : step;
    std::printf("# %.2f %9.3f %7.3f %8.2f", i * kSample_s, linear ? d.dot(u) * 1000 : turned, linear ? (d - d.dot(u) * u).norm() * 1000 : d.norm() * 1000,
                step / kSample_s);
    for (int j = 0; j < 6; ++j) std::printf(" %.5f", samples[i][j]);
    std::printf(" %u\n", (unsigned)slowed_by[i]);
    previous = p;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string elf, modes = "XY,XZ,R1,R2", trace;
  bool at_given = false;
  Joints at{};
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
    } else if (a == "--at" && has_value &&
               std::sscanf(argv[i + 1], "%lf,%lf,%lf,%lf,%lf,%lf", &at[0], &at[1], &at[2], &at[3], &at[4], &at[5]) == 6) {
      at_given = true;
      ++i;
    } else if (a == "--trace" && has_value) {
      trace = argv[++i];
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
    const Joints q = at_given ? at : pose(seed, k);
    PoseRun run(elf, seed, k, q);
    if (!run.start()) {
      std::fprintf(stderr, "motion_sweep: pose %d: the arm did not start\n", k);
      continue;
    }
    for (config::Mode mode : kModes) {
      if (modes.find(mode_name(mode)) == std::string::npos) continue;
      const std::vector<StickTest> list = stick_tests(mode);
      for (int t = 0; t < (int)list.size() && t < tests; ++t) {
        if (!trace.empty() && trace != std::string(mode_name(mode)) + ":" + list[t].name) continue;
        print_row(run.run(list[t]));
        if (!trace.empty()) print_trace(list[t], run.samples(), run.slowed_by());
      }
    }
  }
  return 0;
}
