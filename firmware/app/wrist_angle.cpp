#include "app/wrist_angle.h"

#include <avr/eeprom.h>

#include "core/record_ring.h"
#include "drivers/eeprom_map.h"
#include "kinematics/arm_model.h"

namespace wmra {
namespace app {
namespace wrist_angle {

namespace {

struct Eeprom {
  static uint8_t read(uint16_t address) { return eeprom_read_byte((const uint8_t*)address); }
  static void write(uint16_t address, uint8_t byte) { eeprom_write_byte((uint8_t*)address, byte); }
  static bool ready() { return eeprom_is_ready(); }
};

// 1: the value is J6's angle in Angle counts (fx::kAngleTurn a turn), kUnknown none
constexpr uint8_t kFormat = 1;
constexpr uint8_t kSlots = eeprom_map::kWristAngleRingBytes / 8;
using Ring = core::RecordRing<Eeprom, eeprom_map::kWristAngleRing, kSlots, kFormat>;
static_assert(Ring::kBytes == eeprom_map::kWristAngleRingBytes, "the ring fills its area");
constexpr int32_t kUnknown = INT32_MIN;
constexpr int32_t kMin = fx::angle_deg(Ratio{arm::q_min_deg[5], 1}).raw, kMax = fx::angle_deg(Ratio{arm::q_max_deg[5], 1}).raw;

Ring g_ring;

}  // namespace

bool load(fx::Angle& angle) {
  int32_t value;
  if (!g_ring.load(value) || value < kMin || value > kMax) return false;  // (kUnknown is below kMin)
  angle = fx::Angle{value};
  return true;
}

void record(fx::Angle angle) { g_ring.save(angle.raw); }
void forget() { g_ring.save(kUnknown); }
void service() { g_ring.service(); }

}  // namespace wrist_angle
}  // namespace app
}  // namespace wmra
