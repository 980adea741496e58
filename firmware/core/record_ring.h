// A value that changes often (J6's angle at rest) kept in EEPROM as a ring of small
// records: each save writes the next slot, so each slot takes one save in kSlots and the cells
// wear kSlots times slower than one record rewritten in place. A record is 8 bytes:
//
//   seq (uint16) | value (int32) | crc (uint16)        little-endian
//
// The CRC (CRC-16/CCITT-FALSE, the serial link's) covers a format byte, seq and value: the
// format is not stored, so a record of another format (another firmware's meaning of the value)
// fails the check as a corrupt one does. load() takes the valid record with the newest seq
// (serial arithmetic: seq wraps at 2^16, and the valid records of a ring span kSlots of them).
//
// A save writes the slot after the newest record, which holds the oldest, one byte per
// service() while the EEPROM is ready, seq first and the CRC last: from the first byte that
// changes to the last the slot fails its check, so a power loss at any byte of the write leaves
// the newest record as it was, and load() returns the value saved before. A save while one is
// under way restarts it in the same slot with the new value.
//
// Memory is the EEPROM's access, static functions: uint8_t read(uint16_t address),
// void write(uint16_t address, uint8_t byte), bool ready() (a byte may be written now).
#pragma once

#include <stdint.h>

#include "protocol/frame.h"

namespace wmra {
namespace core {

template <class Memory, uint16_t kBase, uint8_t kSlots, uint8_t kFormat>
class RecordRing {
 public:
  static constexpr uint8_t kRecordBytes = 8;
  static constexpr uint16_t kBytes = (uint16_t)kSlots * kRecordBytes;
  static_assert(kSlots >= 2 && kSlots <= 255, "a ring of 2 to 255 slots");

  // The newest valid record's value: false when no slot holds a valid record (a new board, a
  // lost EEPROM, records of another format). Every later save goes after the newest: called
  // before the first save.
  bool load(int32_t& value) {
    bool found = false;
    for (uint8_t slot = 0; slot < kSlots; ++slot) {
      uint8_t r[kRecordBytes];
      read_record(slot, r);
      if (!valid(r)) continue;
      const uint16_t seq = (uint16_t)(r[0] | (uint16_t)r[1] << 8);
      if (found && (int16_t)(seq - seq_) <= 0) continue;
      found = true;
      newest_ = slot;
      seq_ = seq;
      value = (int32_t)((uint32_t)r[2] | (uint32_t)r[3] << 8 | (uint32_t)r[4] << 16 | (uint32_t)r[5] << 24);
    }
    if (!found) {
      newest_ = kSlots - 1;  // the first save writes slot 0
      seq_ = 0xFFFF;
    }
    return found;
  }

  // Schedules a record of value (written by service()).
  void save(int32_t value) {
    if (!writing_) target_ = (uint8_t)(newest_ + 1 == kSlots ? 0 : newest_ + 1);
    const uint16_t seq = (uint16_t)(seq_ + 1);
    image_[0] = (uint8_t)seq;
    image_[1] = (uint8_t)(seq >> 8);
    for (uint8_t i = 0; i < 4; ++i) image_[2 + i] = (uint8_t)((uint32_t)value >> (8 * i));
    const uint16_t crc = crc_of(image_);
    image_[6] = (uint8_t)crc;
    image_[7] = (uint8_t)(crc >> 8);
    next_ = 0;
    writing_ = true;
  }

  // One byte of a scheduled record, if the EEPROM is ready: bytes that already hold their value
  // are passed over (a read is fast), at most one is written. The call after the last byte's
  // write ends the record.
  void service() {
    if (!writing_ || !Memory::ready()) return;
    const uint16_t base = address(target_);
    while (next_ < kRecordBytes) {
      const uint8_t i = next_++;
      if (Memory::read((uint16_t)(base + i)) != image_[i]) {
        Memory::write((uint16_t)(base + i), image_[i]);
        return;
      }
    }
    newest_ = target_;
    seq_ = (uint16_t)(image_[0] | (uint16_t)image_[1] << 8);
    writing_ = false;
  }

  bool busy() const { return writing_; }

 private:
  static uint16_t address(uint8_t slot) { return (uint16_t)(kBase + (uint16_t)slot * kRecordBytes); }
  static void read_record(uint8_t slot, uint8_t* r) {
    const uint16_t base = address(slot);
    for (uint8_t i = 0; i < kRecordBytes; ++i) r[i] = Memory::read((uint16_t)(base + i));
  }
  static uint16_t crc_of(const uint8_t* r) {
    uint16_t crc = protocol::crc16_update(protocol::kCrcInit, kFormat);
    for (uint8_t i = 0; i < kRecordBytes - 2; ++i) crc = protocol::crc16_update(crc, r[i]);
    return crc;
  }
  static bool valid(const uint8_t* r) { return crc_of(r) == (uint16_t)(r[6] | (uint16_t)r[7] << 8); }

  // all zero until load(): the firmware keeps the ring in .bss
  uint8_t newest_ = 0;   // the slot of the newest valid record
  uint16_t seq_ = 0;     // and its seq
  uint8_t target_ = 0;   // the slot being written
  uint8_t next_ = 0;     // the next byte of image_ to write (kRecordBytes: all written, ends at the next call)
  bool writing_ = false;
  uint8_t image_[kRecordBytes] = {};
};

}  // namespace core
}  // namespace wmra
