// J6's angle at rest, kept in EEPROM as a ring of records (core/record_ring.h) in its
// own area (drivers/eeprom_map.h), apart from the settings: a record is 8 bytes, and the ring's
// 128 slots share the writes, so each cell takes one record in 128 (100,000 writes a cell: 12.8
// million records). The EEPROM writes one byte at a time: service() shares it with the settings'
// writer (eeprom_store.h), each writing only while it is ready.
#pragma once

#include <stdint.h>

#include "kinematics/fixed_trig.h"

namespace wmra {
namespace app {
namespace wrist_angle {

// The angle recorded last, false when none is: a new board, a lost EEPROM, records of another
// format, an angle beyond J6's range, or a homing that found the recorded angle wrong (forget()).
bool load(fx::Angle& angle);
void record(fx::Angle angle);  // J6 at rest there: a record (written by service())
void forget();                 // J6's angle is not known: a record that says so
void service();                // every tick: a byte of a pending record, if the EEPROM is ready

}  // namespace wrist_angle
}  // namespace app
}  // namespace wmra
