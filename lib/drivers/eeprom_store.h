// A block of settings in EEPROM with a header (magic, version, size) and a CRC-16, so that a
// blank chip, a half-written block or a block from another firmware version is detected and
// replaced by the defaults rather than trusted. Writing never blocks the control loop: save()
// marks the block dirty and service(), called every tick, writes one changed byte whenever the
// EEPROM is ready (3.4 ms a byte).
#pragma once

#include <stdint.h>

namespace wmra {
namespace eeprom_store {

enum class LoadResult : uint8_t { loaded = 0, blank = 1, bad_crc = 2, other_version = 3 };

// Reads the block at EEPROM address 0 into data (size bytes); anything but loaded leaves data
// undefined: the caller then sets its defaults.
LoadResult load(uint8_t version, void* data, uint16_t size);
// Schedules a write of data (kept by the caller until written; it may change meanwhile).
void save(uint8_t version, const void* data, uint16_t size);
void service();
bool busy();

}  // namespace eeprom_store
}  // namespace wmra
