// The pose that S3's R2 turn starts from (test/sim/firmware/test_motion_scenarios.cpp), joint
// angles in degrees. At the ready pose the turn is out of the arm's reach;
// test/host/test_turn_reach.cpp checks both and tells how this pose was chosen.
#pragma once

namespace wmra {
namespace test {

constexpr double kR2Pose_deg[6] = {70, 20, -80, -145, 0, 0};

}  // namespace test
}  // namespace wmra
