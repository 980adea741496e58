// jointsim: one joint, one controller of lib/control, a plant model; CSV on stdout (header first).
//
//   jointsim seed0 [--target COUNTS] [--kp 13] [--kd 0.02] [--alpha 5000] [--vs 1000] [--dt 0.01]
//                  [--duration 1] [--variant thesis|firmware] [--ramp-alpha A] [--timer-hz 250000|2000000]
//   jointsim seed1-relay --fs HZ --deadzone-deg D [--target-rad 6.2832] [--drive-v 12] [--duration 6]
//   jointsim dc --joint 2|3|4 --controller pid|relay --step-rad R [--start-rad 0] [--duration 3]
//               [--rate 1000] [--poles P1,P2,P3] [--deadzone-deg 0.5] [--hysteresis-deg 0] [--relay-duty 1]
//               [--noise-mv 1.5] [--seed 1] [--park-counts 0] [--no-payload] [--show-design]
//   jointsim --help | --version
//
// What each models: sim.h and README. A wrong option, a missing or non-numeric value, or a value
// out of range gets a message on stderr and exit status 2 (the tools' convention for a bad
// command line).
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "sim.h"
#include "version_text.h"

using namespace wmra;
using namespace wmra::jointsim;

namespace {

struct BadInput {
  std::string message;
};

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// The words after the preset: --name value pairs and --name flags, each at most once.
class Args {
 public:
  Args(const std::string& preset, const std::vector<std::string>& words, const std::set<std::string>& valued,
       const std::set<std::string>& flags)
      : preset_(preset) {
    for (size_t i = 0; i < words.size(); ++i) {
      const std::string& w = words[i];
      if (w.rfind("--", 0) != 0) throw BadInput{preset + ": unexpected argument '" + w + "'"};
      const std::string name = w.substr(2);
      if (values_.count(name) || flags_.count(name)) throw BadInput{preset + ": " + w + " given twice"};
      if (flags.count(name)) {
        flags_.insert(name);
      } else if (valued.count(name)) {
        if (i + 1 >= words.size()) throw BadInput{preset + ": " + w + " needs a value"};
        values_[name] = words[++i];
      } else {
        throw BadInput{preset + ": unknown option " + w};
      }
    }
  }
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  bool flag(const std::string& name) const { return flags_.count(name) != 0; }
  void require(const std::string& name) const {
    if (!has(name)) throw BadInput{preset_ + ": --" + name + " is required"};
  }
  // a finite number within [lo, hi] (or the default when absent)
  double real(const std::string& name, double fallback, double lo, double hi) const {
    if (!has(name)) return fallback;
    const double v = parse(name, values_.at(name));
    check_range(name, v, lo, hi);
    return v;
  }
  long integer(const std::string& name, long fallback, long lo, long hi) const {
    if (!has(name)) return fallback;
    const double v = parse(name, values_.at(name));
    if (v != std::floor(v)) throw BadInput{preset_ + ": --" + name + ": '" + values_.at(name) + "' is not an integer"};
    check_range(name, v, (double)lo, (double)hi);
    return (long)v;
  }
  std::string word(const std::string& name, const std::string& fallback, const std::set<std::string>& allowed) const {
    if (!has(name)) return fallback;
    const std::string& v = values_.at(name);
    if (!allowed.count(v)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw BadInput{preset_ + ": --" + name + ": '" + v + "' is not one of " + list};
    }
    return v;
  }
  std::vector<double> reals(const std::string& name, double lo, double hi) const {
    std::vector<double> out;
    if (!has(name)) return out;
    std::string s = values_.at(name), item;
    size_t start = 0;
    while (true) {
      const size_t comma = s.find(',', start);
      item = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      const double v = parse(name, item);
      check_range(name, v, lo, hi);
      out.push_back(v);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return out;
  }

 private:
  double parse(const std::string& name, const std::string& word) const {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (word.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      throw BadInput{preset_ + ": --" + name + ": '" + word + "' is not a finite number"};
    }
    return v;
  }
  void check_range(const std::string& name, double v, double lo, double hi) const {
    if (v < lo || v > hi) {
      throw BadInput{preset_ + ": --" + name + " " + number(v) + " is outside [" + number(lo) + ", " + number(hi) +
                     "]"};
    }
  }
  std::string preset_;
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_;
};

void seed0(const std::vector<std::string>& words) {
  const Args a("seed0", words,
               {"target", "kp", "kd", "alpha", "vs", "dt", "duration", "variant", "ramp-alpha", "timer-hz"}, {});
  Seed0Options o;
  o.target_counts = (int32_t)a.integer("target", o.target_counts, -30000, 30000);
  o.kp = a.real("kp", o.kp, 0, 127);
  o.kd_s = a.real("kd", o.kd_s, 0, 10);
  o.alpha_steps_s2 = a.real("alpha", o.alpha_steps_s2, 1, 1e6);
  o.v_s_steps_s = a.real("vs", o.v_s_steps_s, 1, 50000);
  o.dt_s = a.real("dt", o.dt_s, 0.001, 0.1);
  o.duration_s = a.real("duration", o.duration_s, o.dt_s, 60);
  o.variant = a.word("variant", "thesis", {"thesis", "firmware"}) == "thesis" ? control::Seed0Variant::thesis
                                                                              : control::Seed0Variant::firmware;
  o.ramp_alpha_steps_s2 = a.real("ramp-alpha", 0, 0, 1e7);
  o.timer_hz = (int32_t)std::stol(a.word("timer-hz", std::to_string(o.timer_hz), {"250000", "2000000"}));
  write_csv(std::cout, run_seed0(o));
}

void seed1(const std::vector<std::string>& words) {
  const Args a("seed1-relay", words, {"fs", "deadzone-deg", "target-rad", "drive-v", "duration"}, {});
  a.require("fs");
  a.require("deadzone-deg");
  Seed1Options o;
  o.fs_hz = a.real("fs", o.fs_hz, 1, 20000);
  o.deadzone_deg = a.real("deadzone-deg", o.deadzone_deg, 0, 180);
  o.target_rad = a.real("target-rad", o.target_rad, -200, 200);
  o.drive_v = a.real("drive-v", o.drive_v, 0.1, 48);
  o.duration_s = a.real("duration", o.duration_s, 1.0 / o.fs_hz, 60);
  write_csv(std::cout, run_seed1_relay(o));
}

void dc(const std::vector<std::string>& words) {
  const Args a("dc", words,
               {"joint", "controller", "step-rad", "start-rad", "duration", "rate", "poles", "deadzone-deg",
                "hysteresis-deg", "relay-duty", "noise-mv", "seed", "park-counts"},
               {"no-payload", "show-design"});
  a.require("joint");
  a.require("controller");
  a.require("step-rad");
  DcOptions o;
  o.joint = (int)a.integer("joint", 2, 2, 4);
  o.controller = a.word("controller", "pid", {"pid", "relay"}) == "pid" ? DcController::pid : DcController::relay;
  o.step_rad = a.real("step-rad", o.step_rad, -2 * kPi, 2 * kPi);
  o.start_rad = a.real("start-rad", o.start_rad, -2 * kPi, 2 * kPi);
  o.duration_s = a.real("duration", o.duration_s, 0.01, 60);
  o.rate_hz = a.real("rate", kDcDefaultRateHz, 10, 5000);
  o.poles = a.reals("poles", -1000, -0.01);
  if (a.has("poles") && o.poles.size() != 3) throw BadInput{"dc: --poles takes three poles P1,P2,P3 (rad/s, < 0)"};
  o.deadzone_deg = a.real("deadzone-deg", o.deadzone_deg, 0, 30);
  o.hysteresis_deg = a.real("hysteresis-deg", o.hysteresis_deg, 0, 30);
  o.relay_duty = a.real("relay-duty", o.relay_duty, 0.01, 1);
  o.noise_mv = a.real("noise-mv", o.noise_mv, 0, 100);
  o.seed = (uint64_t)a.integer("seed", 1, 0, 2147483647);
  o.payload = !a.flag("no-payload");
  o.park_counts = (int32_t)a.integer("park-counts", 0, 0, 50);
  const DcResult r = run_dc(o);
  if (a.flag("show-design") && o.controller == DcController::pid) {
    const DcDesign& d = r.design;
    std::fprintf(stderr,
                 "jointsim: joint %d linearised at %.4g rad: K = %.1f counts/s at full duty, tau = %.4f s "
                 "(J = %.4f kg m^2 at the worm, %.2f counts/rad)\n"
                 "jointsim: poles %.4g, %.4g, %.4g rad/s -> Kp %.5f /count, Ki %.5f /(count s), Kd %.6f s/count\n"
                 "jointsim: pid.h at %.0f Hz, 16 units/count: kp_q4 %d, ki_q8 %d, kd %d; rate %d, min duty %d, "
                 "zero band %d (Q15)\n",
                 o.joint, o.start_rad, d.k_counts_s, d.tau_s, d.inertia_kgm2, d.counts_per_rad, d.poles[0].real(),
                 d.poles[1].real(), d.poles[2].real(), d.continuous.kp, d.continuous.ki, d.continuous.kd, o.rate_hz,
                 d.fixed.gains.kp_q4, d.fixed.gains.ki_q8, d.fixed.gains.kd, d.config.rate_q15, d.config.min_duty_q15,
                 d.config.zero_band_q15);
  }
  write_csv(std::cout, r);
}

const char kUsage[] =
    "usage: jointsim seed0 [--target COUNTS] [--kp 13] [--kd 0.02] [--alpha 5000] [--vs 1000] [--dt 0.01]\n"
    "                      [--duration 1] [--variant thesis|firmware] [--ramp-alpha A]\n"
    "                      [--timer-hz 250000|2000000]\n"
    "       jointsim seed1-relay --fs HZ --deadzone-deg D [--target-rad 6.2832] [--drive-v 12]\n"
    "                      [--duration 6]\n"
    "       jointsim dc --joint 2|3|4 --controller pid|relay --step-rad R [--start-rad 0] [--duration 3]\n"
    "                      [--rate 1000] [--poles P1,P2,P3] [--deadzone-deg 0.5] [--hysteresis-deg 0] "
    "[--relay-duty 1]\n"
    "                      [--noise-mv 1.5] [--seed 1] [--park-counts 0] [--no-payload] [--show-design]\n"
    "       jointsim --help | --version\n"
    "CSV on stdout, header line first.\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "jointsim: no preset (seed0, seed1-relay or dc)\n" << kUsage;
    return 2;
  }
  const std::string preset = argv[1];
  if (preset == "-h" || preset == "--help") {
    std::cout << kUsage;
    return 0;
  }
  if (preset == "--version") {
    std::cout << version_text("jointsim") << "\n";
    return 0;
  }
  const std::vector<std::string> words(argv + 2, argv + argc);
  try {
    if (preset == "seed0") {
      seed0(words);
    } else if (preset == "seed1-relay") {
      seed1(words);
    } else if (preset == "dc") {
      dc(words);
    } else if (preset.rfind("-", 0) == 0) {
      throw BadInput{"unknown option '" + preset + "' (a preset comes first: seed0, seed1-relay or dc)"};
    } else {
      throw BadInput{"unknown preset '" + preset + "' (seed0, seed1-relay or dc)"};
    }
  } catch (const BadInput& e) {
    std::cerr << "jointsim: " << e.message << "\n";
    return 2;
  } catch (const BadOption& e) {
    std::cerr << "jointsim: " << preset << ": " << e.what() << "\n";
    return 2;
  }
  return 0;
}
