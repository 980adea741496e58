// The joystick button (INT5, falling edges) and the safety button (INT4, any change): each
// handler counts; the main loop prints the counts and the pin levels when they change.
#include "board_io.h"

using namespace wmra;

namespace {
volatile uint8_t button_falls, estop_changes;
}

ISR(INT5_vect) { button_falls++; }
ISR(INT4_vect) { estop_changes++; }

int main() {
  io::input_pullup(board::kJoystickButton);
  io::input_pullup(board::kSafetyButton);
  EICRB = (1 << ISC51) | (1 << ISC40);  // INT5 falling, INT4 any change
  EIFR = (1 << INTF5) | (1 << INTF4);
  EIMSK = (1 << INT5) | (1 << INT4);
  sei();
  uint8_t last_b = 0xFF, last_e = 0xFF;
  for (;;) {
    const uint8_t b = button_falls, e = estop_changes;
    if (b != last_b || e != last_e) {
      last_b = b;
      last_e = e;
      probe::print("button ");
      probe::print_uint(b);
      probe::print(" estop ");
      probe::print_uint(e);
      probe::print(" levels ");
      probe::put(io::read(board::kJoystickButton) ? '1' : '0');
      probe::put(io::read(board::kSafetyButton) ? '1' : '0');
      probe::put('\n');
    }
  }
}
