// Scan of the analog inputs, one sweep per control tick: snapshot() hands the loop the last
// sweep's results and starts the next sweep, whose conversions the ADC interrupt chains
// (store, next channel) and stops after the last channel, so the loop never waits on a
// conversion. At a 125 kHz ADC clock a conversion takes 104 us: up to eight channels (a channel
// may be listed twice, converted twice) are converted within 832 us of the snapshot, before
// the next tick reads them. Why not free-running: converting all the time (~9 kHz) cost ~1,100
// cycles of interrupts per 1 ms tick, for results the loop never read.
#pragma once

#include <stdint.h>

namespace wmra {
namespace adc {

constexpr uint8_t kMaxChannels = 8;

// channels: ADC0..7 numbers, converted in this order; results are read by index in the same
// order. Starts the first sweep.
void start(const uint8_t* channels, uint8_t count);
// copies the latest result of every channel (10-bit counts) into counts[0..kMaxChannels)
// (slots past the channels given to start() are 0), atomically, and starts the next sweep
// (unless the last one is still converting: it goes on, and its results come next)
void snapshot(uint16_t* counts);

}  // namespace adc
}  // namespace wmra
