// Pin and timer access for the simulator's test images, from the board's pin map.
#pragma once

#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

#include "probe.h"
#include "drivers/pins.h"
#include "wmra_mega/board.h"

namespace io {

using wmra::board::Channel;
using wmra::board::ComparePin;
using wmra::board::Pin;
using wmra::board::Timer;
namespace m2560 = wmra::m2560;
using wmra::pins::input_pullup;
using wmra::pins::output;
using wmra::pins::read;
using wmra::pins::reg16;
using wmra::pins::reg8;
using wmra::pins::set_com;
using wmra::pins::write;
inline volatile uint16_t& ocr(ComparePin c) { return wmra::pins::ocr16(c); }

inline void print_int(int32_t v) {
  if (v < 0) {
    probe::put('-');
    v = -v;
  }
  probe::print_uint((uint32_t)v);
}

// UART0 at 115200 baud (U2X, UBRR 16: 117,647 baud, 2.1 % off), 8N1, receive interrupt on
inline void uart0_begin() {
  UCSR0A = 1 << U2X0;
  UBRR0 = 16;
  UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
  UCSR0C = 3 << UCSZ00;
}
inline void uart0_send(uint8_t c) {
  while (!(UCSR0A & (1 << UDRE0))) {
  }
  UDR0 = c;
}

}  // namespace io
