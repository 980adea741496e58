// The link's receive budget (config::kMaxRxBytesPerTick, kMaxRxStepsPerTick) against floods of
// broken frames, on a model of link::receive: the line at the board's baud rate into the UART's
// receive ring (bytes beyond it lost, as uart.cpp's ISR loses them), and each 1 ms tick's read
// as link.cpp makes it: the silence first, then the parser's steps. Whether the parser keeps up
// with a flood, what it loses, and when a stop sent after it is taken. (The firmware itself on
// the virtual arm: test_link_scenarios.)
#include <gtest/gtest.h>

#include <cstdio>
#include <deque>
#include <random>
#include <vector>

#include "config/control_config.h"
#include "drivers/uart.h"
#include "protocol/messages.h"
#include "protocol/parser.h"
#include "wmra_mega/board.h"

using namespace wmra;

namespace {

constexpr double kByte_ms = 10.0 * 1000 / board::kSerialBaud;  // 8N1

struct FloodResult {
  double stop_ms = -1;  // from the stop's last byte to the iteration after the read that took it; -1: never
  long lost_bytes = 0;  // the receive ring full
  double steps_per_byte = 0;  // the parser's steps while the flood came, a byte of it
};

// `pattern` repeated for flood_ms, then (after gap_ms of silence) a stop frame.
FloodResult flood_then_stop(const std::vector<uint8_t>& pattern, double flood_ms, double gap_ms) {
  std::vector<uint8_t> line;
  while (line.size() * kByte_ms < flood_ms) line.insert(line.end(), pattern.begin(), pattern.end());
  const size_t flood_bytes = line.size();
  uint8_t stop[protocol::kMaxFrameBytes];
  const uint8_t n_stop = protocol::write_frame((uint8_t)protocol::MsgType::cmd_stop, 9, nullptr, 0, stop);
  line.insert(line.end(), stop, stop + n_stop);
  const auto arrival_ms = [&](size_t i) { return i * kByte_ms + (i >= flood_bytes ? gap_ms : 0); };

  FloodResult r;
  protocol::Parser parser;
  std::deque<uint8_t> ring;
  size_t sent = 0;
  long steps = 0;
  // the link reads half a tick in (after the iteration)
  uint8_t quiet_ms = 0;  // whole ticks without a byte, as link.cpp counts them
  for (int tick = 0; tick < 1000 && r.stop_ms < 0; ++tick) {
    const double read_ms = tick + 0.5;
    const size_t sent_before = sent;
    while (sent < line.size() && arrival_ms(sent) <= read_ms) {
      if (ring.size() < uart::kRxBytes - 1u)
        ring.push_back(line[sent]);
      else
        ++r.lost_bytes;
      ++sent;
    }
    quiet_ms = sent != sent_before ? 0 : (uint8_t)(quiet_ms < 255 ? quiet_ms + 1 : 255);
    if (ring.empty()) parser.line_quiet(quiet_ms);
    uint8_t bytes = config::kMaxRxBytesPerTick;
    for (uint8_t n = config::kMaxRxStepsPerTick; n > 0; --n) {
      bool complete;
      if (parser.caught_up()) {
        if (bytes == 0 || ring.empty()) break;
        --bytes;
        complete = parser.feed(ring.front());
        ring.pop_front();
      } else {
        complete = parser.step();
      }
      if (sent <= flood_bytes) ++steps;
      if (complete && parser.frame().type == (uint8_t)protocol::MsgType::cmd_stop)
        r.stop_ms = tick + 1 - arrival_ms(line.size() - 1);
    }
  }
  r.steps_per_byte = (double)steps / flood_bytes;
  return r;
}

std::vector<uint8_t> bytes_of(const char* hex) {
  std::vector<uint8_t> out;
  for (const char* c = hex; c[0] && c[1]; c += 2) out.push_back((uint8_t)std::stoul(std::string(c, 2), nullptr, 16));
  return out;
}

}  // namespace

// Floods of 100 ms, a stop at once after each and one after 50 ms of silence. Random bytes, a
// frame cut short, repeated, and frames that say 64 bytes and bring 14 are read as they come,
// nothing lost: the stop is obeyed within 10 ms. (The last needs 43 steps a tick: with
// 32, as many steps as bytes, 132 bytes were lost.) A flood made for the rescan (the worst of
// a search over short patterns) outruns the budget by far, and the stop sent straight after it
// is lost with its bytes. After any of them, once the line has been quiet a while, a stop is
// obeyed at once: nothing wedges the link.
TEST(ParserBudget, FloodsOfBrokenFramesThenAStop) {
  std::mt19937 rng(30u);
  std::vector<uint8_t> noise(2000);
  for (uint8_t& b : noise) b = (uint8_t)rng();
  const std::vector<uint8_t> half = bytes_of("a50317050c320000");  // a velocity command cut after 3 of 12
  const std::vector<uint8_t> says_64 = bytes_of("a503170540000102030405060708090a0b0c0d");
  const std::vector<uint8_t> made = bytes_of("a5033fa540a503a50340a540a5a503a50340a540a5a503");
  struct Case {
    const char* name;
    const std::vector<uint8_t>* pattern;
    double stop_within_ms;  // < 0: the stop straight after it may be lost
  };
  const Case cases[] = {
      {"random bytes", &noise, 10.0},
      {"a frame cut short, repeated", &half, 10.0},
      {"frames saying 64 bytes, bringing 14", &says_64, 10.0},
      {"made for the rescan", &made, -1},
  };
  for (const Case& c : cases) {
    const FloodResult at_once = flood_then_stop(*c.pattern, 100, 0);
    const FloodResult after_quiet = flood_then_stop(*c.pattern, 100, 50);
    std::printf("%-36s %4.1f steps a byte, %3ld bytes lost; a stop at once obeyed %5.1f ms after its last byte, "
                "after 50 ms quiet %3.1f ms\n",
                c.name, at_once.steps_per_byte, at_once.lost_bytes, at_once.stop_ms, after_quiet.stop_ms);
    if (c.stop_within_ms > 0) {
      EXPECT_EQ(at_once.lost_bytes, 0) << c.name;
      EXPECT_GT(at_once.stop_ms, 0) << c.name;
      EXPECT_LE(at_once.stop_ms, c.stop_within_ms) << c.name;
    }
    EXPECT_GT(after_quiet.stop_ms, 0) << c.name;
    EXPECT_LE(after_quiet.stop_ms, 1.5) << c.name;  // the next read, the iteration after it
  }
}
