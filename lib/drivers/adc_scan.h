// Scan of the analog inputs, one sweep per control tick, started at a fixed phase of the tick
// by Timer1's compare B (the system tick's timer): its conversions the ADC interrupt chains
// (store, next channel) and stops after the last channel, so the loop never waits on a
// conversion, and snapshot() hands the loop the latest results. At a 125 kHz ADC clock a
// conversion takes 104 us: the phase sets how old each reading is when the next tick reads it.
// Why not started by the loop: its readings would be as old as the loop is long (the DC joints'
// feedback wants them fresh: a sweep from the loop's start converted each pot twice, the second
// for freshness, three conversions a tick for nothing). Why not free-running: converting all the
// time (~9 kHz) cost ~1,100 cycles of interrupts per 1 ms tick, for results the loop never read.
#pragma once

#include <stdint.h>

namespace wmra {
namespace adc {

constexpr uint8_t kMaxChannels = 8;

// channels: ADC0..7 numbers (count >= 1), converted in this order; results are read by index in the same
// order. Starts a first sweep now, then one every tick at sweep_phase_us after the system
// tick's compare (tick::start() first: Timer1 runs).
void start(const uint8_t* channels, uint8_t count, uint16_t sweep_phase_us);
// copies the latest result of every channel (10-bit counts) into counts[0..kMaxChannels)
// (slots past the channels given to start() are 0), atomically
void snapshot(uint16_t* counts);

}  // namespace adc
}  // namespace wmra
