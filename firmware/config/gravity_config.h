// What the DC joints lift: the arm's mass properties (seed 2, Table 3.4 from CAD, digest 1.6),
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

// The Mabuchi 578VA with its worm: 9.12 N m at stall at 12 V (digest 1.2); each DC joint's own
// gear after it, tenths (SPEC 4: 1:4.5, 1:2.5, 1:2)
constexpr int16_t kDcStallTorque_cNm = 912;
constexpr int16_t kDcGear_tenths[3] = {45, 25, 20};
// A worm gear that does not back-drive takes a load that aids the motion itself: lowering needs
// no effort against gravity, only lifting does (and at rest the joint holds unpowered).
constexpr bool kDcSelfLocking = true;

static_assert(kPayloadMass_g >= 0 && kPayloadMass_g <= 3000 && kPayloadOffset_mm >= 0 && kPayloadOffset_mm <= 300,
              "payload: 0..3 kg, 0..300 mm beyond the frame-6 origin");
static_assert(kDcStallTorque_cNm > 0 && kDcGear_tenths[0] >= 10 && kDcGear_tenths[1] >= 10 && kDcGear_tenths[2] >= 10,
              "a DC drive's stall torque and its joint gear (a reduction)");

}  // namespace config
}  // namespace wmra
