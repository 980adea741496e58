// The serial protocol on the ATmega2560: prints the text of test/common/protocol_vectors.h,
// which test_avr_protocol compares with the host's byte for byte, then times the calls the
// firmware makes (avr-run measures the regions; region 1 is the empty one it subtracts).
#include "probe.h"
#include "protocol_vectors.h"

using namespace wmra::protocol;

namespace {

enum Region : uint8_t { kEmpty = 1, kWriteState, kParseState, kDecodeState, kCheckCommand };

// globals and volatile inputs, so that nothing timed can be folded at compile time
volatile uint32_t in_t_ms = 1000;
volatile uint8_t sink;
StateMsg state;
StateMsg decoded;
Frame command;
uint8_t frame[kMaxFrameBytes];
Parser parser;

}  // namespace

int main() {
  probe::ConsolePut put;
  wmra::protocol_vectors::emit_all(put);

  probe::name_region(kEmpty, "empty");
  probe::name_region(kWriteState, "write_state_frame");
  probe::name_region(kParseState, "parse_state_frame");
  probe::name_region(kDecodeState, "decode_state");
  probe::name_region(kCheckCommand, "check_command");
  state = wmra::protocol_vectors::sample_state();
  command.type = (uint8_t)MsgType::cmd_speed_scale;
  command.len = 1;
  for (uint8_t k = 0; k < 8; ++k) {
    state.t_ms = in_t_ms;
    command.payload[0] = (uint8_t)(in_t_ms + k);
    probe::start(kEmpty);
    probe::stop(kEmpty);
    probe::start(kWriteState);
    const uint8_t n = write_message(state, k, frame);
    probe::stop(kWriteState);
    uint8_t frames = 0;
    probe::start(kParseState);
    for (uint8_t i = 0; i < n; ++i) frames = (uint8_t)(frames + parser.feed(frame[i]));  // as the firmware reads
    probe::stop(kParseState);
    probe::start(kDecodeState);
    const bool ok = decode(parser.frame(), decoded);
    probe::stop(kDecodeState);
    probe::start(kCheckCommand);
    const ReplyStatus status = check_command(command);
    probe::stop(kCheckCommand);
    sink = (uint8_t)(frames + ok + (uint8_t)status + (uint8_t)decoded.t_ms);
  }
  probe::finish();
}
