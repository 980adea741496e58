// Prints the fixed-point kinematics of the shared test vectors; test/avr/kinematics
// compares this output with the same code compiled for the host.
#include "kinematics_vectors.h"
#include "probe.h"

int main() {
  probe::ConsolePut put;
  wmra::vectors::emit_all(put);
  probe::print("END\n");
  probe::finish();
}
