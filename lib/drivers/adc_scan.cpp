#include "drivers/adc_scan.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "drivers/isr_scratch.h"
#include "drivers/system_tick.h"

namespace wmra {
namespace adc {

namespace {
static_assert(kMaxChannels == 8, "snapshot's copy");
// One slot a channel in sweep order: its latest result, then the ADMUX of the channel after it
// (AVcc reference and channel; 0 after the last: the sweep is done). The ISR walks it with
// post-incremented loads and stores and tests the next ADMUX's REFS0 bit with sbrs, none of
// which touches SREG. Aligned within one 256-byte page: the slot pointer is one byte.
struct Slot {
  uint16_t count;
  uint8_t next_admux;
};
volatile Slot g_slots[kMaxChannels] __attribute__((aligned(32)));
static_assert(sizeof g_slots <= 32, "the slots within their alignment: one page");
uint8_t g_first_admux;
volatile uint8_t g_slot_lo;  // the low address byte of the slot of the conversion under way
// enabled, interrupt on, /128 (125 kHz): with ADSC, a conversion started
constexpr uint8_t kAdcsraOn = (1 << ADEN) | (1 << ADIE) | (1 << ADPS2) | (1 << ADPS1) | (1 << ADPS0);

inline uint8_t admux(uint8_t channel) { return (uint8_t)((1 << REFS0) | (channel & 7)); }
}  // namespace

void start(const uint8_t* channels, uint8_t count, uint16_t sweep_phase_us) {
  if (count > kMaxChannels) count = kMaxChannels;
  g_first_admux = admux(channels[0]);
  uint8_t analog = 0;
  for (uint8_t i = 0; i < count; ++i) {
    g_slots[i].next_admux = i + 1 < count ? admux(channels[i + 1]) : 0;
    analog |= (uint8_t)(1 << (channels[i] & 7));
  }
  // their digital input buffers off: a pot's mid-rail voltage on a Schmitt trigger draws current
  // and couples noise (datasheet 26.8.6, DIDR0)
  DIDR0 = analog;
  ADCSRB = 0;  // MUX5 = 0: ADC0..7, no auto trigger
  ADCSRA = kAdcsraOn;
  const uint8_t s = SREG;
  cli();
  // the first sweep now (the ADC is idle: ADIF clear)
  g_slot_lo = (uint8_t)(uintptr_t)&g_slots[0];
  ADMUX = g_first_admux;
  ADCSRA = kAdcsraOn | (1 << ADSC);
  SREG = s;
  tick::start_phase_compare(sweep_phase_us);
}

void snapshot(uint16_t* counts) {
  const uint8_t s = SREG;
  cli();
  // every slot, unrolled: a loop over the channels took ~160 cycles, these 32 moves 64
  counts[0] = g_slots[0].count;
  counts[1] = g_slots[1].count;
  counts[2] = g_slots[2].count;
  counts[3] = g_slots[3].count;
  counts[4] = g_slots[4].count;
  counts[5] = g_slots[5].count;
  counts[6] = g_slots[6].count;
  counts[7] = g_slots[7].count;
  SREG = s;
}

}  // namespace adc
}  // namespace wmra

using namespace wmra;

// Store the result, start the next channel; after the last, make the next sweep's first channel
// ready. Assembly without SREG (no instruction here changes it), three registers saved: in C
// the ISR saved eight (r0, r1, RAMPZ among them) and took 98 cycles; with an index and a
// compare, 66. Two of the three registers saved in the scratch registers (isr_scratch.h). It
// runs once a channel a tick.
ISR(ADC_vect, ISR_NAKED) {
  asm volatile(
      "out  %[scratch_a], r24\n\t"
      "out  %[scratch_b], r30\n\t"
      "push r31\n\t"
      "lds  r30, %[slot_lo]\n\t"
      "ldi  r31, hi8(%[slots])\n\t"
      "lds  r24, %[adcl]\n\t"  // ADCL first: it locks ADCH until ADCH is read
      "st   Z+, r24\n\t"
      "lds  r24, %[adch]\n\t"
      "st   Z+, r24\n\t"
      "ld   r24, Z+\n\t"
      "sbrs r24, %[refs0]\n\t"
      "rjmp 1f\n\t"
      "sts  %[admux_reg], r24\n\t"
      "ldi  r24, %[start]\n\t"
      "sts  %[adcsra], r24\n\t"
      "sts  %[slot_lo], r30\n\t"
      "pop  r31\n\t"
      "in   r30, %[scratch_b]\n\t"
      "in   r24, %[scratch_a]\n\t"
      "reti\n"
      "1:\n\t"
      "ldi  r30, lo8(%[slots])\n\t"
      "sts  %[slot_lo], r30\n\t"
      "lds  r24, %[first]\n\t"
      "sts  %[admux_reg], r24\n\t"
      "pop  r31\n\t"
      "in   r30, %[scratch_b]\n\t"
      "in   r24, %[scratch_a]\n\t"
      "reti"
      :
      : [slot_lo] "i"(&adc::g_slot_lo), [slots] "i"(adc::g_slots), [first] "i"(&adc::g_first_admux),
        [adcl] "n"(_SFR_MEM_ADDR(ADCL)), [adch] "n"(_SFR_MEM_ADDR(ADCH)), [admux_reg] "n"(_SFR_MEM_ADDR(ADMUX)),
        [adcsra] "n"(_SFR_MEM_ADDR(ADCSRA)), [refs0] "n"(REFS0), [start] "n"(adc::kAdcsraOn | (1 << ADSC)),
        [scratch_a] "n"(isr_scratch::kA_io), [scratch_b] "n"(isr_scratch::kB_io));
}

// The sweep's start, every tick at its phase (compare B, moved on by the tick's ISR): the first
// channel is selected already. Only with the ADC idle, neither converting nor holding a result
// its ISR has yet to store: a sweep still under way (impossible at one per tick: eight
// conversions take 832 us) is left to finish. Assembly without SREG (lds, sbrc, ldi, sts), one
// register saved, in a scratch register (isr_scratch.h): 24 cycles; with the compare's move
// and the first channel's select here, 55 (inside the iteration, which the sweep starts in).
ISR(TIMER1_COMPB_vect, ISR_NAKED) {
  asm volatile(
      "out  %[scratch_a], r24\n\t"
      "lds  r24, %[adcsra]\n\t"
      "sbrc r24, %[adsc]\n\t"
      "rjmp 1f\n\t"
      "sbrc r24, %[adif]\n\t"
      "rjmp 1f\n\t"
      "ldi  r24, %[start]\n\t"
      "sts  %[adcsra], r24\n"
      "1:\n\t"
      "in   r24, %[scratch_a]\n\t"
      "reti"
      :
      : [adcsra] "n"(_SFR_MEM_ADDR(ADCSRA)), [adsc] "n"(ADSC), [adif] "n"(ADIF),
        [start] "n"(adc::kAdcsraOn | (1 << ADSC)), [scratch_a] "n"(isr_scratch::kA_io));
}
