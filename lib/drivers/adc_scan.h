// Background scan of the analog inputs: the ADC interrupt stores each result and starts the
// next channel, so the control loop only copies the latest values (no blocking conversion).
// At a 125 kHz ADC clock a conversion takes 104 us: five channels are all fresh every 520 us,
// twice per control tick.
#pragma once

#include <stdint.h>

namespace wmra {
namespace adc {

constexpr uint8_t kMaxChannels = 8;

// channels: ADC0..7 numbers, scanned in this order; results are read by index in the same order
void start(const uint8_t* channels, uint8_t count);
// copies the latest result of every channel (10-bit counts), atomically
void snapshot(uint16_t* counts);

}  // namespace adc
}  // namespace wmra
