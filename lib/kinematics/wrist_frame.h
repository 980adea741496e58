// Axes of frame 5 (the wrist frame that the rotation modes turn about), in the base frame.
//
// In the frame turned by q1 (see inverse_jacobian.h) the joint-5 axis is z5 = (s234, 0, -c234)
// and the joint-6 axis is z6 = (c234 c5, -s5, s234 c5). With alpha5 = -pi/2, z6 is y5, and
// x5 = y5 x z5 = (s5 c234, c5, s5 s234). Turning by q1 gives the base
// frame. test/host checks all three against the DH frames.
#pragma once

#include "kinematics/forward_kinematics.h"

namespace wmra {
namespace kin {

template <class N>
struct WristAxes {
  Vec3<typename N::Unit> x5, y5, z5;
};

template <class N, class Trig>
Vec3<typename N::Unit> turned_by_q1(const Trig& t, const Vec3<typename N::Unit>& v) {
  return Vec3<typename N::Unit>{t.c1 * v.x - t.s1 * v.y, t.s1 * v.x + t.c1 * v.y, v.z};
}

// the axes in the frame turned by q1 (inverse_jacobian.h's J^-1 of w about them, the rotation
// modes', is written out from these)
template <class N, class Trig>
WristAxes<N> wrist_axes_turned(const Trig& t) {
  WristAxes<N> a;
  a.x5 = {t.s5 * t.c234, t.c5, t.s5 * t.s234};
  a.y5 = {t.c234 * t.c5, -t.s5, t.s234 * t.c5};
  a.z5 = {t.s234, typename N::Unit{}, -t.c234};
  return a;
}

template <class N, class Trig>
WristAxes<N> wrist_axes(const Trig& t) {
  const WristAxes<N> turned = wrist_axes_turned<N>(t);
  return WristAxes<N>{turned_by_q1<N>(t, turned.x5), turned_by_q1<N>(t, turned.y5), turned_by_q1<N>(t, turned.z5)};
}

}  // namespace kin
}  // namespace wmra
