// Two registers the assembly ISRs save working registers in: GPIOR1 and GPIOR2, general-purpose
// I/O registers, written with OUT and read back with IN (one cycle each, against two for PUSH
// and POP). Safe because no ISR nests (none enables interrupts) and nothing else uses them
// (GPIOR0 is the simulator's console; sim/runner/probe_ports.h's timed regions on GPIOR1/2 are
// for the bench images under avr-run, never the firmware).
#pragma once

#include <avr/io.h>

namespace wmra {
namespace isr_scratch {

constexpr uint8_t kA_io = _SFR_IO_ADDR(GPIOR1);
constexpr uint8_t kB_io = _SFR_IO_ADDR(GPIOR2);

}  // namespace isr_scratch
}  // namespace wmra
