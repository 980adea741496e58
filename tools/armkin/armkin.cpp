// armkin: the arm's kinematics from the command line.
//
//   armkin [--fixed] fk Q1..Q6
//   armkin [--fixed] jinv Q1..Q6 VX VY VZ WX WY WZ
//   armkin [--fixed] ik X Y Z R11 R12 R13 R21 R22 R23 R31 R32 R33
//   armkin [--fixed] --batch      (the same commands, without "armkin", one per line on stdin)
//   armkin --help | --version
//
// Units: m, rad, m/s, rad/s; base frame; the frame-6 origin. --fixed runs the fixed-point
// instantiation that the firmware uses (inputs rounded to its formats, outputs converted back).
// A bad command line gets a message on stderr and exit status 2 (the tools' convention); in
// --batch a bad line gets an {"error": ...} line, the other lines are answered, and the exit
// status is 1.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "kinematics/inverse_jacobian.h"
#include "kinematics/inverse_kinematics.h"
#include "version_text.h"

using namespace wmra;
using D = kin::Floating<double>;
using kin::Fixed;

namespace {

// twists beyond these are far outside what the arm can do, and outside the range for
// which the fixed-point inverse is proven not to overflow
constexpr double kMaxLinear_m_s = 4.0;
constexpr double kMaxAngular_rad_s = 16.0;
// IK targets: positions beyond this are far out of reach (and outside the fixed-point range
// where rounding is harmless); a rotation matrix must be orthonormal to this tolerance
constexpr double kMaxPosition_m = 4.0;
constexpr double kRotationTolerance = 1e-4;

struct BadInput {
  std::string message;
};

double parse_number(const std::string& word, const char* what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
    throw BadInput{std::string(what) + ": '" + word + "' is not a finite number"};
  }
  return v;
}

std::vector<double> parse_numbers(const std::vector<std::string>& words, size_t count, const std::string& command,
                                  const char* usage) {
  if (words.size() != count) {
    throw BadInput{command + " takes " + std::to_string(count) + " numbers (" + usage + "), got " +
                   std::to_string(words.size())};
  }
  std::vector<double> v;
  for (size_t i = 0; i < count; ++i) v.push_back(parse_number(words[i], command.c_str()));
  return v;
}

void check_joint_limits(const std::vector<double>& q) {
  for (int i = 0; i < arm::kJoints; ++i) {
    if (q[i] < arm::q_min_rad(i) - 1e-9 || q[i] > arm::q_max_rad(i) + 1e-9) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "q%d = %g rad is outside joint %d's limits [%g, %g] rad", i + 1, q[i], i + 1,
                    arm::q_min_rad(i), arm::q_max_rad(i));
      throw BadInput{buf};
    }
  }
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string json_list(const double* v, int n) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) s += (i ? "," : "") + number(v[i]);
  return s + "]";
}

template <class N>
std::string pose_json(const double p[3], const double r[9]) {
  return "{\"p\":" + json_list(p, 3) + ",\"R\":" + json_list(r, 9) + "}";
}

// --- number-policy adapters: double in, double out
kin::JointAngles<D> joints_double(const std::vector<double>& q) {
  kin::JointAngles<D> j;
  for (int i = 0; i < 6; ++i) j.q[i] = q[i];
  return j;
}
kin::JointAngles<Fixed> joints_fixed(const std::vector<double>& q) {
  kin::JointAngles<Fixed> j;
  for (int i = 0; i < 6; ++i) j.q[i] = fx::angle(q[i]);
  return j;
}
double out(double v) { return v; }
double out(fx::Angle v) { return fx::to_radians(v); }
double out(fx::Real v) { return fx::to_double(v); }
double out(fx::Unit v) { return fx::to_double(v); }

template <class N>
std::string fk(const kin::JointAngles<N>& q) {
  const auto pose = kin::forward_kinematics<N>(q);
  const double p[3] = {out(pose.p_m.x), out(pose.p_m.y), out(pose.p_m.z)};
  double r[9];
  for (int i = 0; i < 9; ++i) r[i] = out(pose.R[i / 3][i % 3]);
  return pose_json<N>(p, r);
}

template <class N>
std::string jinv(const kin::JointAngles<N>& q, const kin::Twist<N>& twist) {
  const auto inv = kin::inverse_jacobian<N>(q, twist);
  double qd[6];
  for (int i = 0; i < 6; ++i) qd[i] = out(inv.qd_rad_s[i]);
  return "{\"qd\":" + json_list(qd, 6) + ",\"det\":" + number(out(kin::determinant<N>(inv.factors))) + ",\"status\":\"" +
         kin::to_string(inv.status) + "\"}";
}

// the target pose: a position within reach of the numbers and an orthonormal rotation
void check_target(const std::vector<double>& x) {
  for (int i = 0; i < 3; ++i) {
    if (std::abs(x[i]) > kMaxPosition_m) {
      throw BadInput{"ik: position component " + number(x[i]) + " m exceeds " + number(kMaxPosition_m) + " m"};
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += x[3 + 3 * i + k] * x[3 + 3 * j + k];
      if (std::abs(dot - (i == j ? 1.0 : 0.0)) > kRotationTolerance) {
        throw BadInput{"ik: R11..R33 is not a rotation matrix (rows " + std::to_string(i + 1) + " and " +
                       std::to_string(j + 1) + " have dot product " + number(dot) + ")"};
      }
    }
  }
}

