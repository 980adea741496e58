#include "drivers/uart.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "wmra_mega/board.h"

namespace wmra {
namespace uart {

namespace {
static_assert((kRxBytes & (kRxBytes - 1)) == 0 && kTxBytes == 256, "ring sizes");
// U2X: 16 MHz / (8 (16 + 1)) = 117,647 baud, +2.1 % (what the Arduino core uses at 115200)
constexpr uint16_t kUbrr = (uint16_t)((board::kCpuHz / 4 / board::kSerialBaud - 1) / 2);
static_assert(kUbrr == 16, "115200 baud at 16 MHz with U2X");

volatile uint8_t g_rx[kRxBytes];
volatile uint8_t g_rx_head, g_rx_tail;
volatile uint8_t g_tx[kTxBytes];
volatile uint8_t g_tx_head, g_tx_tail;  // uint8 indices wrap at 256 by themselves
volatile uint16_t g_overruns;
}  // namespace

void start() {
  // U2X before UBRR: the chip does not care, but simavr 1.6 computes its baud rate when UBRR
  // is written and would otherwise run the line at half speed
  UCSR0A = (1 << U2X0);
  UBRR0 = kUbrr;
  UCSR0C = (1 << UCSZ01) | (1 << UCSZ00);  // 8N1
  UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
}

bool read(uint8_t& byte) {
  const uint8_t tail = g_rx_tail;
  if (tail == g_rx_head) return false;
  byte = g_rx[tail];
  g_rx_tail = (uint8_t)((tail + 1) & (kRxBytes - 1));
  return true;
}

bool write(const uint8_t* data, uint8_t count) {
  uint8_t head = g_tx_head;
  const uint8_t used = (uint8_t)(head - g_tx_tail);
  if ((uint16_t)used + count > kTxBytes - 1) return false;
  for (uint8_t i = 0; i < count; ++i) g_tx[head++] = data[i];
  g_tx_head = head;
  // read-modify-write racing the ISR's clear of UDRIE0 is harmless: the ISR runs once more
  UCSR0B |= (1 << UDRIE0);
  return true;
}

uint16_t rx_overruns() {
  const uint8_t s = SREG;
  cli();
  const uint16_t n = g_overruns;
  SREG = s;
  return n;
}

}  // namespace uart
}  // namespace wmra

using namespace wmra;

ISR(USART0_RX_vect) {
  const bool lost = UCSR0A & (1 << DOR0);  // the receiver dropped a byte before this one
  const uint8_t byte = UDR0;
  const uint8_t head = uart::g_rx_head;
  const uint8_t next = (uint8_t)((head + 1) & (uart::kRxBytes - 1));
  if (lost || next == uart::g_rx_tail) {
    if (uart::g_overruns != 0xFFFF) uart::g_overruns = uart::g_overruns + 1;
    if (next == uart::g_rx_tail) return;
  }
  uart::g_rx[head] = byte;
  uart::g_rx_head = next;
}

ISR(USART0_UDRE_vect) {
  const uint8_t tail = uart::g_tx_tail;
  if (tail == uart::g_tx_head) {
    UCSR0B &= (uint8_t)~(1 << UDRIE0);
    return;
  }
  UDR0 = uart::g_tx[tail];
  uart::g_tx_tail = (uint8_t)(tail + 1);
}
