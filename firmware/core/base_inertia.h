// The arm's inertia about the base axis at a pose, and the hand's distance from that axis: what
// J1's stepper stops, and how far the hand goes while it does (config/stop_config.h).
//
// The point masses of config/gravity_config.h, each at its horizontal distance r from the base
// axis: I = sum m r^2, plus the links' own inertia about their centres (a constant). As in
// core/gravity.h, u is the horizontal unit vector of the arm's vertical plane; the centre of link
// i (2, 3, 4) lies along u at x c(q2..qi) - y s(q2..qi) beyond the joints before it, and the
// wrist's masses lie on y5 = c5 x4 + s5 z4: along u by L c5 c234, and out of the plane (along
// z4) by L s5. J2's axis is a1 from the base axis along u. Distances in mm, rounded up to 8 mm
// for the squares: an upper bound, which makes J1's stop only gentler. Checked on the host
// against the simulator's inertia (test/host/test_gravity.cpp).
#pragma once

#include <stdint.h>

#include "config/gravity_config.h"
#include "kinematics/arm_model.h"
#include "kinematics/fixed_point.h"

namespace wmra {
namespace core {

namespace base_inertia_detail {
constexpr int16_t mm(double m) { return (int16_t)(m * 1000 + 0.5); }
constexpr int16_t kA1 = mm(arm::a1_m), kA2 = mm(arm::a2_m), kA3 = mm(arm::a3_m), kA4 = mm(arm::a4_m);
constexpr int16_t kPayloadOnY5_mm = (int16_t)(mm(arm::d6_m) + config::kPayloadOffset_mm);
// The links' own inertia about vertical axes through their centres (Table 3.4's largest
// diagonal terms: links 1..5, 2 + 21 + 19 + 5 + 2 g m^2) and link 3's centre 90 mm off the
// arm's plane (1.235 kg: 10 g m^2), which the point masses leave out
constexpr uint16_t kOwn_gm2 = 60;
// one term: mass (g) times the distance's square, in units of (8 mm)^2 (each coordinate rounded
// up to 8 mm: a shift, where whole cm were two divisions a term, ~400 cycles)
inline uint32_t term(int16_t mass_g, int16_t along_mm, int16_t off_mm) {
  const uint16_t a = (uint16_t)(((along_mm < 0 ? -along_mm : along_mm) >> 3) + 1);
  const uint16_t o = (uint16_t)(((off_mm < 0 ? -off_mm : off_mm) >> 3) + 1);
  return fx::mul_uu((uint16_t)mass_g, (uint16_t)(fx::mul_uu(a, a) + fx::mul_uu(o, o)));
}
// len (mm) x a Unit, mm: the product's bits 15..30, as the high half of it doubled (a byte move;
// a shift by 15 is a loop at -Os, ~140 cycles a product)
inline int16_t along(int16_t len_mm, fx::Unit c) { return (int16_t)fx::hi16((uint32_t)fx::mul_ss(len_mm, c.raw) << 1); }
}  // namespace base_inertia_detail

struct BaseLoad {
  uint16_t inertia_gm2;    // about the base axis, g m^2 (kg mm^2 / 1000)
  uint16_t hand_reach_mm;  // the frame-6 origin's distance from the base axis, from above
};

// Trig: kin::JacobianTrig<kin::Fixed> (c2, s2, c23, s23, c234, s234, c5, s5)
template <class Trig>
BaseLoad base_load(const Trig& t) {
  using namespace base_inertia_detail;
  const config::LinkCentre* c = config::kLinkCentre;
  const int16_t elbow = (int16_t)(kA1 + along(kA2, t.c2));
  const int16_t wrist_base = (int16_t)(elbow + along(kA3, t.c23));
  const int16_t wrist = (int16_t)(wrist_base + along(kA4, t.c234));
  const fx::Unit c5c234 = t.c5 * t.c234;
  uint32_t sum = 0;  // g (8 mm)^2
  sum += term(c[0].mass_g, (int16_t)(kA1 + along(c[0].x_mm, t.c2) - along(c[0].y_mm, t.s2)), 0);
  sum += term(c[1].mass_g, (int16_t)(elbow + along(c[1].x_mm, t.c23) - along(c[1].y_mm, t.s23)), 0);
  sum += term(c[2].mass_g, (int16_t)(wrist_base + along(c[2].x_mm, t.c234) - along(c[2].y_mm, t.s234)), 0);
  sum += term(config::kLink5Mass_g, (int16_t)(wrist + along(config::kLink5CentreY_mm, c5c234)),
              along(config::kLink5CentreY_mm, t.s5));
  sum += term(config::kPayloadMass_g, (int16_t)(wrist + along(kPayloadOnY5_mm, c5c234)), along(kPayloadOnY5_mm, t.s5));
  // g m^2 = sum 64 / 10^6 = sum 2^-14 1.0486: by shifts, sum (2^-14 + 2^-18 + 2^-19), 1.6 % over
  const uint16_t inertia = (uint16_t)((sum >> 14) + (sum >> 18) + (sum >> 19) + 1 + kOwn_gm2);
  // the hand's distance, from above without a root: max + min / 2 of its two components is
  // at least their length (and at most 1.12 times it)
  const int16_t hand_along = (int16_t)(wrist + along(mm(arm::d6_m), c5c234)), hand_off = along(mm(arm::d6_m), t.s5);
  const uint16_t ha = (uint16_t)(hand_along < 0 ? -hand_along : hand_along), ho = (uint16_t)(hand_off < 0 ? -hand_off : hand_off);
  // (+4: the products above are floored)
  const uint16_t reach = (uint16_t)((ha > ho ? ha + (ho >> 1) : ho + (ha >> 1)) + 4);
  return BaseLoad{inertia, reach};
}

}  // namespace core
}  // namespace wmra
