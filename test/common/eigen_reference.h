// Independent reference for the kinematics tests: the arm as six modified-DH matrices
// multiplied with Eigen, its geometric Jacobian from those frames, and Eigen's inverse.
// Nothing here uses the closed forms under test or the thesis's printed Jacobian.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <random>

#include "kinematics/arm_model.h"

namespace wmra::ref {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Joints = std::array<double, 6>;

// Craig's link transform, Eq. 2.14 of seed 2
inline Eigen::Matrix4d mdh(double alpha, double a, double d, double theta) {
  const double ca = std::cos(alpha), sa = std::sin(alpha), ct = std::cos(theta), st = std::sin(theta);
  Eigen::Matrix4d t;
  t << ct, -st, 0, a, st * ca, ct * ca, -sa, -sa * d, st * sa, ct * sa, ca, ca * d, 0, 0, 0, 1;
  return t;
}

// frames 0T1 .. 0T6 from Table 3.3(b); joint 5's DH angle is q5 - pi/2
inline std::array<Eigen::Matrix4d, 6> frames(const Joints& q) {
  using namespace wmra::arm;
  const double alpha[6] = {0, kPi / 2, 0, 0, kPi / 2, -kPi / 2};
  const double a[6] = {0, a1_m, a2_m, a3_m, a4_m, 0};
  const double d[6] = {d1_m, 0, 0, 0, 0, d6_m};
  const double offset[6] = {0, 0, 0, 0, -kPi / 2, 0};
  std::array<Eigen::Matrix4d, 6> out;
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) {
    t = t * mdh(alpha[i], a[i], d[i], q[i] + offset[i]);
    out[i] = t;
  }
  return out;
}

inline Eigen::Matrix4d fk(const Joints& q) { return frames(q)[5]; }

// geometric Jacobian of the frame-6 origin, rows (v; w) in the base frame
inline Mat6 geometric_jacobian(const Joints& q) {
  const auto f = frames(q);
  const Eigen::Vector3d p6 = f[5].block<3, 1>(0, 3);
  Mat6 j;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d z = f[i].block<3, 1>(0, 2);
    const Eigen::Vector3d p = f[i].block<3, 1>(0, 3);
    j.block<3, 1>(0, i) = z.cross(p6 - p);
    j.block<3, 1>(3, i) = z;
  }
  return j;
}

// Jacobian by central differences of fk: linear part from the position, angular part from
// the skew-symmetric part of dR R^T
inline Mat6 numeric_jacobian(const Joints& q, double h = 1e-6) {
  Mat6 j;
  const Eigen::Matrix3d r0 = fk(q).block<3, 3>(0, 0);
  for (int i = 0; i < 6; ++i) {
    Joints qp = q, qm = q;
    qp[i] += h;
    qm[i] -= h;
    const Eigen::Matrix4d tp = fk(qp), tm = fk(qm);
    j.block<3, 1>(0, i) = (tp.block<3, 1>(0, 3) - tm.block<3, 1>(0, 3)) / (2 * h);
    const Eigen::Matrix3d w = (tp.block<3, 3>(0, 0) - tm.block<3, 3>(0, 0)) / (2 * h) * r0.transpose();
    j(3, i) = w(2, 1);
    j(4, i) = w(0, 2);
    j(5, i) = w(1, 0);
  }
  return j;
}

inline Joints random_joints(std::mt19937_64& rng) {
  Joints q;
  for (int i = 0; i < 6; ++i) {
    std::uniform_real_distribution<double> u(wmra::arm::q_min_rad(i), wmra::arm::q_max_rad(i));
    q[i] = u(rng);
  }
  return q;
}

}  // namespace wmra::ref
