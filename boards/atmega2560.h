// Facts of the ATmega2560 shared by every board on it: data-space addresses of the ports and
// timers, and the vector table. The drivers (lib/drivers) turn a board's pins into register
// accesses with them; the simulator reads the firmware's registers from outside (avr->data[...])
// with the same numbers. (A board's pin map is in its own folder.) Plain C++14.
#pragma once

#include <stdint.h>

#include "wmra_mega/board.h"

namespace wmra {
namespace m2560 {

constexpr uint16_t kRamStart = 0x200;
constexpr uint16_t kRamEnd = 0x21FF;
constexpr uint16_t kSpl = 0x5D, kSph = 0x5E;
constexpr uint16_t kMcusr = 0x54;
constexpr uint16_t kUcsr0b = 0xC1;  // RXEN0 is bit 4
constexpr int kVectors = 57;
constexpr int kVectorBytes = 4;  // JMP per vector
// the hardware's interrupt response (push of the 3-byte PC, clear I, jump to the vector)
constexpr int kInterruptResponseCycles = 5;
constexpr uint16_t kReti = 0x9518;

// PINx; DDRx = PINx + 1; PORTx = PINx + 2
constexpr uint16_t pin_register(board::Port p) {
  return p <= board::Port::G ? (uint16_t)(0x20 + 3 * (int)p) : (uint16_t)(0x100 + 3 * ((int)p - (int)board::Port::H));
}
constexpr uint16_t ddr_register(board::Port p) { return pin_register(p) + 1; }
constexpr uint16_t port_register(board::Port p) { return pin_register(p) + 2; }
constexpr char port_letter(board::Port p) { return "ABCDEFGHJKL"[(int)p]; }
static_assert(pin_register(board::Port::G) == 0x32 && pin_register(board::Port::L) == 0x109, "port addresses");

// Timer registers. 8-bit timers (0, 2) have no ICR and no channel C; their WGM2 is TCCRnB bit 3.
struct TimerRegisters {
  uint16_t tccra, tccrb, tccrc, tcnt, icr;  // 0 = absent; 16-bit values: low byte address
  uint16_t ocr[3];
  bool sixteen_bit;
};
constexpr TimerRegisters kTimers[6] = {
    {0x44, 0x45, 0, 0x46, 0, {0x47, 0x48, 0}, false},
    {0x80, 0x81, 0x82, 0x84, 0x86, {0x88, 0x8A, 0x8C}, true},
    {0xB0, 0xB1, 0, 0xB2, 0, {0xB3, 0xB4, 0}, false},
    {0x90, 0x91, 0x92, 0x94, 0x96, {0x98, 0x9A, 0x9C}, true},
    {0xA0, 0xA1, 0xA2, 0xA4, 0xA6, {0xA8, 0xAA, 0xAC}, true},
    {0x120, 0x121, 0x122, 0x124, 0x126, {0x128, 0x12A, 0x12C}, true},
};
constexpr const TimerRegisters& timer_registers(board::Timer t) { return kTimers[(int)t]; }
// COMnx1:0 in TCCRnA: bits 7:6 (A), 5:4 (B), 3:2 (C); FOCnx in TCCRnC (16-bit) bits 7, 6, 5
constexpr int com_shift(board::Channel c) { return 6 - 2 * (int)c; }

constexpr const char* kVectorNames[kVectors] = {
    "RESET",        "INT0",         "INT1",         "INT2",         "INT3",         "INT4",
    "INT5",         "INT6",         "INT7",         "PCINT0",       "PCINT1",       "PCINT2",
    "WDT",          "TIMER2_COMPA", "TIMER2_COMPB", "TIMER2_OVF",   "TIMER1_CAPT",  "TIMER1_COMPA",
    "TIMER1_COMPB", "TIMER1_COMPC", "TIMER1_OVF",   "TIMER0_COMPA", "TIMER0_COMPB", "TIMER0_OVF",
    "SPI_STC",      "USART0_RX",    "USART0_UDRE",  "USART0_TX",    "ANALOG_COMP",  "ADC",
    "EE_READY",     "TIMER3_CAPT",  "TIMER3_COMPA", "TIMER3_COMPB", "TIMER3_COMPC", "TIMER3_OVF",
    "USART1_RX",    "USART1_UDRE",  "USART1_TX",    "TWI",          "SPM_READY",    "TIMER4_CAPT",
    "TIMER4_COMPA", "TIMER4_COMPB", "TIMER4_COMPC", "TIMER4_OVF",   "TIMER5_CAPT",  "TIMER5_COMPA",
    "TIMER5_COMPB", "TIMER5_COMPC", "TIMER5_OVF",   "USART2_RX",    "USART2_UDRE",  "USART2_TX",
    "USART3_RX",    "USART3_UDRE",  "USART3_TX",
};

}  // namespace m2560
}  // namespace wmra
