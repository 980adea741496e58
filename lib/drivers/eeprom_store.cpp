#include "drivers/eeprom_store.h"

#include <avr/eeprom.h>

#include "protocol/frame.h"

namespace wmra {
namespace eeprom_store {

namespace {

constexpr uint8_t kMagic0 = 'W', kMagic1 = 'A';
constexpr uint16_t kHeaderBytes = 5;  // magic (2), version, size (2)

const uint8_t* g_data;
uint16_t g_size;
uint8_t g_header[kHeaderBytes];
uint8_t g_crc[2];
uint16_t g_next;  // next image byte to compare; g_size + header + crc = done
bool g_dirty;

uint16_t crc_of(const uint8_t* header, const uint8_t* data, uint16_t size) {
  uint16_t crc = 0xFFFF;
  for (uint16_t i = 0; i < kHeaderBytes; ++i) crc = protocol::crc16_update(crc, header[i]);
  for (uint16_t i = 0; i < size; ++i) crc = protocol::crc16_update(crc, data[i]);
  return crc;
}

void make_header(uint8_t* h, uint8_t version, uint16_t size) {
  h[0] = kMagic0;
  h[1] = kMagic1;
  h[2] = version;
  h[3] = (uint8_t)size;
  h[4] = (uint8_t)(size >> 8);
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
  uint8_t h[kHeaderBytes];
  eeprom_read_block(h, (const void*)0, kHeaderBytes);
  if (h[0] != kMagic0 || h[1] != kMagic1) return LoadResult::blank;
  uint8_t want[kHeaderBytes];
  make_header(want, version, size);
  for (uint8_t i = 2; i < kHeaderBytes; ++i)
    if (h[i] != want[i]) return LoadResult::other_version;
  eeprom_read_block(data, (const void*)kHeaderBytes, size);
  uint8_t crc[2];
  eeprom_read_block(crc, (const void*)(kHeaderBytes + size), 2);
  const uint16_t c = crc_of(h, (const uint8_t*)data, size);
  if (crc[0] != (uint8_t)c || crc[1] != (uint8_t)(c >> 8)) return LoadResult::bad_crc;
  return LoadResult::loaded;
}

void save(uint8_t version, const void* data, uint16_t size) {
  g_data = (const uint8_t*)data;
  g_size = size;
  make_header(g_header, version, size);
  g_next = 0;
  g_dirty = true;
}

namespace {
__attribute__((noinline)) void write_next() {
  if (!eeprom_is_ready()) return;
  if (g_next == 0) {  // (re)start: the CRC of the data as it is now
    const uint16_t c = crc_of(g_header, g_data, g_size);
    g_crc[0] = (uint8_t)c;
    g_crc[1] = (uint8_t)(c >> 8);
  }
  const uint16_t total = kHeaderBytes + g_size + 2;
  // skip bytes that already hold their value (a read is fast); write at most one
  while (g_next < total) {
    const uint8_t want = image_byte(g_next);
    uint8_t* address = (uint8_t*)g_next;
    ++g_next;
    if (eeprom_read_byte(address) != want) {
      eeprom_write_byte(address, want);
      return;
    }
  }
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
