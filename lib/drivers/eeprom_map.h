// Where each thing the firmware keeps lives in the ATmega2560's 4 KB of EEPROM:
//
//   0    .. 1023   the settings, copy 0 (eeprom_store.h)
//   1024 .. 2047   free
//   2048 .. 3071   the settings, copy 1
//   3072 .. 4095   J6's angle at rest, a ring of records (firmware/app/wrist_angle.h)
//
// The copies stay at 0 and 2048, where boards in use keep them (a copy once had the whole
// 2 KB; the settings take 134 bytes of it). The ring takes the top kilobyte, which no firmware
// wrote before it: its own check tells its records from whatever is there.
#pragma once

#include <stdint.h>

namespace wmra {
namespace eeprom_map {

constexpr uint16_t kBytes = 4096;
constexpr uint16_t kSettingsCopy[2] = {0, 2048};
constexpr uint16_t kSettingsCopyBytes = 1024;
constexpr uint16_t kWristAngleRing = 3072;
constexpr uint16_t kWristAngleRingBytes = 1024;

static_assert(kSettingsCopy[0] + kSettingsCopyBytes <= kSettingsCopy[1] &&
                  kSettingsCopy[1] + kSettingsCopyBytes <= kWristAngleRing && kWristAngleRing + kWristAngleRingBytes <= kBytes,
              "the areas do not overlap and fit the EEPROM");

}  // namespace eeprom_map
}  // namespace wmra
