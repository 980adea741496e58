#include "app/settings.h"

#include <stddef.h>

#include "config/control_config.h"
#include "config/joints_config.h"
#include "core/resolved_rate.h"
#include "kinematics/fixed_trig.h"
#include "kinematics/flash.h"
#include "protocol/messages.h"

namespace wmra {
namespace app {

namespace {

using namespace config;
constexpr int16_t kConfigAtMin_counts_x16 = (int16_t)((int32_t)kPotAtMin_mV * 1024 * kPositionUnitsPerCount / kAdcRef_mV);
constexpr int16_t kConfigAtMax_counts_x16 = (int16_t)((int32_t)kPotAtMax_mV * 1024 * kPositionUnitsPerCount / kAdcRef_mV);

// Both readings within the 10-bit ADC's range, the upper limit's at least 600 counts above the
// lower's (in 32 bits: int is 16 on the AVR, and a difference of two int16 overflows it). The
// tracking thresholds are in pot units (15 mrad slows the hand, 50 stops it): with J4's 320 deg
// over 600 counts a count is 9.3 mrad, and the slow threshold stays above 1.5 counts of noise.
constexpr int16_t kMaxReading_counts_x16 = 1023 * 16;
constexpr int32_t kMinSpan_counts_x16 = protocol::kPotCalibrationMinSpan_counts_x16;
constexpr bool plausible(int16_t at_min, int16_t at_max) {
  return at_min >= 0 && at_min <= kMaxReading_counts_x16 && at_max >= 0 && at_max <= kMaxReading_counts_x16 &&
         (int32_t)at_max - at_min >= kMinSpan_counts_x16;
}
static_assert(plausible(kConfigAtMin_counts_x16, kConfigAtMax_counts_x16),
              "joints_config.h's pot calibration passes the check a person's calibration does");

// the config's values for the joints nobody calibrated
void apply_config_calibration(Settings& s) {
  for (uint8_t d = 0; d < 3; ++d) {
    if (s.pot_calibrated & (1 << d)) continue;
    s.pot_at_min_counts_x16[d] = kConfigAtMin_counts_x16;
    s.pot_at_max_counts_x16[d] = kConfigAtMax_counts_x16;
  }
}

// The ready pose in Angle counts, in flash: converted at run time (a joint a run-time index)
// angle_deg's Ratio was 64-bit arithmetic, which linked libgcc's 64-bit division
struct PoseCounts {
  int32_t angle[6];
};
constexpr PoseCounts ready_pose() {
  PoseCounts p{};
  for (uint8_t j = 0; j < 6; ++j) p.angle[j] = fx::angle_deg(Ratio{kReadyPose_deg[j], 1}).raw;
  return p;
}
constexpr PoseCounts kReadyPose WMRA_FLASH = ready_pose();

void set_ready_pose(Settings& s, uint8_t slot) {
  for (uint8_t j = 0; j < 6; ++j) s.pose_angle[slot][j] = fx::flash_read_i32(&kReadyPose.angle[j]);
}

void set_defaults(Settings& s) {
  for (uint8_t slot = 0; slot < kPoseSlots; ++slot) set_ready_pose(s, slot);
  s.pose_valid = 1;
  s.pot_calibrated = 0;
  s.stick_centre_counts[0] = s.stick_centre_counts[1] = 0;
  apply_config_calibration(s);
}

// The soft stops (a joint stops this far inside its switch), Angle counts, the control loop's
// (core::joint_motion_limits); in flash (48 bytes of RAM otherwise)
struct SoftStops {
  int32_t min[6], max[6];
};
constexpr SoftStops soft_stops() {
  SoftStops stops{};
  for (uint8_t j = 0; j < 6; ++j) {
    stops.min[j] = core::joint_motion_limits(j).soft_min.raw;
    stops.max[j] = core::joint_motion_limits(j).soft_max.raw;
  }
  return stops;
}
constexpr SoftStops kSoftStops WMRA_FLASH = soft_stops();

// A stored pose beyond a soft stop (store_pose clamps to them: a block with a valid CRC that
// this firmware did not write, an edited config's narrower limits) is dropped: a move to it would drive
// a joint past its soft stop towards the switch. The ready pose falls back to the config's.
void drop_poses_beyond_the_soft_stops(Settings& s) {
  for (uint8_t slot = 0; slot < kPoseSlots; ++slot) {
    bool within = true;
    for (uint8_t j = 0; j < 6; ++j)
      if (s.pose_angle[slot][j] < fx::flash_read_i32(&kSoftStops.min[j]) ||
          s.pose_angle[slot][j] > fx::flash_read_i32(&kSoftStops.max[j]))
        within = false;
    if (within) continue;
    s.pose_valid &= (uint8_t)~(1 << slot);
    if (slot == 0) {
      set_ready_pose(s, 0);
      s.pose_valid |= 1;
    }
  }
}

// none (0 0), or a centre a new board's calibration would accept (the joystick's mid-scale:
// adc_max / 2, 511)
constexpr uint16_t kStickMid_counts = 1023 / 2;
bool near_mid(uint16_t c) { return (uint16_t)(c - (kStickMid_counts - kStickCentreTolerance_counts)) <= 2 * kStickCentreTolerance_counts; }
bool plausible_stick_centre(uint16_t x, uint16_t y) { return (x == 0 && y == 0) || (near_mid(x) && near_mid(y)); }

bool plausible(const Settings& s) {
  for (uint8_t d = 0; d < 3; ++d) {
    if (!plausible(s.pot_at_min_counts_x16[d], s.pot_at_max_counts_x16[d])) return false;
  }
  return plausible_stick_centre(s.stick_centre_counts[0], s.stick_centre_counts[1]);
}

}  // namespace

// Version 1 was this block without pot_calibrated, and no command could set its calibration:
// its poses are kept and its calibration is the config's. Version 2 was the block without
// stick_centre_counts: it keeps everything and has no stored centre (a new board's check).
constexpr uint16_t kVersion1Bytes = offsetof(Settings, pot_calibrated);
constexpr uint16_t kVersion2Bytes = offsetof(Settings, stick_centre_counts);
static_assert(kVersion1Bytes == 6 * 2 + kPoseSlots * 6 * 4 + 1, "version 1's fields, packed as avr-gcc packs them");
static_assert(kVersion2Bytes == kVersion1Bytes + 1, "version 2's fields, packed as avr-gcc packs them");
static_assert(sizeof(Settings) <= eeprom_store::kMaxDataBytes, "the settings fit a copy's room in EEPROM");
eeprom_store::LoadResult load_settings(Settings& s) {
  eeprom_store::LoadResult r = eeprom_store::load(kSettingsVersion, &s, sizeof s);
  if (r == eeprom_store::LoadResult::other_version) {
    s.stick_centre_counts[0] = s.stick_centre_counts[1] = 0;
    if (eeprom_store::load(2, &s, kVersion2Bytes) == eeprom_store::LoadResult::loaded) {
      r = eeprom_store::LoadResult::loaded;
    } else if (eeprom_store::load(1, &s, kVersion1Bytes) == eeprom_store::LoadResult::loaded) {
      s.pot_calibrated = 0;
      r = eeprom_store::LoadResult::loaded;
    }
  }
  if (r == eeprom_store::LoadResult::loaded) {
    apply_config_calibration(s);
    drop_poses_beyond_the_soft_stops(s);
    if (!plausible(s)) r = eeprom_store::LoadResult::bad_crc;
  }
  if (r != eeprom_store::LoadResult::loaded) set_defaults(s);
  return r;
}

// The joint stands between its limits, so its pot reads between their readings: a calibration
// that puts the present reading beyond one (a typo, the two values swapped) would be stored and
// then fault or move the joint at the next arming. The tolerance is the pot rail check's margin
// (kRailMargin_counts, 20 counts, 6 to 11 deg over J2-J4's spans): a joint resting on its end
// stop, a few counts of noise past the reading taken there, is accepted.
constexpr int16_t kReadingBeyondLimit_counts_x16 = kRailMargin_counts * kPositionUnitsPerCount;

bool set_pot_calibration(Settings& s, uint8_t d, int16_t at_min_counts_x16, int16_t at_max_counts_x16,
                         int16_t reading_counts_x16) {
  if (d >= 3) return false;
  if (at_min_counts_x16 == 0 && at_max_counts_x16 == 0) {
    s.pot_calibrated &= (uint8_t)~(1 << d);
    apply_config_calibration(s);
  } else {
    if (!plausible(at_min_counts_x16, at_max_counts_x16)) return false;
    if (reading_counts_x16 < at_min_counts_x16 - kReadingBeyondLimit_counts_x16 ||
        reading_counts_x16 > at_max_counts_x16 + kReadingBeyondLimit_counts_x16)
      return false;
    s.pot_at_min_counts_x16[d] = at_min_counts_x16;
    s.pot_at_max_counts_x16[d] = at_max_counts_x16;
    s.pot_calibrated |= (uint8_t)(1 << d);
  }
  save_settings(s);
  return true;
}

bool set_stick_centre(Settings& s, uint16_t x_counts, uint16_t y_counts) {
  if (!plausible_stick_centre(x_counts, y_counts)) return false;
  s.stick_centre_counts[0] = x_counts;
  s.stick_centre_counts[1] = y_counts;
  save_settings(s);
  return true;
}

void save_settings(const Settings& s) { eeprom_store::save(kSettingsVersion, &s, sizeof s); }

}  // namespace app
}  // namespace wmra
