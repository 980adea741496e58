#include "app/settings.h"

#include "config/joints_config.h"
#include "kinematics/fixed_trig.h"

namespace wmra {
namespace app {

namespace {

using namespace config;
constexpr int16_t kConfigAtMin_counts_x16 = (int16_t)((int32_t)kPotAtMin_mV * 1024 * kPositionUnitsPerCount / kAdcRef_mV);
constexpr int16_t kConfigAtMax_counts_x16 = (int16_t)((int32_t)kPotAtMax_mV * 1024 * kPositionUnitsPerCount / kAdcRef_mV);

// a pot across the 10-bit ADC's range, its limits at least 200 counts apart (a quarter of
// the range: less would leave a count worth more than ~0.5 deg of the joint)
bool plausible(int16_t at_min, int16_t at_max) {
  return at_min >= 0 && at_max <= 1023 * 16 && at_max - at_min >= 200 * 16;
}
static_assert(kConfigAtMin_counts_x16 >= 0 && kConfigAtMax_counts_x16 <= 1023 * 16 &&
                  kConfigAtMax_counts_x16 - kConfigAtMin_counts_x16 >= 200 * 16,
              "joints_config.h's pot calibration passes the check a person's calibration does");

// the config's values for the joints nobody calibrated
void apply_config_calibration(Settings& s) {
  for (uint8_t d = 0; d < 3; ++d) {
    if (s.pot_calibrated & (1 << d)) continue;
    s.pot_at_min_counts_x16[d] = kConfigAtMin_counts_x16;
    s.pot_at_max_counts_x16[d] = kConfigAtMax_counts_x16;
  }
}

void set_defaults(Settings& s) {
  for (uint8_t slot = 0; slot < kPoseSlots; ++slot)
    for (uint8_t j = 0; j < 6; ++j) s.pose_angle[slot][j] = fx::angle_deg(Ratio{kReadyPose_deg[j], 1}).raw;
  s.pose_valid = 1;
  s.pot_calibrated = 0;
  apply_config_calibration(s);
}

bool plausible(const Settings& s) {
  for (uint8_t d = 0; d < 3; ++d) {
    if (!plausible(s.pot_at_min_counts_x16[d], s.pot_at_max_counts_x16[d])) return false;
  }
  return true;
}

}  // namespace

// Version 1 was this block without pot_calibrated, and no command could set its calibration:
// its poses are kept and its calibration is the config's.
eeprom_store::LoadResult load_settings(Settings& s) {
  eeprom_store::LoadResult r = eeprom_store::load(kSettingsVersion, &s, sizeof s);
  if (r == eeprom_store::LoadResult::other_version &&
      eeprom_store::load(1, &s, sizeof s - sizeof s.pot_calibrated) == eeprom_store::LoadResult::loaded) {
    s.pot_calibrated = 0;
    r = eeprom_store::LoadResult::loaded;
  }
  if (r == eeprom_store::LoadResult::loaded) {
    apply_config_calibration(s);
    if (!plausible(s)) r = eeprom_store::LoadResult::bad_crc;
  }
  if (r != eeprom_store::LoadResult::loaded) set_defaults(s);
  return r;
}

bool set_pot_calibration(Settings& s, uint8_t d, int16_t at_min_counts_x16, int16_t at_max_counts_x16) {
  if (d >= 3) return false;
  if (at_min_counts_x16 == 0 && at_max_counts_x16 == 0) {
    s.pot_calibrated &= (uint8_t)~(1 << d);
    apply_config_calibration(s);
  } else {
    if (!plausible(at_min_counts_x16, at_max_counts_x16)) return false;
    s.pot_at_min_counts_x16[d] = at_min_counts_x16;
    s.pot_at_max_counts_x16[d] = at_max_counts_x16;
    s.pot_calibrated |= (uint8_t)(1 << d);
  }
  save_settings(s);
  return true;
}

void save_settings(const Settings& s) { eeprom_store::save(kSettingsVersion, &s, sizeof s); }

}  // namespace app
}  // namespace wmra
