// UART0 (the Mega's USB serial) at 115200 8N1 with interrupt-driven ring buffers: the control
// loop never waits for the line. A frame is queued whole or not at all, so a full buffer drops
// frames (counted), never bytes inside one.
#pragma once

#include <stdint.h>

namespace wmra {
namespace uart {

constexpr uint8_t kRxBytes = 64;  // ring sizes: powers of two (indices wrap with a mask)
constexpr uint16_t kTxBytes = 256;

void start();
bool read(uint8_t& byte);
bool received();  // a byte is waiting
// bytes the line has brought, those lost included, modulo 256: a change between two reads is a
// byte come in between (the link's measure of the line's silence, whether or not it has read
// what came: a partial frame waits for the line, not for the reader)
uint8_t arrived();
// false: no room (with keep_free bytes left free after it), nothing queued
bool write(const uint8_t* data, uint8_t count, uint8_t keep_free = 0);
uint16_t rx_overruns();  // bytes lost: ring full or the receiver's own overrun

}  // namespace uart
}  // namespace wmra
