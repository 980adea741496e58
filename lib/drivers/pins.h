// A board's pins (boards/<board>/board.h) as register accesses. Every address is a compile-time
// constant (the accessors are always inlined, also at -Os, so that it folds), so a write to a
// low port compiles to sbi/cbi; the ports above 0x5F (H..L) need a
// read-modify-write, done with interrupts masked so that an ISR's write to the same port is not
// lost.
#pragma once

#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

#include "atmega2560.h"

namespace wmra {
namespace pins {

using board::Channel;
using board::ComparePin;
using board::Pin;

__attribute__((always_inline)) inline volatile uint8_t& reg8(uint16_t address) { return *(volatile uint8_t*)address; }
__attribute__((always_inline)) inline volatile uint16_t& reg16(uint16_t address) { return *(volatile uint16_t*)address; }

__attribute__((always_inline)) inline void output(Pin p) { reg8(m2560::ddr_register(p.port)) |= (uint8_t)(1 << p.bit); }
__attribute__((always_inline)) inline void input_pullup(Pin p) {
  reg8(m2560::ddr_register(p.port)) &= (uint8_t)~(1 << p.bit);
  reg8(m2560::port_register(p.port)) |= (uint8_t)(1 << p.bit);
}
__attribute__((always_inline)) inline void write(Pin p, bool high) {
  const uint8_t s = SREG;
  cli();
  if (high) {
    reg8(m2560::port_register(p.port)) |= (uint8_t)(1 << p.bit);
  } else {
    reg8(m2560::port_register(p.port)) &= (uint8_t)~(1 << p.bit);
  }
  SREG = s;
}
__attribute__((always_inline)) inline bool read(Pin p) { return (reg8(m2560::pin_register(p.port)) >> p.bit) & 1; }

__attribute__((always_inline)) inline volatile uint16_t& ocr16(ComparePin c) { return reg16(m2560::timer_registers(c.timer).ocr[(int)c.channel]); }
__attribute__((always_inline)) inline volatile uint8_t& ocr8(ComparePin c) { return reg8(m2560::timer_registers(c.timer).ocr[(int)c.channel]); }
// COMnx1:0 of a compare channel (callers mask interrupts if an ISR writes the same TCCRnA)
__attribute__((always_inline)) inline void set_com(ComparePin c, uint8_t com) {
  volatile uint8_t& a = reg8(m2560::timer_registers(c.timer).tccra);
  const uint8_t shift = (uint8_t)m2560::com_shift(c.channel);
  a = (uint8_t)((a & ~(3 << shift)) | (com << shift));
}

}  // namespace pins
}  // namespace wmra
