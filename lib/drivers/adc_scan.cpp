#include "drivers/adc_scan.h"

#include <avr/interrupt.h>
#include <avr/io.h>

namespace wmra {
namespace adc {

namespace {
uint8_t g_channels[kMaxChannels];
uint8_t g_count;
volatile uint8_t g_index;  // the channel being converted; g_count: the sweep is done
volatile uint16_t g_counts[kMaxChannels];

inline void select(uint8_t channel) { ADMUX = (uint8_t)((1 << REFS0) | (channel & 7)); }  // AVcc reference

// ADIF is clear here (no conversion pending), so the read-modify-write of ADCSRA clears nothing
inline void start_sweep() {
  g_index = 0;
  select(g_channels[0]);
  ADCSRA |= (1 << ADSC);
}
}  // namespace

void start(const uint8_t* channels, uint8_t count) {
  g_count = count > kMaxChannels ? kMaxChannels : count;
  for (uint8_t i = 0; i < g_count; ++i) g_channels[i] = channels[i];
  ADCSRB = 0;  // MUX5 = 0: ADC0..7
  // enable, interrupt, /128 (125 kHz), single conversions
  ADCSRA = (1 << ADEN) | (1 << ADIE) | (1 << ADPS2) | (1 << ADPS1) | (1 << ADPS0);
  start_sweep();
}

void snapshot(uint16_t* counts) {
  const uint8_t s = SREG;
  cli();
  for (uint8_t i = 0; i < g_count; ++i) counts[i] = g_counts[i];
  if (g_index >= g_count) start_sweep();
  SREG = s;
}

}  // namespace adc
}  // namespace wmra

using namespace wmra;

ISR(ADC_vect) {
  const uint8_t i = adc::g_index;
  adc::g_counts[i] = ADC;
  const uint8_t next = (uint8_t)(i + 1);
  adc::g_index = next;
  if (next < adc::g_count) {
    adc::select(adc::g_channels[next]);
    ADCSRA |= (1 << ADSC);
  }
}
