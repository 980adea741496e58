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

}  // namespace io
