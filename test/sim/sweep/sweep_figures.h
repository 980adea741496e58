// One stick test's figures, from the plant's true joint angles (sampled every 10 ms) through the
// Eigen reference's FK, against the ideal arm fed the same stick. The linear modes (XY, XZ) are
// judged on the frame-6 origin along the commanded line; the rotation modes (R1, R2) on the
// hand's turn (the angle between its orientations) and on the origin, which must stay put.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ideal_arm.h"
#include "sweep_plan.h"

namespace wmra {
namespace sweep {

constexpr double kSample_s = 0.01;
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

struct Figures {
  unsigned ineligible = 0;      // the ideal arm's Ineligible bits (0: the test counts for S15)
  double steady_ratio = kNone;  // speed along the command over the steady window / commanded
  double off_axis_mm = kNone;   // linear: largest distance from the commanded line
  double orientation_deg = kNone;  // linear: largest turn of the hand
  double origin_mm = kNone;     // rotation: largest move of the frame-6 origin
  double peak_100ms = kNone;    // fastest 0.1 s while the stick is held / steady commanded speed
  double peak_20ms = kNone;     // the same over 0.02 s
  double release = kNone;       // travel after the release: mm (linear) or deg (rotation)
  double ideal_release = kNone;  // the ideal arm's
  double rebound_mm = kNone;    // linear: back from the furthest point after the release
  double settle_s = kNone;      // release to the last sample faster than 5 mm/s (2 deg/s)
  int elbow_crossings = 0;      // sin q3 changed sign
  bool elbow_flipped = false;   // and ended on the other branch
  // the ideal arm went >= 20 mm (10 deg), the arm < 10 % of that, and the ideal motion took no
  // singular factor towards zero at first (kTowardsSingular: there the firmware stops it)
  bool stuck = false;
  long long lost_steps = 0;
  int spec_pass = -1;           // S1/S2 (linear) or S3 (rotation): 1 pass, 0 fail, -1 not an S test (reversal)
};

struct Pose {
  Eigen::Vector3d p;
  Eigen::Matrix3d r;
};
inline Pose pose_of(const Joints& q) {
  const Eigen::Matrix4d t = ref::fk(q);
  return {t.block<3, 1>(0, 3), t.block<3, 3>(0, 0)};
}
inline double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// the commanded steady speed (m/s or rad/s) and, for the linear modes, its direction
inline double commanded_speed(config::Mode mode, double x, double y, const Joints& q, Eigen::Vector3d* direction) {
  const Twist t = mode_twist(mode, StickShaper::shape(x, y), q);
  const bool linear = mode == config::Mode::xy || mode == config::Mode::xz;
  if (linear && direction) *direction = t.v.normalized();
  return linear ? t.v.norm() : t.w.norm();
}

// The ideal arm's samples for the same test from q0, every kSample_s
inline std::vector<Joints> ideal_samples(const StickTest& test, const Joints& q0, unsigned& ineligible) {
  IdealArm arm(q0);
  std::vector<Joints> out{q0};
  const int steps = (int)std::lround((kDrive_s + kAfter_s) / 1e-3), per_sample = (int)std::lround(kSample_s / 1e-3);
  unsigned why_held = 0;
  for (int k = 0; k < steps; ++k) {
    const double t = k * 1e-3;
    const bool held = t < kDrive_s;
    const bool second = t >= kReverseAt_s;
    arm.step(test.mode, held ? (second ? test.x2 : test.x) : 0, held ? (second ? test.y2 : test.y) : 0, 1e-3);
    if (held) why_held = arm.ineligible();
    if ((k + 1) % per_sample == 0) out.push_back(arm.q());
  }
  ineligible = why_held;  // what happens while the hand coasts to rest after the release does not count
  return out;
}

inline Figures figures(const StickTest& test, const std::vector<Joints>& measured, long long lost_steps) {
  Figures f;
  f.lost_steps = lost_steps;
  if (measured.size() < 2) return f;
  const std::vector<Joints> ideal = ideal_samples(test, measured[0], f.ineligible);
  const size_t n = std::min(measured.size(), ideal.size());
  const bool linear = test.mode == config::Mode::xy || test.mode == config::Mode::xz;
  Eigen::Vector3d u, u2;
  const double c = commanded_speed(test.mode, test.x, test.y, measured[0], &u);
  commanded_speed(test.mode, test.x2, test.y2, measured[0], &u2);
  const size_t i_release = (size_t)std::lround(kDrive_s / kSample_s);
  const size_t i_steady = (size_t)std::lround((test.reversal() ? kReverseAt_s + 0.8 : 1.0) / kSample_s);
  std::vector<Pose> m(n), id(n);
  for (size_t i = 0; i < n; ++i) {
    m[i] = pose_of(measured[i]);
    id[i] = pose_of(ideal[i]);
  }
  // progress: along the final direction (linear), or the angle turned so far (rotation)
  std::vector<double> progress(n), ideal_progress(n);
  for (size_t i = 0; i < n; ++i) {
    if (linear) {
      progress[i] = (m[i].p - m[0].p).dot(u2);
      ideal_progress[i] = (id[i].p - id[0].p).dot(u2);
    } else {
      progress[i] = i == 0 ? 0 : progress[i - 1] + angle_between(m[i - 1].r, m[i].r);
      ideal_progress[i] = i == 0 ? 0 : ideal_progress[i - 1] + angle_between(id[i - 1].r, id[i].r);
    }
  }
  const double unit = linear ? 1000.0 : 180.0 / arm::kPi;  // mm or deg
  if (i_release < n && c > 0) {
    f.steady_ratio = (progress[i_release] - progress[i_steady]) / ((i_release - i_steady) * kSample_s * c);
    // a window's speed over the samples it spans, while the stick is held
    const auto peak = [&](size_t span) {
      double best = 0;
      for (size_t i = 0; i + span <= i_release; ++i) {
        const double d = linear ? (m[i + span].p - m[i].p).norm() : progress[i + span] - progress[i];
        best = std::max(best, d / (span * kSample_s));
      }
      return best / c;
    };
    f.peak_100ms = peak(10);
    f.peak_20ms = peak(2);
    f.release = (progress[n - 1] - progress[i_release]) * unit;
    f.ideal_release = (ideal_progress[n - 1] - ideal_progress[i_release]) * unit;
    double furthest = progress[i_release];
    for (size_t i = i_release; i < n; ++i) furthest = std::max(furthest, progress[i]);
    if (linear) f.rebound_mm = (furthest - progress[n - 1]) * unit;
    const double moving = linear ? 0.005 : arm::deg_to_rad(2);
    f.settle_s = 0;
    for (size_t i = i_release + 1; i < n; ++i) {
      const double speed = linear ? (m[i].p - m[i - 1].p).norm() / kSample_s : (progress[i] - progress[i - 1]) / kSample_s;
      if (speed > moving) f.settle_s = (i - i_release) * kSample_s;
    }
  }
  double off = 0, turn = 0, origin = 0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = m[i].p - m[0].p;
    off = std::max(off, (d - d.dot(u) * u).norm());
    turn = std::max(turn, angle_between(m[0].r, m[i].r));
    origin = std::max(origin, d.norm());
  }
  for (size_t i = 1; i < n; ++i)
    if ((std::sin(measured[i][2]) > 0) != (std::sin(measured[i - 1][2]) > 0)) ++f.elbow_crossings;
  f.elbow_flipped = (std::sin(measured[n - 1][2]) > 0) != (std::sin(measured[0][2]) > 0);
  const double ideal_held = i_release < n ? (linear ? (id[i_release].p - id[0].p).norm() : ideal_progress[i_release]) : 0;
  const double held = i_release < n ? (linear ? (m[i_release].p - m[0].p).norm() : progress[i_release]) : 0;
  f.stuck = ideal_held >= (linear ? 0.020 : arm::deg_to_rad(10)) && held < 0.1 * ideal_held && !test.reversal() &&
            !(f.ineligible & kTowardsSingular);
  if (linear) {
    f.off_axis_mm = off * 1000;
    f.orientation_deg = turn * 180 / arm::kPi;
    if (!test.reversal()) f.spec_pass = std::fabs(f.steady_ratio - 1) <= 0.05 && f.off_axis_mm <= 5 && f.orientation_deg <= 1;
  } else {
    f.origin_mm = origin * 1000;
    if (!test.reversal()) f.spec_pass = f.origin_mm <= 5 && std::fabs(f.steady_ratio - 1) <= 0.10;
  }
  return f;
}

}  // namespace sweep
}  // namespace wmra
