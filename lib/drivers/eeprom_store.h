// A block of settings in EEPROM with a header (magic, version, size, generation) and a CRC-16,
// so that a blank chip, a half-written block or a block from another firmware version is
// detected and not trusted. The block is kept twice (two copies):
// a save writes the copy that does not hold the newest valid block, its CRC last, and load()
// takes the valid copy of the newest generation. A power loss at any byte of a write leaves
// the old block or the new one, never none. Writing never blocks the control loop: save()
// marks the block dirty and service(), called every tick, writes one changed byte whenever the
// EEPROM is ready (3.4 ms a byte).
//
// Firmware before the two copies kept a single block at address 0 with a 5-byte header
// (magic "WA", no generation): load() reads it as copy 0 of generation 0 when neither copy is
// valid, so the first save keeps it and writes copy 1.
#pragma once

#include <stdint.h>

#include "drivers/eeprom_map.h"

namespace wmra {
namespace eeprom_store {

enum class LoadResult : uint8_t { loaded = 0, blank = 1, bad_crc = 2, other_version = 3 };

// the copies' places (eeprom_map.h); a copy is its header, the data and the CRC
constexpr uint16_t kHeaderBytes = 6;  // magic (2), version, size (2), generation
constexpr uint16_t kMaxDataBytes = eeprom_map::kSettingsCopyBytes - kHeaderBytes - 2;

// Reads the newest valid block of this version and size into data (size bytes); anything but
// loaded leaves data undefined: the caller then sets its defaults.
LoadResult load(uint8_t version, void* data, uint16_t size);
// Schedules a write of data (kept by the caller until written; it may change meanwhile). A save
// while a write is pending restarts that write (into the same copy) with the data as it is now.
void save(uint8_t version, const void* data, uint16_t size);
void service();
bool busy();

}  // namespace eeprom_store
}  // namespace wmra
