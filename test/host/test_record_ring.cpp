// The EEPROM record ring (firmware/core/record_ring.h) on a model of the chip's EEPROM: what a
// power-up finds after saves, after a power loss at any byte of a write (the byte being written
// left as anything), after records of another format or a corrupt one, and how the writes
// spread over the cells.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <vector>

#include "core/record_ring.h"

namespace wmra {
namespace core {
namespace {

// The EEPROM: 4 KB, a write count per byte; a power loss after `writes_left` more writes
// (each byte written as torn_value instead, then nothing more)
struct Eeprom {
  static std::array<uint8_t, 4096> bytes;
  static std::array<uint32_t, 4096> writes;
  static long writes_left;
  static int torn_value;  // -1: the interrupted write leaves the old byte
  static uint8_t read(uint16_t a) { return bytes.at(a); }
  static void write(uint16_t a, uint8_t v) {
    if (writes_left == 0) return;  // no power
    if (--writes_left == 0 && torn_value >= 0) v = (uint8_t)torn_value;
    if (writes_left == 0 && torn_value < 0) return;
    bytes.at(a) = v;
    ++writes.at(a);
  }
  static bool ready() { return true; }
  static void erase() {
    bytes.fill(0xFF);
    writes.fill(0);
    writes_left = -1;
    torn_value = -1;
  }
};
std::array<uint8_t, 4096> Eeprom::bytes;
std::array<uint32_t, 4096> Eeprom::writes;
long Eeprom::writes_left = -1;
int Eeprom::torn_value = -1;

constexpr uint16_t kBase = 3072;
constexpr uint8_t kSlots = 128;
using Ring = RecordRing<Eeprom, kBase, kSlots, 1>;
using OtherFormat = RecordRing<Eeprom, kBase, kSlots, 2>;

// a power-up: a new ring reads the EEPROM
bool power_up(int32_t& value) {
  Ring r;
  return r.load(value);
}

void save_whole(Ring& r, int32_t value) {
  r.save(value);
  for (int i = 0; i < 20 && r.busy(); ++i) r.service();
  ASSERT_FALSE(r.busy());
}

class RecordRingTest : public ::testing::Test {
 protected:
  void SetUp() override { Eeprom::erase(); }
};

TEST_F(RecordRingTest, ABlankOrZeroedEepromHoldsNoRecord) {
  int32_t v = 0;
  EXPECT_FALSE(power_up(v)) << "erased (0xFF)";
  Eeprom::bytes.fill(0);
  EXPECT_FALSE(power_up(v)) << "zeroed";
}

TEST_F(RecordRingTest, TheNewestSaveWinsOverManyTurnsOfTheRing) {
  Ring r;
  int32_t v;
  ASSERT_FALSE(r.load(v));
  for (int32_t k = 0; k < 3 * kSlots + 17; ++k) {
    save_whole(r, k * 1000 - 70000);
    ASSERT_TRUE(power_up(v));
    ASSERT_EQ(v, k * 1000 - 70000) << "save " << k;
  }
}

// 70,000 saves: the 16-bit seq wraps; the newest still wins, and a ring loaded anew after the
// wrap goes on from it
TEST_F(RecordRingTest, TheSeqWrapsWithoutLosingTheNewest) {
  Ring r;
  int32_t v;
  r.load(v);
  for (int32_t k = 0; k < 70000; ++k) {
    save_whole(r, k);
    if (k % 9973 == 0 || k > 65530) {
      ASSERT_TRUE(power_up(v));
      ASSERT_EQ(v, k);
    }
  }
  Ring again;
  ASSERT_TRUE(again.load(v));
  save_whole(again, -5);
  ASSERT_TRUE(power_up(v));
  EXPECT_EQ(v, -5);
}

// A power loss at every byte of a write, the byte being written left as it was or as any of a
// few values: the power-up finds the value saved before, or (the write complete) the new one,
// never anything else and never none.
TEST_F(RecordRingTest, APowerLossAtAnyByteKeepsTheValueBefore) {
  int cases = 0, old_kept = 0;
  for (int torn : {-1, 0x00, 0xFF, 0x5A}) {
    for (int saves_before = 1; saves_before < 2 * kSlots + 3; saves_before += 37) {
      for (long cut = 1; cut <= 8; ++cut) {
        Eeprom::erase();
        Ring r;
        int32_t v;
        r.load(v);
        for (int k = 0; k < saves_before; ++k) save_whole(r, 1000 + k);
        const int32_t before = 1000 + saves_before - 1, after = -123456789;
        // the bytes this save changes, from a whole save on a copy
        const std::array<uint8_t, 4096> kept = Eeprom::bytes;
        Ring whole = r;
        save_whole(whole, after);
        int changed = 0;
        for (int a = 0; a < 4096; ++a) changed += Eeprom::bytes[a] != kept[a];
        Eeprom::bytes = kept;
        Eeprom::writes_left = cut;
        Eeprom::torn_value = torn;
        r.save(after);
        for (int i = 0; i < 20 && r.busy(); ++i) r.service();
        ++cases;
        ASSERT_TRUE(power_up(v)) << "torn " << torn << " before " << saves_before << " cut " << cut;
        ASSERT_TRUE(v == before || v == after) << v;
        if (cut < changed) {
          EXPECT_EQ(v, before) << "an unfinished record: the value before; cut at write " << cut << " of " << changed;
        }
        old_kept += v == before;
      }
    }
  }
  std::printf("power losses during a write: %d cases, the value before kept in %d\n", cases, old_kept);
}

// a save after a power loss mid-write goes into the slot the loss spoiled, and wins
TEST_F(RecordRingTest, ASaveAfterAPowerLossWins) {
  Ring r;
  int32_t v;
  r.load(v);
  save_whole(r, 11);
  Eeprom::writes_left = 3;
  r.save(22);
  for (int i = 0; i < 20; ++i) r.service();
  Eeprom::writes_left = -1;
  Ring after;
  ASSERT_TRUE(after.load(v));
  EXPECT_EQ(v, 11);
  save_whole(after, 33);
  ASSERT_TRUE(power_up(v));
  EXPECT_EQ(v, 33);
}

// Records of another format (another firmware's meaning of the value) are not read; the first
// save of this format then wins over them.
TEST_F(RecordRingTest, RecordsOfAnotherFormatAreNotRead) {
  OtherFormat other;
  int32_t v;
  other.load(v);
  for (int k = 0; k < 10; ++k) {
    other.save(777);
    for (int i = 0; i < 20; ++i) other.service();
  }
  EXPECT_FALSE(power_up(v));
  Ring r;
  EXPECT_FALSE(r.load(v));
  save_whole(r, 5);
  ASSERT_TRUE(power_up(v));
  EXPECT_EQ(v, 5);
}

// A bit flipped in the newest record: the one before wins; in every record: none
TEST_F(RecordRingTest, ACorruptRecordGivesWayToTheOneBefore) {
  Ring r;
  int32_t v;
  r.load(v);
  for (int k = 0; k < 5; ++k) save_whole(r, 100 + k);
  Eeprom::bytes[kBase + 4 * Ring::kRecordBytes + 3] ^= 0x10;  // slot 4 holds the newest
  ASSERT_TRUE(power_up(v));
  EXPECT_EQ(v, 103);
  for (int slot = 0; slot < 4; ++slot) Eeprom::bytes[kBase + slot * Ring::kRecordBytes] ^= 0x01;
  EXPECT_FALSE(power_up(v));
}

// A save while one is being written restarts it in the same slot: one slot per record, and the
// last value saved is the one kept
TEST_F(RecordRingTest, ASaveDuringAWriteRestartsItInTheSameSlot) {
  Ring r;
  int32_t v;
  r.load(v);
  save_whole(r, 1);
  r.save(2);
  r.service();
  r.service();
  r.save(3);
  for (int i = 0; i < 20; ++i) r.service();
  ASSERT_TRUE(power_up(v));
  EXPECT_EQ(v, 3);
  int slots_written = 0;
  for (int slot = 0; slot < kSlots; ++slot) slots_written += Eeprom::writes[kBase + slot * Ring::kRecordBytes] > 0;
  EXPECT_EQ(slots_written, 2);
}

// The wear: every cell of the ring takes one record in kSlots, nothing outside it is written,
// and a save writes only the bytes that change
TEST_F(RecordRingTest, SavesSpreadOverEverySlot) {
  Ring r;
  int32_t v;
  r.load(v);
  constexpr int kSaves = 10 * kSlots;
  for (int k = 0; k < kSaves; ++k) save_whole(r, k);
  uint32_t most = 0, total = 0;
  for (int a = 0; a < 4096; ++a) {
    if (a < kBase || a >= kBase + Ring::kBytes) {
      ASSERT_EQ(Eeprom::writes[a], 0u) << "outside the ring: " << a;
    }
    most = std::max(most, Eeprom::writes[a]);
    total += Eeprom::writes[a];
  }
  std::printf("%d saves: %u bytes written, at most %u writes a cell\n", kSaves, total, most);
  EXPECT_LE(most, (uint32_t)(kSaves / kSlots));
  EXPECT_LE(total, (uint32_t)kSaves * Ring::kRecordBytes);
}

}  // namespace
}  // namespace core
}  // namespace wmra
