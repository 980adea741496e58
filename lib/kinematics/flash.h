// Constant tables in program memory: on the AVR they live in flash and are read with LPM
// (8 KB of RAM is too little to copy them); on the host they are ordinary constants.
#pragma once

#include <stdint.h>

#if defined(__AVR__)
#include <avr/pgmspace.h>
#define WMRA_FLASH PROGMEM
namespace wmra {
namespace fx {
inline int16_t flash_read_i16(const int16_t* p) { return (int16_t)pgm_read_word(p); }
inline uint16_t flash_read_u16(const uint16_t* p) { return pgm_read_word(p); }
inline int32_t flash_read_i32(const int32_t* p) { return (int32_t)pgm_read_dword(p); }
}  // namespace fx
}  // namespace wmra
#else
#define WMRA_FLASH
namespace wmra {
namespace fx {
inline int16_t flash_read_i16(const int16_t* p) { return *p; }
inline uint16_t flash_read_u16(const uint16_t* p) { return *p; }
inline int32_t flash_read_i32(const int32_t* p) { return *p; }
}  // namespace fx
}  // namespace wmra
#endif
