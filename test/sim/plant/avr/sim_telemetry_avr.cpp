// The serial protocol (firmware/protocol) over UART0 at 115200, as the firmware will speak
// it, for armsim's decoder: a boot frame with MCUSR, then a state frame every 20 ms (Timer1);
// every command frame gets a reply with check_command's status, a valid mode or speed_scale
// command sets what the state frames report, and the parser's counters go out in them.
// Nothing moves: this image only talks.
#include "board_io.h"
#include "protocol/messages.h"
#include "protocol/parser.h"

namespace pr = wmra::protocol;

namespace {
volatile uint8_t rx[64];
volatile uint8_t head, tail;
uint8_t seq;

template <class Msg>
void send_message(const Msg& m) {
  uint8_t frame[pr::kMaxFrameBytes];
  const uint8_t n = pr::write_message(m, seq++, frame);
  for (uint8_t i = 0; i < n; ++i) io::uart0_send(frame[i]);
}
// the reply to a command, and what a valid mode or speed_scale sets
void answer(const pr::Frame& f, pr::StateMsg& state) {
  const pr::ReplyStatus status = pr::check_command(f);
  if (status == pr::ReplyStatus::ok && f.type == (uint8_t)pr::MsgType::cmd_mode) state.mode = f.payload[0];
  if (status == pr::ReplyStatus::ok && f.type == (uint8_t)pr::MsgType::cmd_speed_scale) state.speed_scale_pct = f.payload[0];
  if (status != pr::ReplyStatus::ok) ++state.rx_rejected;
  send_message(pr::ReplyMsg{f.type, f.seq, (uint8_t)status});
}
}  // namespace

ISR(USART0_RX_vect) { rx[head++ & 63] = UDR0; }

int main() {
  const uint8_t cause = MCUSR;
  MCUSR = 0;
  io::uart0_begin();
  TCCR1A = 0;
  OCR1A = 1249;                         // 20 ms at 16 MHz / 256
  TCCR1B = (1 << WGM12) | (1 << CS12);  // CTC, clk / 256
  send_message(pr::BootMsg{cause, (uint8_t)pr::Calibration::defaults_blank});
  sei();

  pr::Parser parser;
  pr::StateMsg state = {};
  state.reset_cause = cause;
  state.state = 4;  // running
  state.speed_scale_pct = 100;
  for (;;) {
    while (tail != head) {
      parser.push(rx[tail++ & 63]);
      while (parser.next()) answer(parser.frame(), state);
    }
    if (TIFR1 & (1 << OCF1A)) {
      TIFR1 = 1 << OCF1A;
      state.t_ms += 20;
      state.rx_crc_errors = parser.crc_errors();
      state.rx_framing_errors = parser.framing_errors();
      send_message(state);
    }
  }
}
