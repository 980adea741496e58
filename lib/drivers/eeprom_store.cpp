#include "drivers/eeprom_store.h"

#include <avr/eeprom.h>

#include "protocol/frame.h"

namespace wmra {
namespace eeprom_store {

static_assert(eeprom_map::kBytes == E2END + 1, "the map is the chip's EEPROM");

namespace {

constexpr uint8_t kMagic0 = 'W', kMagic1 = 'B';
constexpr uint8_t kLegacyMagic1 = 'A';     // the single block before the copies, at address 0
constexpr uint8_t kLegacyHeaderBytes = 5;  // magic (2), version, size (2): no generation

const uint8_t* g_data;
uint16_t g_size;
uint8_t g_header[kHeaderBytes];
uint8_t g_crc[2];
uint16_t g_next;  // next image byte to compare; header + g_size + crc = done
bool g_dirty;
uint8_t g_valid_copy;        // holds the newest valid block (none: 1, so the first save writes copy 0)
uint8_t g_valid_generation;  // its generation
uint8_t g_target_copy;       // the copy being written

uint16_t copy_address(uint8_t copy) { return copy ? eeprom_map::kSettingsCopy[1] : eeprom_map::kSettingsCopy[0]; }

__attribute__((noinline)) uint16_t crc_of(const uint8_t* header, uint8_t header_bytes, const uint8_t* data, uint16_t size) {
  uint16_t crc = protocol::crc16_update(0xFFFF, header, header_bytes);
  for (uint16_t i = 0; i < size; ++i) crc = protocol::crc16_update(crc, data[i]);
  return crc;
}

// Reads the block at address (header_bytes of header, magic1 its second byte) into h and data:
// loaded when its version, size and CRC hold
LoadResult read_block(uint16_t address, uint8_t magic1, uint8_t header_bytes, uint8_t* h, uint8_t version, void* data,
                      uint16_t size) {
  eeprom_read_block(h, (const void*)address, header_bytes);
  if (h[0] != kMagic0 || h[1] != magic1) return LoadResult::blank;
  if (h[2] != version || h[3] != (uint8_t)size || h[4] != (uint8_t)(size >> 8)) return LoadResult::other_version;
  address += header_bytes;
  eeprom_read_block(data, (const void*)address, size);
  if (eeprom_read_word((const uint16_t*)(address + size)) != crc_of(h, header_bytes, (const uint8_t*)data, size))
    return LoadResult::bad_crc;
  return LoadResult::loaded;
}

// byte i of the image: header, data, crc
uint8_t image_byte(uint16_t i) {
  if (i < kHeaderBytes) return g_header[i];
  i -= kHeaderBytes;
  if (i < g_size) return g_data[i];
  return g_crc[i - g_size];
}

}  // namespace

LoadResult load(uint8_t version, void* data, uint16_t size) {
  // anything but loaded: the most telling of the blocks' results (another version: the caller
  // may migrate it)
  LoadResult result = LoadResult::blank;
  uint8_t h[kHeaderBytes];
  bool found = false;
  for (uint8_t c = 0; c < 2; ++c) {
    const LoadResult r = read_block(copy_address(c), kMagic1, kHeaderBytes, h, version, data, size);
    if (r > result) result = r;
    // the generation wraps: the newer is less than 128 ahead
    if (r == LoadResult::loaded && (!found || (int8_t)(h[kHeaderBytes - 1] - g_valid_generation) > 0)) {
      found = true;
      g_valid_copy = c;
      g_valid_generation = h[kHeaderBytes - 1];
    }
  }
  if (found) {
    eeprom_read_block(data, (const void*)(copy_address(g_valid_copy) + kHeaderBytes), size);
    return LoadResult::loaded;
  }
  // the single block of before, as copy 0 of generation 0
  const LoadResult r = read_block(0, kLegacyMagic1, kLegacyHeaderBytes, h, version, data, size);
  g_valid_generation = 0;
  g_valid_copy = r == LoadResult::loaded ? 0 : 1;
  return r == LoadResult::loaded || r > result ? r : result;
}

void save(uint8_t version, const void* data, uint16_t size) {
  if (!g_dirty) g_target_copy = (uint8_t)(1 - g_valid_copy);
  g_data = (const uint8_t*)data;
  g_size = size;
  g_header[0] = kMagic0;
  g_header[1] = kMagic1;
  g_header[2] = version;
  g_header[3] = (uint8_t)size;
  g_header[4] = (uint8_t)(size >> 8);
  g_header[5] = (uint8_t)(g_valid_generation + 1);
  g_next = 0;
  g_dirty = true;
}

namespace {
__attribute__((noinline)) void write_next() {
  if (!eeprom_is_ready()) return;
  if (g_next == 0) {  // (re)start: the CRC of the data as it is now
    const uint16_t c = crc_of(g_header, kHeaderBytes, g_data, g_size);
    g_crc[0] = (uint8_t)c;
    g_crc[1] = (uint8_t)(c >> 8);
  }
  const uint16_t total = kHeaderBytes + g_size + 2;
  const uint16_t base = copy_address(g_target_copy);
  // skip bytes that already hold their value (a read is fast); write at most one. The
  // generation (in the header) changes first and the CRC last: the copy fails its check from
  // its first byte written to its last.
  while (g_next < total) {
    const uint8_t want = image_byte(g_next);
    uint8_t* address = (uint8_t*)(base + g_next);
    ++g_next;
    if (eeprom_read_byte(address) != want) {
      eeprom_write_byte(address, want);
      return;
    }
  }
  g_valid_copy = g_target_copy;
  g_valid_generation = g_header[kHeaderBytes - 1];
  g_dirty = false;
}
}  // namespace

// every tick: the registers write_next() needs are saved only while a write is pending
void service() {
  if (g_dirty) write_next();
}

bool busy() { return g_dirty; }

}  // namespace eeprom_store
}  // namespace wmra
