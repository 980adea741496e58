// Configurations that are read once, at boot, kept in flash: on the AVR a constant that is passed
// by reference or indexed at run time is copied into RAM at start-up and stays there (.rodata is
// RAM), so a boot-only table costs its size in RAM for good. PROGMEM keeps one copy in flash, and
// from_flash() copies an entry into a temporary while it is used.
#pragma once

#include <avr/pgmspace.h>

namespace wmra {
namespace app {

template <typename T>
T from_flash(const T& in_flash) {
  T copy;
  memcpy_P(&copy, &in_flash, sizeof copy);
  return copy;
}

}  // namespace app
}  // namespace wmra
