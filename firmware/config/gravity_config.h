// What the DC joints lift: the arm's mass properties (Torres's thesis, Table 3.4, from CAD),
// the payload it is designed for, and the torque of the DC drives. The firmware's gravity
// feedforward (firmware/core/gravity.h) is built from these at compile time. Only the parts
// that load J2..J4 matter: each link's centre of mass in its own frame (x, y; z lies along the
// joint axes and makes no torque about them), and the wrist's mass on its joint-5 frame's y axis.
#pragma once

#include <stdint.h>

namespace wmra {
namespace config {

struct LinkCentre {
  int16_t x_mm, y_mm;  // centre of mass in the link's own frame (modified DH)
  int16_t mass_g;
};
// links 2, 3, 4 (Table 3.4)
constexpr LinkCentre kLinkCentre[3] = {{231, 7, 1257}, {235, -8, 1235}, {97, 30, 672}};
// link 5: on y5, which is z6 (the tool axis)
constexpr int16_t kLink5CentreY_mm = 91;
constexpr int16_t kLink5Mass_g = 537;
// The payload on the tool axis, this far beyond the frame-6 origin: seed 2's design load, 1.2 kg
// at 10 cm. The integral of each joint's PID takes up whatever the real load differs by; set
// what the arm carries most of the time.
constexpr int16_t kPayloadMass_g = 1200;
constexpr int16_t kPayloadOffset_mm = 100;

// The Mabuchi 578VA with its worm: 9.12 N m at stall at 12 V (Torres, Table 3.1); each DC joint's own
// gear after it, tenths (1:4.5, 1:2.5, 1:2)
constexpr int16_t kDcStallTorque_cNm = 912;
constexpr int16_t kDcGear_tenths[3] = {45, 25, 20};
// A worm gear that does not back-drive takes a load that aids the motion itself: lowering needs
// no effort against gravity, only lifting does (and at rest the joint holds unpowered).
constexpr bool kDcSelfLocking = true;

constexpr bool link_centres_ok() {
  for (int i = 0; i < 3; ++i)
    if (kLinkCentre[i].mass_g <= 0 || kLinkCentre[i].mass_g > 10000 || kLinkCentre[i].x_mm < -500 ||
        kLinkCentre[i].x_mm > 500 || kLinkCentre[i].y_mm < -500 || kLinkCentre[i].y_mm > 500)
      return false;
  return true;
}
static_assert(link_centres_ok(),
              "kLinkCentre: each link's mass in (0, 10] kg and its centre within 0.5 m of its joint (a link's own "
              "length; the holding efforts' sum below full duty is checked in core/gravity.h)");
static_assert(kLink5Mass_g > 0 && kLink5Mass_g <= 10000 && kLink5CentreY_mm >= -300 && kLink5CentreY_mm <= 300,
              "kLink5Mass_g in (0, 10] kg, kLink5CentreY_mm within 0.3 m of the wrist");
static_assert(kPayloadMass_g >= 0 && kPayloadMass_g <= 3000 && kPayloadOffset_mm >= 0 && kPayloadOffset_mm <= 300,
              "kPayloadMass_g in [0, 3000], kPayloadOffset_mm in [0, 300] beyond the frame-6 origin");
static_assert(kDcStallTorque_cNm > 0 && kDcGear_tenths[0] >= 10 && kDcGear_tenths[1] >= 10 && kDcGear_tenths[2] >= 10,
              "kDcStallTorque_cNm > 0, kDcGear_tenths >= 10 (a reduction)");
static_assert(kDcStallTorque_cNm <= 10000 && kDcGear_tenths[0] <= 1000 && kDcGear_tenths[1] <= 1000 && kDcGear_tenths[2] <= 1000,
              "kDcStallTorque_cNm at most 100 N m, kDcGear_tenths at most 100:1 (a typo by a factor of ten)");

}  // namespace config
}  // namespace wmra
