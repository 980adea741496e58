// The firmware of the wheelchair-mounted arm on the ATmega2560 (docs/design.md).
//
// Start-up: every output is made safe before anything else (drivers disabled, bridges low),
// then the watchdog, the settings and J6's angle at rest from EEPROM, the peripherals, and a
// boot frame with the reset cause and whether J6's angle was recorded. Then, every 1 ms: one
// control iteration (its drives' loops included) with the timing probe (D49) high,
// the watchdog kicked, the serial link served and an EEPROM byte written if one is pending;
// between ticks the CPU sleeps (idle), which is what the simulator counts as free time.
#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

#include "app/arm_control.h"
#include "app/link.h"
#include "app/settings.h"
#include "app/wrist_angle.h"
#include "drivers/bridges.h"
#include "drivers/eeprom_store.h"
#include "drivers/inputs.h"
#include "drivers/pins.h"
#include "drivers/steppers.h"
#include "drivers/system_tick.h"
#include "drivers/uart.h"
#include "drivers/watchdog.h"
#include "protocol/messages.h"
#include "wmra_mega/board.h"

using namespace wmra;

int main() {
  steppers::start();
  bridges::start();
  pins::write(board::kTimingProbe, false);
  pins::output(board::kTimingProbe);
  watchdog::start(&app::outputs_off);

  static app::Settings settings;
  const eeprom_store::LoadResult loaded = app::load_settings(settings);
  fx::Angle j6_at_rest;
  const bool j6_recorded = app::wrist_angle::load(j6_at_rest);
  tick::start();
  uart::start();
  inputs::start(&app::stop_from_interrupt);
  app::start(settings, j6_recorded ? &j6_at_rest : nullptr);
  app::link::start(watchdog::reset_cause(), (uint8_t)((uint8_t)loaded | (j6_recorded ? protocol::kBootJ6AngleRecorded : 0)));
  sei();

  static app::Requests requests{false, false, false, -1, false, false, {0, 0, 0}, {0, 0, 0}, 0, 0, false, false};
  for (;;) {
    const uint8_t ticks = tick::wait();
    // TCNT1 read with interrupts off: its high byte comes through Timer1's TEMP byte, which the
    // tick's and the servo's ISRs overwrite with their compare writes (datasheet 17.3)
    uint16_t begin, end;
    ATOMIC_BLOCK(ATOMIC_FORCEON) { begin = TCNT1; }
    pins::write(board::kTimingProbe, true);
    app::iterate(requests, ticks);
    pins::write(board::kTimingProbe, false);
    ATOMIC_BLOCK(ATOMIC_FORCEON) { end = TCNT1; }
    const uint16_t counts = (uint16_t)(end - begin);  // Timer1 counts at 2 MHz: 8 CPU cycles a count
    watchdog::kick();
    app::link::poll(requests, ticks, counts > 8191 ? 0xFFFF : (uint16_t)(counts * 8));
    eeprom_store::service();
    app::wrist_angle::service();
  }
}
