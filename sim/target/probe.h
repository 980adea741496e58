// Target side of the simavr probe (see sim/runner/probe_ports.h): console output and timed
// regions for AVR programs run by avr-run. On a real board these are writes to unused
// general-purpose I/O registers and do nothing.
#pragma once

#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <stdint.h>

#include "probe_ports.h"

namespace probe {

inline void put(char c) { _SFR_IO8(WMRA_PROBE_CONSOLE_IO) = (uint8_t)c; }
// put() as a function object, for code that writes through a Put& sink
struct ConsolePut {
  void operator()(char c) const { put(c); }
};
inline void print(const char* s) {
  while (*s) put(*s++);
}
inline void print_hex(uint32_t v, uint8_t digits) {
  for (int8_t i = (int8_t)(digits - 1); i >= 0; --i) {
    const uint8_t n = (uint8_t)((v >> (4 * i)) & 0xF);
    put((char)(n < 10 ? '0' + n : 'a' + n - 10));
  }
}
inline void print_uint(uint32_t v) {
  char buf[11];
  uint8_t n = 0;
  do {
    buf[n++] = (char)('0' + v % 10);
    v /= 10;
  } while (v);
  while (n) put(buf[--n]);
}

// "@ID NAME" tells the runner what region ID measures
inline void name_region(uint8_t id, const char* name) {
  put('@');
  print_uint(id);
  put(' ');
  print(name);
  put('\n');
}
inline void start(uint8_t id) { _SFR_IO8(WMRA_PROBE_START_IO) = id; }
inline void stop(uint8_t id) { _SFR_IO8(WMRA_PROBE_STOP_IO) = id; }

// stop the simulation: sleep with interrupts off
[[noreturn]] inline void finish() {
  cli();
  sleep_enable();
  for (;;) sleep_cpu();
}

}  // namespace probe