kin::Pose<D> pose_double(const std::vector<double>& x) {
  kin::Pose<D> target;
  target.p_m = {x[0], x[1], x[2]};
  for (int i = 0; i < 9; ++i) target.R[i / 3][i % 3] = x[3 + i];
  return target;
}
kin::Pose<Fixed> pose_fixed(const std::vector<double>& x) {
  kin::Pose<Fixed> target;
  target.p_m = {fx::real(x[0]), fx::real(x[1]), fx::real(x[2])};
  for (int i = 0; i < 9; ++i) target.R[i / 3][i % 3] = fx::unit(x[3 + i]);
  return target;
}

// Poses without a solution give an empty list (the interface has no status field); why
// there is none goes to stderr.
template <class N>
std::string ik(const kin::Pose<N>& target) {
  const auto sols = kin::inverse_kinematics<N>(target);
  if (sols.status == kin::IkStatus::degenerate) {
    std::fprintf(stderr, "armkin: ik: degenerate pose (wrist point on the base axis or cos q5 = 0): "
                         "infinitely many solutions, none listed\n");
  } else if (sols.status == kin::IkStatus::unreachable) {
    std::fprintf(stderr, "armkin: ik: no solution within the joint limits\n");
  }
  std::string s = "{\"solutions\":[";
  for (int k = 0; k < sols.count; ++k) {
    double q[6];
    for (int j = 0; j < 6; ++j) q[j] = out(sols.q[k].q[j]);
    s += (k ? "," : "") + json_list(q, 6);
  }
  return s + "]}";
}

std::string run_command(const std::vector<std::string>& words, bool fixed) {
  if (words.empty()) throw BadInput{"no command (fk, jinv or ik)"};
  const std::string& cmd = words[0];
  const std::vector<std::string> args(words.begin() + 1, words.end());
  if (cmd == "fk") {
    const auto q = parse_numbers(args, 6, cmd, "Q1..Q6 in rad");
    check_joint_limits(q);
    return fixed ? fk<Fixed>(joints_fixed(q)) : fk<D>(joints_double(q));
  }
  if (cmd == "jinv") {
    const auto a = parse_numbers(args, 12, cmd, "Q1..Q6 in rad, VX VY VZ in m/s, WX WY WZ in rad/s");
    check_joint_limits(a);
    for (int i = 6; i < 12; ++i) {
      const double limit = i < 9 ? kMaxLinear_m_s : kMaxAngular_rad_s;
      if (std::abs(a[i]) > limit) {
        throw BadInput{"jinv: twist component " + number(a[i]) + " exceeds " + number(limit) +
                       (i < 9 ? " m/s" : " rad/s")};
      }
    }
    if (fixed) {
      kin::Twist<Fixed> t{{fx::real(a[6]), fx::real(a[7]), fx::real(a[8])}, {fx::real(a[9]), fx::real(a[10]), fx::real(a[11])}};
      return jinv<Fixed>(joints_fixed(a), t);
    }
    kin::Twist<D> t{{a[6], a[7], a[8]}, {a[9], a[10], a[11]}};
    return jinv<D>(joints_double(a), t);
  }
  if (cmd == "ik") {
    const auto x = parse_numbers(args, 12, cmd, "X Y Z in m and R11..R33 row by row");
    check_target(x);
    return fixed ? ik<Fixed>(pose_fixed(x)) : ik<D>(pose_double(x));
  }
  throw BadInput{"unknown command '" + cmd + "' (fk, jinv or ik)"};
}

std::vector<std::string> split(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}

const char kUsage[] =
    "usage: armkin [--fixed] fk Q1..Q6\n"
    "       armkin [--fixed] jinv Q1..Q6 VX VY VZ WX WY WZ\n"
    "       armkin [--fixed] ik X Y Z R11 R12 R13 R21 R22 R23 R31 R32 R33\n"
    "       armkin [--fixed] --batch   (commands on stdin, one per line)\n"
    "       armkin --help | --version\n"
    "Units: m, rad, m/s, rad/s; base frame. --fixed: the firmware's fixed-point arithmetic. JSON on stdout.\n";

int usage_error(const std::string& message) {
  std::cerr << "armkin: " << message << "\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  bool fixed = false, batch = false;
  std::vector<std::string> words;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (!words.empty()) {
      words.push_back(a);  // the command's numbers, negative ones among them
    } else if (a == "--fixed") {
      fixed = true;
    } else if (a == "--batch") {
      batch = true;
    } else if (a == "-h" || a == "--help") {
      std::cout << kUsage;
      return 0;
    } else if (a == "--version") {
      std::cout << version_text("armkin") << "\n";
      return 0;
    } else if (a.size() > 1 && a[0] == '-') {
      return usage_error("unknown option '" + a + "'");
    } else {
      words.push_back(a);
    }
  }
  if (batch) {
    if (!words.empty()) return usage_error("--batch reads its commands from stdin, not the command line");
    int errors = 0;
    std::string line;
    while (std::getline(std::cin, line)) {
      const auto w = split(line);
      if (w.empty()) continue;
      try {
        std::cout << run_command(w, fixed) << "\n";
      } catch (const BadInput& e) {
        std::cerr << "armkin: " << e.message << "\n";
        std::cout << "{\"error\":\"" << e.message << "\"}\n";
        ++errors;
      }
    }
    return errors ? 1 : 0;
  }
  if (words.empty()) return usage_error("no command (fk, jinv or ik)");
  try {
    std::cout << run_command(words, fixed) << "\n";
  } catch (const BadInput& e) {
    std::cerr << "armkin: " << e.message << "\n";
    return 2;
  }
  return 0;
}
