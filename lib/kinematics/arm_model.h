// The wheelchair arm of R. A. Torres's thesis (2020; seed 2): Craig's modified DH (Table 3.3(b) of
// the thesis), joint limits (Table 3.7) and the singular factors of its Jacobian.
//
// Joint variable convention: q5 = 0 is the arm stretched; the DH angle of joint 5 is
// q5 - pi/2 (as the thesis's Eq. 4.5 and all after it use its theta'5; its Eq. 3.1 says the
// opposite). At q = 0 the frame-6 origin is at (1.077, 0, 0.187) m.
// Numbers are exact ratios (ratio.h) so that the fixed-point constants are the same on the
// AVR and the host; the *_m and *_rad doubles are for host code.
#pragma once

#include "kinematics/ratio.h"

namespace wmra {
namespace arm {

constexpr double kPi = 3.14159265358979323846;

// link lengths and offsets, metres (from millimetres)
constexpr Ratio d1{187, 1000};
constexpr Ratio a1{14, 1000};
constexpr Ratio a2{350, 1000};
constexpr Ratio a3{350, 1000};
constexpr Ratio a4{165, 1000};
constexpr Ratio d6{198, 1000};
constexpr double d1_m = to_double(d1), a1_m = to_double(a1), a2_m = to_double(a2), a3_m = to_double(a3),
                 a4_m = to_double(a4), d6_m = to_double(d6);

constexpr int kJoints = 6;
constexpr int16_t q_min_deg[kJoints] = {-90, -45, -135, -160, -90, -360};
constexpr int16_t q_max_deg[kJoints] = {90, 135, 160, 160, 90, 360};
constexpr double deg_to_rad(double d) { return d * kPi / 180.0; }
constexpr double q_min_rad(int joint) { return deg_to_rad(q_min_deg[joint]); }
constexpr double q_max_rad(int joint) { return deg_to_rad(q_max_deg[joint]); }

// The Jacobian's determinant is -c5 s3 a2 a3 R5 with R5 = a1 + c2 a2 + c23 a3 + c234 a4,
// the horizontal distance of the joint-5 origin from the base axis. Each factor has a
// band where the inverse is damped (status singular) and a wider band where the
// firmware slows down (status near_singular).
struct SingularBands {
  Ratio damp_c5;
  Ratio damp_s3;
  Ratio damp_r5_m;
  Ratio slow_c5;
  Ratio slow_s3;
  Ratio slow_r5_m;
};
constexpr SingularBands kSingularBands = {{5, 100}, {5, 100}, {5, 100}, {20, 100}, {20, 100}, {15, 100}};

// Inverse kinematics calls a pose degenerate (a free joint, infinitely many solutions) when
// the joint-5 origin is within this many metres of the base axis or |cos q5| is below it:
// one step of a Q15 Unit, so the fixed-point code only flags exact zeros of its inputs.
constexpr Ratio kIkDegenerate{1, 50000};

// The wrist reaches at most this far from the base axis, so R5 always fits a Unit.
constexpr double max_r5_m = a1_m + a2_m + a3_m + a4_m;
static_assert(max_r5_m < 1.0, "R5 is carried as a Q15 Unit and must stay below 1 m");
static_assert(d1_m + a2_m + a3_m < 1.0, "the height chain d1 + s2 a2 + s23 a3 is summed as a Q31 Span");
static_assert(a1_m < 1 && a2_m < 1 && a3_m < 1 && a4_m < 1 && d1_m < 1 && d6_m < 1,
              "link constants are UQ16 Lengths and must stay below 1 m");
static_assert(d1_m + a2_m + a3_m + a4_m + d6_m < 2.0, "positions must stay far inside the Real range");

}  // namespace arm
}  // namespace wmra
