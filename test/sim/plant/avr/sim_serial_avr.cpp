// UART0 at 115200 baud: at boot "boot MCUSR PINB PIND PINE" in hex (the reset cause and the
// switch inputs), then an echo of what arrives (RX interrupt). A 'W' starts the watchdog
// (15 ms) and hangs in a loop, an 'H' starts it and halts (sleep with interrupts off): the
// simulator must count each reset, and the inputs must read the same after it.
#include <avr/sleep.h>
#include <avr/wdt.h>

#include "board_io.h"

namespace {
volatile uint8_t rx[64];
volatile uint8_t head, tail;

void tx_hex(uint8_t v) {
  const char* h = "0123456789abcdef";
  io::uart0_send((uint8_t)h[v >> 4]);
  io::uart0_send((uint8_t)h[v & 15]);
}
}  // namespace

ISR(USART0_RX_vect) { rx[head++ & 63] = UDR0; }

int main() {
  const uint8_t cause = MCUSR;
  MCUSR = 0;
  wdt_disable();
  io::uart0_begin();
  PORTB = 0x7F;  // pull-ups on the port B switches
  const char* s = "boot ";
  while (*s) io::uart0_send((uint8_t)*s++);
  tx_hex(cause);
  io::uart0_send(' ');
  tx_hex(PINB & 0x7F);
  io::uart0_send(' ');
  tx_hex(PIND & 0x0F);
  io::uart0_send(' ');
  tx_hex(PINE & 0x30);
  io::uart0_send('\n');
  sei();
  for (;;) {
    while (tail != head) {
      const uint8_t c = rx[tail++ & 63];
      io::uart0_send(c);
      if (c == 'W') {
        wdt_enable(WDTO_15MS);
        for (;;) {
        }
      }
      if (c == 'H') {
        while (!(UCSR0A & (1 << TXC0))) {
        }
        wdt_enable(WDTO_15MS);
        cli();
        sleep_enable();
        sleep_cpu();
      }
    }
  }
}
