// What the arm keeps across power cycles, in EEPROM (lib/drivers/eeprom_store.h): the DC
// joints' potentiometer calibration, the stored poses and the joystick's released centre.
// Defaults come from the config when the EEPROM is blank, corrupt or from another layout
// version (versions 1 and 2 keep what they had: the layout only grew at the end). A joint's calibration is kept
// only once a person set it (cmd_pot_calibration); until then it follows joints_config.h at
// every boot, so that an edited config takes effect on the next flash although flashing
// leaves the EEPROM as it was.
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
  uint8_t pot_calibrated;             // bit per DC joint: its two values were set by a person
  uint16_t stick_centre_counts[2];    // the stick's released centre x, y (cmd_stick_centre); 0 0: none
};

// 2 added pot_calibrated at the end, 3 stick_centre_counts; a version 1 block keeps its poses,
// a version 2 block its poses and calibration (load_settings)
constexpr uint8_t kSettingsVersion = 3;

// loads, or sets the defaults; returns how
eeprom_store::LoadResult load_settings(Settings& s);
void save_settings(const Settings& s);
// One DC joint's (d: 0..2 for J2..J4) pot counts x 16 at its limits; both 0 return it to
// joints_config.h. False, changing nothing, for values no pot and amplifier could give, a
// reversed pot (at_min above at_max: swap its outer wires, docs/arm-guide.md), or limits that
// leave the pot's present reading beyond one of them by more than the rail check's margin.
bool set_pot_calibration(Settings& s, uint8_t d, int16_t at_min_counts_x16, int16_t at_max_counts_x16,
                         int16_t reading_counts_x16);
// The stick's released centre (x, y counts), kept; 0 0 forgets it. False, changing nothing, for
// a centre beyond kStickCentreTolerance_counts of mid-scale (what a new board accepts).
bool set_stick_centre(Settings& s, uint16_t x_counts, uint16_t y_counts);

}  // namespace app
}  // namespace wmra
