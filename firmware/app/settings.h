// What the arm keeps across power cycles, in EEPROM (lib/drivers/eeprom_store.h): the DC
// joints' potentiometer calibration and the stored poses. Defaults come from the config when
// the EEPROM is blank, corrupt or from another layout version.
#pragma once

#include <stdint.h>

#include "drivers/eeprom_store.h"

namespace wmra {
namespace app {

constexpr uint8_t kPoseSlots = 4;

struct Settings {
  int16_t pot_at_min_counts_x16[3];  // ADC counts x 16 at each DC joint's lower limit
  int16_t pot_at_max_counts_x16[3];  // and at its upper limit
  int32_t pose_angle[kPoseSlots][6];  // fx::Angle raw; slot 0 defaults to the ready pose
  uint8_t pose_valid;                 // bit per slot
};

constexpr uint8_t kSettingsVersion = 1;

// loads, or sets the defaults; returns how
eeprom_store::LoadResult load_settings(Settings& s);
void save_settings(const Settings& s);

}  // namespace app
}  // namespace wmra
