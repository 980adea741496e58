#include "drivers/uart.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "drivers/isr_scratch.h"
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
volatile uint8_t g_arrived;
// Page-aligned: the ISR's index is the low byte of the byte's address (no add, no carry). In
// .data, whose largest alignment the link puts first (firmware/CMakeLists.txt): at the start of
// RAM, 0x200, a page; in .bss it sat at the first page after .data, the bytes before it unused
// (168 B with J6's homing; static RAM 3,197 -> 3,037 B, its 256 zeros copied from flash at boot).
volatile uint8_t g_tx[kTxBytes] __attribute__((aligned(256), section(".data")));
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

bool received() { return g_rx_tail != g_rx_head; }

uint8_t arrived() { return g_arrived; }

bool write(const uint8_t* data, uint8_t count, uint8_t keep_free) {
  uint8_t head = g_tx_head;
  const uint8_t used = (uint8_t)(head - g_tx_tail);
  if ((uint16_t)used + count + keep_free > kTxBytes - 1) return false;
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
  uart::g_arrived = (uint8_t)(uart::g_arrived + 1);
  const uint8_t head = uart::g_rx_head;
  const uint8_t next = (uint8_t)((head + 1) & (uart::kRxBytes - 1));
  if (lost || next == uart::g_rx_tail) {
    if (uart::g_overruns != 0xFFFF) uart::g_overruns = uart::g_overruns + 1;
    if (next == uart::g_rx_tail) return;
  }
  uart::g_rx[head] = byte;
  uart::g_rx_head = next;
}

// One byte out of the ring, or the interrupt off when it is empty. Assembly, three registers
// saved (two in the scratch registers, isr_scratch.h): in C it saved eight (r0, r1, RAMPZ among
// them) and took 67 cycles, for every byte of telemetry. A byte sent changes no flag (cpse
// compares without them, ld Z+ moves the tail on, wrapping at 256 with the ring's page), so
// only the empty ring's path saves SREG: 36 cycles a byte (with an index add, a compare and
// every save a push, 50).
ISR(USART0_UDRE_vect, ISR_NAKED) {
  asm volatile(
      "out  %[scratch_a], r24\n\t"
      "out  %[scratch_b], r30\n\t"
      "push r31\n\t"
      "lds  r30, %[tail]\n\t"
      "lds  r24, %[head]\n\t"
      "cpse r30, r24\n\t"
      "rjmp 1f\n\t"
      "in   r31, __SREG__\n\t"
      "lds  r24, %[ucsrb]\n\t"
      "andi r24, %[udrie_off]\n\t"
      "sts  %[ucsrb], r24\n\t"
      "out  __SREG__, r31\n\t"
      "rjmp 2f\n"
      "1:\n\t"
      "ldi  r31, hi8(%[tx])\n\t"
      "ld   r24, Z+\n\t"
      "sts  %[udr], r24\n\t"
      "sts  %[tail], r30\n"
      "2:\n\t"
      "pop  r31\n\t"
      "in   r30, %[scratch_b]\n\t"
      "in   r24, %[scratch_a]\n\t"
      "reti"
      :
      : [tail] "i"(&uart::g_tx_tail), [head] "i"(&uart::g_tx_head), [tx] "i"(uart::g_tx), [udr] "n"(_SFR_MEM_ADDR(UDR0)),
        [ucsrb] "n"(_SFR_MEM_ADDR(UCSR0B)), [udrie_off] "n"((uint8_t) ~(1 << UDRIE0)),
        [scratch_a] "n"(isr_scratch::kA_io), [scratch_b] "n"(isr_scratch::kB_io));
}
