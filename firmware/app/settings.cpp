#include "app/settings.h"

#include "config/joints_config.h"
#include "kinematics/fixed_trig.h"

namespace wmra {
namespace app {

namespace {

void set_defaults(Settings& s) {
  using namespace config;
  const int32_t lo = (int32_t)kPotAtMin_mV * 1024 * kPositionUnitsPerCount / kAdcRef_mV;
  const int32_t hi = (int32_t)kPotAtMax_mV * 1024 * kPositionUnitsPerCount / kAdcRef_mV;
  for (uint8_t d = 0; d < 3; ++d) {
    s.pot_at_min_counts_x16[d] = (int16_t)lo;
    s.pot_at_max_counts_x16[d] = (int16_t)hi;
  }
  for (uint8_t slot = 0; slot < kPoseSlots; ++slot)
    for (uint8_t j = 0; j < 6; ++j) s.pose_angle[slot][j] = fx::angle_deg(Ratio{kReadyPose_deg[j], 1}).raw;
  s.pose_valid = 1;
}

bool plausible(const Settings& s) {
  for (uint8_t d = 0; d < 3; ++d) {
    if (s.pot_at_min_counts_x16[d] < 0 || s.pot_at_max_counts_x16[d] > 1023 * 16 ||
        s.pot_at_max_counts_x16[d] - s.pot_at_min_counts_x16[d] < 200 * 16)
      return false;
  }
  return true;
}

}  // namespace

eeprom_store::LoadResult load_settings(Settings& s) {
  eeprom_store::LoadResult r = eeprom_store::load(kSettingsVersion, &s, sizeof s);
  if (r == eeprom_store::LoadResult::loaded && !plausible(s)) r = eeprom_store::LoadResult::bad_crc;
  if (r != eeprom_store::LoadResult::loaded) set_defaults(s);
  return r;
}

void save_settings(const Settings& s) { eeprom_store::save(kSettingsVersion, &s, sizeof s); }

}  // namespace app
}  // namespace wmra
