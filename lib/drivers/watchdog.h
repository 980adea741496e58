// The watchdog and the reset cause. After a watchdog reset the watchdog stays on at its
// shortest period, so it is switched off in .init3, before the C runtime's data copy; the
// cause (MCUSR) is saved there and cleared for the next reset.
//
// The Mega's stock stk500v2 bootloader clears MCUSR itself and does not pass it on, so behind
// it the firmware sees 0 after every reset. The cause is then inferred from RAM, which a
// watchdog or external reset keeps and a power loss does not: a 32-bit trace this firmware
// leaves once it runs, and a stall mark set when the loop has stalled (below). A hang with
// interrupts off leaves no mark: it reads as an external reset.
//
// A stall: the main loop has not taken its ticks for kStallCut_ms while interrupts still run.
// The watchdog alone would leave the outputs as the loop last set them until it bites (60 ms:
// a stepper at its last speed, a bridge at its last duty). The tick ISR enters stalled()
// instead: every output off at once, then nothing runs until the watchdog resets the chip
// (60 ms after the loop's last kick). A stall is never waited out: the loop's longest pass (an
// iteration and a state frame) is under 1.5 ms, so a loop kStallCut_ms late is broken.
#pragma once

#include <stdint.h>

namespace wmra {
namespace watchdog {

enum ResetCause : uint8_t {
  kPowerOn = 1, kExternal = 2, kBrownOut = 4, kWatchdog = 8,  // MCUSR bits
  kInferred = 0x80,  // MCUSR was clear (a bootloader cleared it): the cause from RAM
};
constexpr uint8_t kStallCut_ms = 10;
static_assert(kStallCut_ms >= 5 && kStallCut_ms < 60, "several ticks of margin, and the cut well before the watchdog's 60 ms");

// MCUSR as it was at this reset, or the inferred cause | kInferred (a brown-out that kept RAM
// reads as external, one that did not as power-on)
uint8_t reset_cause();
// 60 ms: many control ticks, but far less than a person's reaction. outputs_off: what makes
// every output safe (the safety button's), for stalled().
void start(void (*outputs_off)());
void kick();
// From the tick ISR (interrupts off), the moment the loop has gone kStallCut_ms without taking
// its ticks: marks the stall, turns the outputs off and waits for the watchdog's reset.
[[noreturn]] void stalled();

}  // namespace watchdog
}  // namespace wmra
