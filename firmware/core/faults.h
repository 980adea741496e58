// The firmware's fault bits, as the supervisor latches them and telemetry reports them.
// Bits 0..11 are the plausibility flags of the DC joints (lib/control/plausibility.h), four per
// joint; the rest are the arm's own. kFaultsLatched are the ones that stop the arm until a
// re-arm; the others are conditions reported while they last.
#pragma once

#include <stdint.h>

namespace wmra {
namespace core {

enum FaultBit : uint8_t {
  kFaultBitJ2 = 0,  // J2's stall, sign, jump, rail at bits 0..3; J3 at 4..7; J4 at 8..11
  kFaultBitLimitUnexpected = 12,  // a limit switch closed that the motion did not expect
  kFaultBitHomingFailed = 13,     // a stepper did not find its switch within its travel
  kFaultBitTracking = 14,         // a DC joint fell too far behind its reference
  kFaultBitMovedWhileStopped = 15,  // a DC joint's pot moved while its bridge braked (worm, gear)
  kFaultBitStickInvalid = 16,     // the joystick reads at a rail (unplugged, broken): no motion
  kFaultBitLoopOverrun = 17,      // a control iteration missed its tick
  kFaultBitPositionLost = 18,     // a stepper's switch closed where its count says it cannot be
};

constexpr uint32_t fault_mask(uint8_t bit) { return (uint32_t)1 << bit; }
// the plausibility flags (control::PlausibilityFault) of DC joint d (0 = J2, 1 = J3, 2 = J4)
constexpr uint32_t dc_joint_faults(uint8_t d, uint8_t plausibility_flags) {
  return (uint32_t)(plausibility_flags & 0x0F) << (kFaultBitJ2 + 4 * d);
}

constexpr uint32_t kFaultsLatched = 0xFFFFu | fault_mask(kFaultBitPositionLost);  // bits 0..15, 18

// names for telemetry decoders, index = bit; empty = unused
constexpr const char* kFaultNames[32] = {
    "j2_stall", "j2_sign", "j2_jump", "j2_rail", "j3_stall", "j3_sign", "j3_jump", "j3_rail",
    "j4_stall", "j4_sign", "j4_jump", "j4_rail", "limit_unexpected", "homing_failed", "tracking", "moved_while_stopped",
    "stick_invalid", "loop_overrun", "position_lost", "", "", "", "", "",
    "", "", "", "", "", "", "", ""};

}  // namespace core
}  // namespace wmra
