#include "arm_statics.h"

#include <cmath>

namespace wmra {
namespace plant {

namespace {

using Vec = std::array<double, 3>;

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec apply(const Frame& f, const double local[3]) {
  Vec v;
  for (int r = 0; r < 3; ++r) v[r] = f.p[r] + f.R[r][0] * local[0] + f.R[r][1] * local[1] + f.R[r][2] * local[2];
  return v;
}

}  // namespace

std::array<Frame, kJoints> arm_frames(const std::array<double, kJoints>& q) {
  // Craig's modified DH, Table 3.3(b): alpha_{i-1}, a_{i-1}, d_i; theta_5 = q5 - pi/2
  const double alpha[kJoints] = {0, kPi / 2, 0, 0, kPi / 2, -kPi / 2};
  const double a[kJoints] = {0, arm::a1_m, arm::a2_m, arm::a3_m, arm::a4_m, 0};
  const double d[kJoints] = {arm::d1_m, 0, 0, 0, 0, arm::d6_m};
  std::array<Frame, kJoints> frames;
  Frame t = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}};
  for (int i = 0; i < kJoints; ++i) {
    const double th = q[i] - (i == 4 ? kPi / 2 : 0.0);
    const double ca = std::cos(alpha[i]), sa = std::sin(alpha[i]), ct = std::cos(th), st = std::sin(th);
    // local transform: rows of [R | p]
    const double L[3][4] = {{ct, -st, 0, a[i]}, {st * ca, ct * ca, -sa, -sa * d[i]}, {st * sa, ct * sa, ca, ca * d[i]}};
    Frame n;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) n.R[r][c] = t.R[r][0] * L[0][c] + t.R[r][1] * L[1][c] + t.R[r][2] * L[2][c];
      n.p[r] = t.p[r] + t.R[r][0] * L[0][3] + t.R[r][1] * L[1][3] + t.R[r][2] * L[2][3];
    }
    frames[i] = n;
    t = n;
  }
  return frames;
}

JointLoads joint_loads(const std::array<double, kJoints>& q, bool gravity, bool payload) {
  const auto f = arm_frames(q);
  struct Mass {
    Vec c;
    double m;
    int link;  // 0-based link index, or -1 for the payload
  };
  Mass masses[kJoints + 1];
  int n = 0;
  for (int j = 0; j < kJoints; ++j) {
    if (kLinks[j].mass_kg > 0) masses[n++] = {apply(f[j], kLinks[j].r_cm_m), kLinks[j].mass_kg, j};
  }
  if (payload) {
    const double local[3] = {0, 0, kPayloadOffsetM};
    masses[n++] = {apply(f[kJoints - 1], local), kPayloadKg, -1};
  }
  const Vec g = {0, 0, -kGravityMs2};

  JointLoads out;
  for (int i = 0; i < kJoints; ++i) {
    const Vec z = {f[i].R[0][2], f[i].R[1][2], f[i].R[2][2]};
    const Vec p = {f[i].p[0], f[i].p[1], f[i].p[2]};
    double tau = 0, inertia = 0;
    for (int k = 0; k < n; ++k) {
      const Mass& m = masses[k];
      if (m.link >= 0 && m.link < i) continue;  // inboard links do not move with joint i
      const Vec r = {m.c[0] - p[0], m.c[1] - p[1], m.c[2] - p[2]};
      const Vec arm = cross(z, r);
      tau += dot(arm, Vec{m.m * g[0], m.m * g[1], m.m * g[2]});
      inertia += m.m * dot(arm, arm);
      if (m.link >= 0) {  // the link's own inertia about an axis along z: z' I z in its frame
        const LinkMass& L = kLinks[m.link];
        Vec zl;
        for (int c = 0; c < 3; ++c) zl[c] = f[m.link].R[0][c] * z[0] + f[m.link].R[1][c] * z[1] + f[m.link].R[2][c] * z[2];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) inertia += zl[r] * L.inertia_kgm2[r][c] * zl[c];
      } else {
        inertia += m.m * kPayloadGyrationRadiusM * kPayloadGyrationRadiusM;
      }
    }
    out.gravity_nm[i] = gravity ? tau : 0.0;
    out.inertia_kgm2[i] = inertia;
  }
  return out;
}

}  // namespace plant
}  // namespace wmra
