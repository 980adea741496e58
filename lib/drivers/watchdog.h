// The watchdog and the reset cause. After a watchdog reset the watchdog stays on at its
// shortest period, so it is switched off in .init3, before the C runtime's data copy; the
// cause (MCUSR) is saved there and cleared for the next reset.
//
// The Mega's stock stk500v2 bootloader clears MCUSR itself and does not pass it on, so behind
// it the firmware sees 0 after every reset. The cause is then inferred from RAM, which a
// watchdog or external reset keeps and a power loss does not: a 32-bit trace this firmware
// leaves once it runs, and a stall mark the tick ISR sets when the loop has not taken its
// ticks for kStallMark_ms (a watchdog reset follows within ~30 ms unless the loop comes back,
// and its next kick clears the mark). A hang with interrupts off leaves no mark: it reads as
// an external reset.
#pragma once

#include <stdint.h>

namespace wmra {
namespace watchdog {

enum ResetCause : uint8_t {
  kPowerOn = 1, kExternal = 2, kBrownOut = 4, kWatchdog = 8,  // MCUSR bits
  kInferred = 0x80,  // MCUSR was clear (a bootloader cleared it): the cause from RAM
};
constexpr uint8_t kStallMark_ms = 30;  // half the watchdog's 60 ms

namespace detail {
extern volatile uint8_t g_stalled;
}

// MCUSR as it was at this reset, or the inferred cause | kInferred (a brown-out that kept RAM
// reads as external, one that did not as power-on)
uint8_t reset_cause();
void start();  // 60 ms: many control ticks, but far less than a person's reaction
void kick();   // also clears the stall mark: the loop came back
// from the tick ISR, the moment the loop has gone kStallMark_ms without taking its ticks
inline void mark_stall() { detail::g_stalled = 1; }

}  // namespace watchdog
}  // namespace wmra
