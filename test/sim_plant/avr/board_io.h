// Pin and timer access for the simulator's test images, from the board's pin map.
#pragma once

#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

#include "probe.h"
#include "wiring/atmega2560.h"
#include "wmra_mega/board.h"

namespace io {

using wmra::board::Channel;
using wmra::board::ComparePin;
using wmra::board::Pin;
using wmra::board::Timer;
namespace m2560 = wmra::m2560;

inline volatile uint8_t& reg8(uint16_t address) { return *(volatile uint8_t*)address; }
inline volatile uint16_t& reg16(uint16_t address) { return *(volatile uint16_t*)address; }

inline void output(Pin p) { reg8(m2560::ddr_register(p.port)) |= (uint8_t)(1 << p.bit); }
inline void input_pullup(Pin p) {
  reg8(m2560::ddr_register(p.port)) &= (uint8_t)~(1 << p.bit);
  reg8(m2560::port_register(p.port)) |= (uint8_t)(1 << p.bit);
}
inline void write(Pin p, bool high) {
  const uint8_t s = SREG;
  cli();
  if (high) {
    reg8(m2560::port_register(p.port)) |= (uint8_t)(1 << p.bit);
  } else {
    reg8(m2560::port_register(p.port)) &= (uint8_t)~(1 << p.bit);
  }
  SREG = s;
}
inline bool read(Pin p) { return (reg8(m2560::pin_register(p.port)) >> p.bit) & 1; }

inline volatile uint16_t& ocr(ComparePin c) { return reg16(m2560::timer_registers(c.timer).ocr[(int)c.channel]); }
// COMnx1:0 of a compare channel
inline void set_com(ComparePin c, uint8_t com) {
  volatile uint8_t& a = reg8(m2560::timer_registers(c.timer).tccra);
  const uint8_t shift = (uint8_t)m2560::com_shift(c.channel);
  a = (uint8_t)((a & ~(3 << shift)) | (com << shift));
}

inline void print_int(int32_t v) {
  if (v < 0) {
    probe::put('-');
    v = -v;
  }
  probe::print_uint((uint32_t)v);
}

}  // namespace io
