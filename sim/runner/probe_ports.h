// I/O ports that an AVR program under simulation uses to talk to the simavr runner.
// They are general-purpose I/O registers, so the same image runs unchanged on the board.
//   GPIOR0: console, one byte per write
//   GPIOR1: start of a timed region, value = region id (1..255)
//   GPIOR2: end of a timed region, value = region id
// The runner, not the program, reads the cycle counter, so timing has no cost inside
// the measured region beyond the OUT instruction.
#pragma once

#define WMRA_PROBE_CONSOLE_IO 0x1E
#define WMRA_PROBE_START_IO 0x2A
#define WMRA_PROBE_STOP_IO 0x2B
#define WMRA_PROBE_DATA_OFFSET 0x20  // data-space address = I/O address + 0x20
