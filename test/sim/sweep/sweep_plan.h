// What the motion sweep runs: seeded poses across the workspace, and per pose every mode with
// the stick along +-each axis at three deflections, the four diagonals, and two reversals.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "config/modes_config.h"
#include "ideal_arm.h"

namespace wmra {
namespace sweep {

// A stick test: the stick at (x, y) from the start, at (x2, y2) from kReverseAt_s on (a
// reversal; otherwise the same), released at kDrive_s, watched until kDrive_s + kAfter_s
struct StickTest {
  config::Mode mode;
  double x, y, x2, y2;
  std::string name;
  bool reversal() const { return x2 != x || y2 != y; }
};

constexpr double kDrive_s = 2.5;
constexpr double kReverseAt_s = 1.25;
constexpr double kAfter_s = 1.5;

inline const char* mode_name(config::Mode m) {
  switch (m) {
    case config::Mode::xy: return "XY";
    case config::Mode::xz: return "XZ";
    case config::Mode::r1: return "R1";
    case config::Mode::r2: return "R2";
    default: return "gripper";
  }
}

inline std::vector<StickTest> stick_tests(config::Mode mode) {
  std::vector<StickTest> t;
  char name[32];
  for (double d : {0.3, 0.6, 1.0}) {
    const double axes[4][2] = {{d, 0}, {-d, 0}, {0, d}, {0, -d}};
    const char* axis_names[4] = {"+x", "-x", "+y", "-y"};
    for (int a = 0; a < 4; ++a) {
      std::snprintf(name, sizeof name, "%s %.1f", axis_names[a], d);
      t.push_back({mode, axes[a][0], axes[a][1], axes[a][0], axes[a][1], name});
    }
  }
  const double diagonals[4][2] = {{1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  const char* diagonal_names[4] = {"+x+y", "+x-y", "-x+y", "-x-y"};
  for (int a = 0; a < 4; ++a) t.push_back({mode, diagonals[a][0], diagonals[a][1], diagonals[a][0], diagonals[a][1], diagonal_names[a]});
  t.push_back({mode, 1, 0, -1, 0, "+x then -x"});
  t.push_back({mode, 0, 1, 0, -1, "+y then -y"});
  return t;
}

constexpr config::Mode kModes[4] = {config::Mode::xy, config::Mode::xz, config::Mode::r1, config::Mode::r2};

// Pose k of the seeded set: joints drawn within their limits less 20 deg (J6 within +-90 deg),
// kept only clear of the slow bands with a margin (|cos q5|, |sin q3| >= 0.3, R5 >= 0.3 m) and
// with the hand above the base's mounting plane (z >= 0). The same seed gives the same poses.
inline Joints pose(uint32_t seed, int k) {
  std::mt19937_64 rng(seed);
  const double margin = arm::deg_to_rad(20);
  int found = -1;
  for (;;) {
    Joints q;
    for (int j = 0; j < 6; ++j) {
      const double lo = j == 5 ? -arm::kPi / 2 : arm::q_min_rad(j) + margin;
      const double hi = j == 5 ? arm::kPi / 2 : arm::q_max_rad(j) - margin;
      q[j] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    if (std::fabs(std::cos(q[4])) < 0.3 || std::fabs(std::sin(q[2])) < 0.3 || r5_m(q) < 0.3) continue;
    if (ref::fk(q)(2, 3) < 0) continue;
    if (++found == k) return q;
  }
}

}  // namespace sweep
}  // namespace wmra
