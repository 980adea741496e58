// Runs the control scenarios of test/common/control_vectors.h on the ATmega2560 and prints
// their outputs; test_avr_control compares them with the host's, byte for byte.
#include "control_vectors.h"
#include "probe.h"

int main() {
  probe::ConsolePut put;
  wmra::control_vectors::emit_all(put);
  probe::finish();
}
