#include "drivers/adc_scan.h"

#include <avr/interrupt.h>
#include <avr/io.h>

namespace wmra {
namespace adc {

namespace {
uint8_t g_channels[kMaxChannels];
uint8_t g_count;
uint8_t g_index;
volatile uint16_t g_counts[kMaxChannels];

inline void select(uint8_t channel) { ADMUX = (uint8_t)((1 << REFS0) | (channel & 7)); }  // AVcc reference
}  // namespace

void start(const uint8_t* channels, uint8_t count) {
  g_count = count > kMaxChannels ? kMaxChannels : count;
  for (uint8_t i = 0; i < g_count; ++i) g_channels[i] = channels[i];
  g_index = 0;
  ADCSRB = 0;  // MUX5 = 0: ADC0..7
  select(g_channels[0]);
  // enable, interrupt, /128 (125 kHz), start the first conversion
  ADCSRA = (1 << ADEN) | (1 << ADIE) | (1 << ADPS2) | (1 << ADPS1) | (1 << ADPS0) | (1 << ADSC);
}

void snapshot(uint16_t* counts) {
  const uint8_t s = SREG;
  cli();
  for (uint8_t i = 0; i < g_count; ++i) counts[i] = g_counts[i];
  SREG = s;
}

}  // namespace adc
}  // namespace wmra

using namespace wmra;

ISR(ADC_vect) {
  adc::g_counts[adc::g_index] = ADC;
  uint8_t next = (uint8_t)(adc::g_index + 1);
  if (next >= adc::g_count) next = 0;
  adc::g_index = next;
  adc::select(adc::g_channels[next]);
  ADCSRA |= (1 << ADSC);
}
