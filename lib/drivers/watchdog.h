// The watchdog and the reset cause. After a watchdog reset the watchdog stays on at its
// shortest period, so it is switched off in .init3, before the C runtime's data copy; the
// cause (MCUSR) is saved there and cleared for the next reset.
#pragma once

#include <stdint.h>

namespace wmra {
namespace watchdog {

enum ResetCause : uint8_t { kPowerOn = 1, kExternal = 2, kBrownOut = 4, kWatchdog = 8 };  // MCUSR bits

uint8_t reset_cause();  // MCUSR as it was at this reset
void start();           // 60 ms: many control ticks, but far less than a person's reaction
void kick();

}  // namespace watchdog
}  // namespace wmra
