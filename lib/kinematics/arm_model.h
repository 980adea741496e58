// The seed-2 wheelchair arm: Craig's modified DH (Table 3.3(b) of the thesis), joint limits
// (Table 3.7) and the singular factors of its Jacobian.
//
// Joint variable convention: q5 = 0 is the arm stretched; the DH angle of joint 5 is
// q5 - pi/2 (seed2-digest, red flag 5). At q = 0 the frame-6 origin is at (1.077, 0, 0.187) m.
#pragma once

namespace wmra {
namespace arm {

constexpr double kPi = 3.14159265358979323846;
constexpr double deg(double d) { return d * kPi / 180.0; }

// link lengths and offsets, metres
constexpr double d1_m = 0.187;
constexpr double a1_m = 0.014;
constexpr double a2_m = 0.350;
constexpr double a3_m = 0.350;
constexpr double a4_m = 0.165;
constexpr double d6_m = 0.198;

constexpr int kJoints = 6;
constexpr double q_min_rad[kJoints] = {deg(-90), deg(-45), deg(-135), deg(-160), deg(-90), deg(-360)};
constexpr double q_max_rad[kJoints] = {deg(90), deg(135), deg(160), deg(160), deg(90), deg(360)};

// The Jacobian's determinant is -c5 s3 a2 a3 R5 with R5 = a1 + c2 a2 + c23 a3 + c234 a4,
// the horizontal distance of the joint-5 origin from the base axis. Each factor has a
// band where the inverse is damped (status singular) and a wider band where the
// firmware slows down (status near_singular).
struct SingularBands {
  double damp_c5;
  double damp_s3;
  double damp_r5_m;
  double slow_c5;
  double slow_s3;
  double slow_r5_m;
};
constexpr SingularBands kSingularBands = {0.05, 0.05, 0.05, 0.20, 0.20, 0.15};

// The wrist reaches at most this far from the base axis, so R5 always fits a Unit.
constexpr double max_r5_m = a1_m + a2_m + a3_m + a4_m;
static_assert(max_r5_m < 1.0, "R5 is carried as a Q15 Unit and must stay below 1 m");
static_assert(a1_m < 1 && a2_m < 1 && a3_m < 1 && a4_m < 1 && d1_m < 1 && d6_m < 1,
              "link constants are UQ16 Lengths and must stay below 1 m");
static_assert(d1_m + a2_m + a3_m + a4_m + d6_m < 2.0, "positions must stay far inside the Real range");

}  // namespace arm
}  // namespace wmra
