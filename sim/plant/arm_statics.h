// Gravity and inertia of the seed-2 arm about each joint axis, from the CAD mass properties
// (Torres, Table 3.4) and the payload, in the modified-DH frames of lib/kinematics.
#pragma once

#include <array>

#include "arm_plant_config.h"

namespace wmra {
namespace plant {

struct JointLoads {
  // torque that gravity applies about each joint axis (N m, + pushes the joint positive)
  std::array<double, kJoints> gravity_nm{};
  // inertia of everything outboard of each joint about its axis, the rest held still (kg m^2)
  std::array<double, kJoints> inertia_kgm2{};
};

struct Frame {
  double R[3][3];
  double p[3];
};

// frames 1..6 of the modified-DH chain in the base frame (index 0 = frame 1)
std::array<Frame, kJoints> arm_frames(const std::array<double, kJoints>& q);

JointLoads joint_loads(const std::array<double, kJoints>& q, bool gravity, bool payload);

}  // namespace plant
}  // namespace wmra
