#include "drivers/watchdog.h"

#include <avr/io.h>
#include <avr/wdt.h>

namespace {
uint8_t g_reset_cause __attribute__((section(".noinit")));
}

// runs before main and before the C runtime initialises RAM
extern "C" void wmra_watchdog_init3() __attribute__((naked, used, section(".init3")));
extern "C" void wmra_watchdog_init3() {
  g_reset_cause = MCUSR;
  MCUSR = 0;
  wdt_disable();
}

namespace wmra {
namespace watchdog {

uint8_t reset_cause() { return g_reset_cause; }
void start() { wdt_enable(WDTO_60MS); }
void kick() { wdt_reset(); }

}  // namespace watchdog
}  // namespace wmra
