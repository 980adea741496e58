#include "drivers/adc_scan.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "drivers/system_tick.h"

namespace wmra {
namespace adc {

namespace {
// Aligned so that the ISR indexes them with an 8-bit add (no carry into the high byte)
static_assert(kMaxChannels == 8, "the alignments below and snapshot's copy");
uint8_t g_admux[kMaxChannels] __attribute__((aligned(8)));  // ADMUX of each channel: AVcc reference, channel
uint8_t g_count;
volatile uint8_t g_index;  // the channel being converted; g_count: the sweep is done
volatile uint16_t g_counts[kMaxChannels] __attribute__((aligned(16)));

// ADIF is clear here (no conversion pending), so the read-modify-write of ADCSRA clears nothing
inline void start_sweep() {
  g_index = 0;
  ADMUX = g_admux[0];
  ADCSRA |= (1 << ADSC);
}
}  // namespace

void start(const uint8_t* channels, uint8_t count, uint16_t sweep_phase_us) {
  g_count = count > kMaxChannels ? kMaxChannels : count;
  for (uint8_t i = 0; i < g_count; ++i) g_admux[i] = (uint8_t)((1 << REFS0) | (channels[i] & 7));
  ADCSRB = 0;  // MUX5 = 0: ADC0..7
  // enable, interrupt, /128 (125 kHz), single conversions
  ADCSRA = (1 << ADEN) | (1 << ADIE) | (1 << ADPS2) | (1 << ADPS1) | (1 << ADPS0);
  const uint8_t s = SREG;
  cli();
  start_sweep();
  // compare A holds the next tick's count (system_tick.cpp): compare B follows it by the phase
  OCR1B = (uint16_t)(OCR1A + sweep_phase_us * tick::kCountsPerUs);
  TIFR1 = (1 << OCF1B);
  TIMSK1 |= (1 << OCIE1B);
  SREG = s;
}

void snapshot(uint16_t* counts) {
  const uint8_t s = SREG;
  cli();
  // every slot, unrolled: the loop over g_count took ~160 cycles, these 32 moves 64
  counts[0] = g_counts[0];
  counts[1] = g_counts[1];
  counts[2] = g_counts[2];
  counts[3] = g_counts[3];
  counts[4] = g_counts[4];
  counts[5] = g_counts[5];
  counts[6] = g_counts[6];
  counts[7] = g_counts[7];
  SREG = s;
}

}  // namespace adc
}  // namespace wmra

using namespace wmra;

// Store the result, start the next channel unless the sweep is done. Assembly, four registers
// saved: in C the ISR saved eight (r0, r1, RAMPZ among them) and took 98 cycles; it runs eight
// times a tick.
ISR(ADC_vect, ISR_NAKED) {
  asm volatile(
      "push r24\n\t"
      "in   r24, __SREG__\n\t"
      "push r24\n\t"
      "push r25\n\t"
      "push r30\n\t"
      "push r31\n\t"
      "lds  r24, %[index]\n\t"
      "mov  r30, r24\n\t"
      "lsl  r30\n\t"
      "subi r30, lo8(-(%[counts]))\n\t"  // aligned: no carry into the high byte
      "ldi  r31, hi8(%[counts])\n\t"
      "lds  r25, %[adcl]\n\t"  // ADCL first: it locks ADCH until ADCH is read
      "st   Z+, r25\n\t"
      "lds  r25, %[adch]\n\t"
      "st   Z, r25\n\t"
      "inc  r24\n\t"
      "sts  %[index], r24\n\t"
      "lds  r25, %[count]\n\t"
      "cp   r24, r25\n\t"
      "brsh 1f\n\t"
      "mov  r30, r24\n\t"
      "subi r30, lo8(-(%[admux]))\n\t"
      "ldi  r31, hi8(%[admux])\n\t"
      "ld   r25, Z\n\t"
      "sts  %[admux_reg], r25\n\t"
      "lds  r25, %[adcsra]\n\t"
      "ori  r25, %[adsc]\n\t"
      "sts  %[adcsra], r25\n"
      "1:\n\t"
      "pop  r31\n\t"
      "pop  r30\n\t"
      "pop  r25\n\t"
      "pop  r24\n\t"
      "out  __SREG__, r24\n\t"
      "pop  r24\n\t"
      "reti"
      :
      : [index] "i"(&adc::g_index), [counts] "i"(adc::g_counts), [count] "i"(&adc::g_count), [admux] "i"(adc::g_admux),
        [adcl] "n"(_SFR_MEM_ADDR(ADCL)), [adch] "n"(_SFR_MEM_ADDR(ADCH)), [admux_reg] "n"(_SFR_MEM_ADDR(ADMUX)),
        [adcsra] "n"(_SFR_MEM_ADDR(ADCSRA)), [adsc] "n"(1 << ADSC));
}

// The sweep's start, every tick at its phase: compare B moved on by a tick, the first channel
// selected and converted. Assembly like the ADC's, three registers saved (in C: ~45 cycles).
// A sweep still converting (impossible at one per tick: eight conversions take 832 us) is
// left to finish.
static_assert(tick::kTickCounts == 2000, "the asm below adds 2000 to OCR1B");
ISR(TIMER1_COMPB_vect, ISR_NAKED) {
  asm volatile(
      "push r24\n\t"
      "in   r24, __SREG__\n\t"
      "push r24\n\t"
      "push r25\n\t"
      "lds  r24, %[ocrl]\n\t"  // the low byte first: it latches the high byte's TEMP
      "lds  r25, %[ocrh]\n\t"
      "subi r24, lo8(-2000)\n\t"
      "sbci r25, hi8(-2000)\n\t"
      "sts  %[ocrh], r25\n\t"  // the high byte first: written through TEMP with the low one
      "sts  %[ocrl], r24\n\t"
      "lds  r24, %[index]\n\t"
      "lds  r25, %[count]\n\t"
      "cp   r24, r25\n\t"
      "brlo 1f\n\t"
      "clr  r25\n\t"  // (not __zero_reg__: r1 may hold a product's high byte here)
      "sts  %[index], r25\n\t"
      "lds  r24, %[admux]\n\t"
      "sts  %[admux_reg], r24\n\t"
      "lds  r24, %[adcsra]\n\t"
      "ori  r24, %[adsc]\n\t"
      "sts  %[adcsra], r24\n"
      "1:\n\t"
      "pop  r25\n\t"
      "pop  r24\n\t"
      "out  __SREG__, r24\n\t"
      "pop  r24\n\t"
      "reti"
      :
      : [index] "i"(&adc::g_index), [count] "i"(&adc::g_count), [admux] "i"(adc::g_admux),
        [ocrl] "n"(_SFR_MEM_ADDR(OCR1BL)), [ocrh] "n"(_SFR_MEM_ADDR(OCR1BH)), [admux_reg] "n"(_SFR_MEM_ADDR(ADMUX)),
        [adcsra] "n"(_SFR_MEM_ADDR(ADCSRA)), [adsc] "n"(1 << ADSC));
}
