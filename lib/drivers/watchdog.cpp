#include "drivers/watchdog.h"

#include <avr/io.h>
#include <avr/wdt.h>

namespace {
constexpr uint32_t kTrace = 0x574D5241;  // "WMRA": random RAM after a power loss matches it 1 in 2^32
uint8_t g_mcusr __attribute__((section(".noinit")));
uint32_t g_trace __attribute__((section(".noinit")));
volatile uint8_t g_stalled __attribute__((section(".noinit")));
uint8_t g_reset_cause;
void (*g_outputs_off)();
}  // namespace

// runs before main and before the C runtime initialises RAM
extern "C" void wmra_watchdog_init3() __attribute__((naked, used, section(".init3")));
extern "C" void wmra_watchdog_init3() {
  g_mcusr = MCUSR;
  MCUSR = 0;
  wdt_disable();
}

namespace wmra {
namespace watchdog {

uint8_t reset_cause() { return g_reset_cause; }

void start(void (*outputs_off)()) {
  g_outputs_off = outputs_off;
  g_reset_cause = g_mcusr != 0             ? g_mcusr
                  : g_trace != kTrace      ? (uint8_t)(kInferred | kPowerOn)
                  : g_stalled != 0         ? (uint8_t)(kInferred | kWatchdog)
                                           : (uint8_t)(kInferred | kExternal);
  g_trace = kTrace;
  g_stalled = 0;
  wdt_enable(WDTO_60MS);
}

void kick() { wdt_reset(); }

void stalled() {
  g_stalled = 1;
  g_outputs_off();
  for (;;) {
  }
}

}  // namespace watchdog
}  // namespace wmra
