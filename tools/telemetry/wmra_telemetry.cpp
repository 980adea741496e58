// wmra-telemetry: the firmware's serial protocol from the command line (docs/telemetry.md).
//
//   wmra-telemetry decode [FILE]              UART bytes (stdin without FILE) -> one JSON line per frame;
//                                             the bytes raw, or as hex text (what encode prints)
//   wmra-telemetry encode COMMAND [ARG...] [--seq N]
//                                             a command frame as lowercase hex (armsim's "serial HEX")
//       stop | rearm | home | mode xy|xz|r1|r2|gripper | speed PCT | goto SLOT | store SLOT
//       | velocity VX VY VZ WX WY WZ          (m/s and rad/s, base frame)
//       | info | jog J RAD_S                (J 1..6; one frame: a jog goes on while they keep coming)
//       | calibration | calibrate J AT_MIN AT_MAX | calibrate-from J READING1 DEG1 READING2 DEG2
//                                             read / set a DC joint's pot calibration (J 2..4, counts x 16);
//                                             calibrate-from extrapolates the limits' readings from two
//                                             readings at measured angles
//   wmra-telemetry listen DEVICE [--send HEX [--every MS]]
//                                             a serial port at 115200 8N1, decoded live until Ctrl-C;
//                                             HEX is sent once the firmware's first frame has arrived,
//                                             and again every MS milliseconds with --every (a velocity
//                                             stream: the firmware stops 100 ms after the last one)
//   wmra-telemetry session DEVICE [--json]    the port kept open, commands from stdin one a line
//                                             (session.h)
//   wmra-telemetry calibrate DEVICE J         J's pot (2..4) calibrated with a person: jogged to two
//                                             angles they measure, answers from stdin (calibrate.h)
//
// decode, listen and session end with a summary line on stderr (frames, errors, seq gaps).
// Exit status: 0 done; 1 calibrate did not store; 2 a bad command line, hex text, session or
// calibrate line (the message says what); 3 a file or port that cannot be opened, read or written.
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include "kinematics/arm_model.h"

#include "calibrate.h"
#include "commands.h"
#include "serial_port.h"
#include "session.h"
#include "telemetry_json.h"
#include "version_text.h"

using namespace wmra;
using namespace wmra::telemetry_cli;

namespace {

const char kUsage[] =
    "usage: wmra-telemetry decode [FILE]   (raw UART bytes, or hex text such as encode prints)\n"
    "       wmra-telemetry encode COMMAND [ARG...] [--seq N]\n"
    "         COMMAND: stop | rearm | home | mode xy|xz|r1|r2|gripper | speed PCT | goto SLOT | store SLOT\n"
    "                  | velocity VX VY VZ WX WY WZ   (m/s, rad/s, base frame)\n"
    "                  | info | jog J RAD_S   (J 1..6; one frame: a jog goes on while they keep coming)\n"
    "                  | stick-centre store|forget\n"
    "                  | calibration | calibrate J AT_MIN AT_MAX   (J 2..4; pot counts x 16; 0 0: the config's)\n"
    "                  | calibrate-from J READING1 DEG1 READING2 DEG2   (two readings at measured angles)\n"
    "       wmra-telemetry listen DEVICE [--send HEX [--every MS]]\n"
    "       wmra-telemetry session DEVICE [--json]\n"
    "         reads commands from stdin, one a line, in encode's words (no --seq), and also\n"
    "         jog J RAD_S [SECONDS]   (the jog frame every 40 ms for SECONDS, 0.1..60, default 1)\n"
    "         sleep SECONDS           (waits, the port still read)\n"
    "         blank lines and # comments are skipped; each command waits up to 1 s for its reply.\n"
    "         Prints each reply, the boot, info and calibration frames, and a status line when the\n"
    "         state, mode, faults or switches change and once a second; --json: every frame as decode\n"
    "         prints it (the replies' lines then go to stderr). The port stays open: a Mega resets\n"
    "         only when it is first opened, and the session waits up to 3 s for its boot frame.\n"
    "       wmra-telemetry calibrate DEVICE J\n"
    "         calibrates J's pot (J 2..4) with you, the arm waiting before homing (wait_home): shows\n"
    "         J's reading and the firmware's angle, then reads your answers from stdin, one a line:\n"
    "         + [SECONDS] | - [SECONDS]   jogs J at +-0.1 rad/s (0.1..20 s, default 1)\n"
    "         DEG                         the angle you measure J at here (an inclinometer): a point\n"
    "         two points at least 10 deg apart give J's readings at its limits; then store? yes | no.\n"
    "         q quits; blank lines and # comments are skipped. Exit 0 stored, 1 not stored, 2 a line\n"
    "         not used (whether or not it stored), 3 the port.\n"
    "       wmra-telemetry --help | --version\n";

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// decode's input, raw bytes or hex text: the first 16 bytes (all of them, when fewer) decide.
// Hex digits and whitespace only is text, two digits a byte, whitespace anywhere between them;
// raw telemetry starts at a sync byte 0xA5 or a frame's middle, hardly ever with 16 such bytes.
class DecodeInput {
 public:
  // the bytes of this chunk of input (none while the first 16 are still being looked at)
  std::vector<uint8_t> bytes(const uint8_t* in, size_t n) {
    if (!decided_) {
      head_.insert(head_.end(), in, in + n);
      if (head_.size() < kLookAt) return {};
      return decide();
    }
    return hex_ ? from_hex(in, n) : std::vector<uint8_t>(in, in + n);
  }
  // at the end of the input: what is still held
  std::vector<uint8_t> end() {
    std::vector<uint8_t> out = decided_ ? std::vector<uint8_t>() : decide();
    if (hex_ && half_ >= 0) throw BadInput{"decode: the hex text ends in half a byte (an odd number of digits)"};
    return out;
  }

 private:
  static constexpr size_t kLookAt = 16;

  std::vector<uint8_t> decide() {
    decided_ = true;
    bool digits = false;
    hex_ = true;
    for (size_t i = 0; i < head_.size() && i < kLookAt; ++i) {
      const uint8_t c = head_[i];
      digits |= std::isxdigit(c) != 0;
      hex_ &= std::isxdigit(c) || std::isspace(c);
    }
    hex_ &= digits;
    return hex_ ? from_hex(head_.data(), head_.size()) : head_;
  }

  std::vector<uint8_t> from_hex(const uint8_t* in, size_t n) {
    std::vector<uint8_t> out;
    for (size_t i = 0; i < n; ++i, ++offset_) {
      const uint8_t c = in[i];
      if (std::isspace(c)) continue;
      if (!std::isxdigit(c)) {
        throw BadInput{"decode: the input began as hex text, but byte " + std::to_string(offset_) +
                       " is not a hex digit (" + (std::isprint(c) ? std::string("'") + (char)c + "'" : "code " + std::to_string(c)) + ")"};
      }
      const int nibble = std::isdigit(c) ? c - '0' : std::tolower(c) - 'a' + 10;
      if (half_ < 0) {
        half_ = nibble;
      } else {
        out.push_back((uint8_t)(half_ << 4 | nibble));
        half_ = -1;
      }
    }
    return out;
  }

  bool decided_ = false, hex_ = false;
  std::vector<uint8_t> head_;
  int half_ = -1;       // the first digit of a byte whose second is still to come
  size_t offset_ = 0;   // of the next input byte
};

// Decodes bytes from fd to stdout until the end of input (or a signal); sends `send` once
// the first frame has arrived, and then every every_ms if that is not 0. With hex_allowed (decode), the
// input may be hex text. Returns the stream, for the summary.
telemetry::FrameStream decode_fd(int fd, const std::vector<uint8_t>& send, int every_ms, bool hex_allowed) {
  telemetry::FrameStream stream;
  DecodeInput input;
  uint8_t buf[4096];
  bool sent = false;
  auto send_now = [&] {
    if (write(fd, send.data(), send.size()) != (ssize_t)send.size()) {
      throw IoError{std::string("write: ") + std::strerror(errno)};
    }
    sent = true;
  };
  auto decode = [&](const std::vector<uint8_t>& bytes) {
    for (uint8_t b : bytes) {
      stream.push(b);
      while (stream.next()) {
        std::printf("%s\n", telemetry::to_json(stream.frame()).c_str());
        if (!send.empty() && !sent) send_now();
      }
    }
    std::fflush(stdout);
  };
  while (!g_stop) {
    if (sent && every_ms > 0) {
      pollfd p{fd, POLLIN, 0};
      const int ready = poll(&p, 1, every_ms);
      if (ready < 0 && errno != EINTR) throw IoError{std::string("poll: ") + std::strerror(errno)};
      if (ready == 0) {
        send_now();
        continue;
      }
      if (ready < 0) continue;
    }
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError{std::string("read: ") + std::strerror(errno)};
    }
    decode(hex_allowed ? input.bytes(buf, (size_t)n) : std::vector<uint8_t>(buf, buf + n));
  }
  if (hex_allowed && !g_stop) decode(input.end());
  return stream;
}

int run(const std::vector<std::string>& args) {
  if (args.empty()) throw BadInput{"no command"};
  const std::string& what = args[0];
  if (what == "encode") {
    std::vector<std::string> words;
    uint8_t seq = 0;
    for (size_t i = 1; i < args.size(); ++i) {
      if (args[i] != "--seq") {
        words.push_back(args[i]);
      } else if (i + 1 < args.size()) {
        seq = (uint8_t)parse_int(args[++i], 0, 255, "--seq");
      } else {
        throw BadInput{"--seq wants a number"};
      }
    }
    std::printf("%s\n", encode(words, seq).c_str());
    // calibrate-from's computed limits, for the person to check before sending them
    if (!words.empty() && words[0] == "calibrate-from") {
      const protocol::PotCalibrationCmd c = pot_calibration_from_words(words);
      std::fprintf(stderr, "calibrate-from: J%d reads %d at %d deg and %d at %d deg (its limits, pot counts x 16)\n", c.joint,
                   c.at_min_counts_x16, arm::q_min_deg[c.joint - 1], c.at_max_counts_x16, arm::q_max_deg[c.joint - 1]);
    }
    return 0;
  }
  if (what == "session") {
    SessionOptions options;
    if (args.size() == 3 && args[2] == "--json") {
      options.json = true;
    } else if (args.size() != 2 || args[1].rfind("--", 0) == 0) {
      throw BadInput{"session takes DEVICE [--json]"};
    }
    options.device = args[1];
    options.input_fd = STDIN_FILENO;
    return run_session(options);
  }
  if (what == "calibrate") {
    if (args.size() != 3 || args[1].rfind("--", 0) == 0) throw BadInput{"calibrate takes DEVICE J"};
    CalibrateOptions options;
    options.device = args[1];
    options.joint = (int)parse_int(args[2], 2, 4, "J (the DC joint: 2, 3 or 4)");
    options.input_fd = STDIN_FILENO;
    return run_calibrate(options);
  }
  int fd = -1;
  std::vector<uint8_t> send;
  int every_ms = 0;
  if (what == "decode") {
    if (args.size() > 2) throw BadInput{"decode takes at most one FILE"};
    fd = args.size() == 2 ? open(args[1].c_str(), O_RDONLY) : STDIN_FILENO;
    if (fd < 0) throw IoError{args[1] + ": " + std::strerror(errno)};
  } else if (what == "listen") {
    if ((args.size() == 4 || args.size() == 6) && args[2] == "--send") {
      send = parse_hex(args[3], "--send");
      if (args.size() == 6) {
        if (args[4] != "--every") throw BadInput{"listen takes DEVICE [--send HEX [--every MS]]"};
        every_ms = (int)parse_int(args[5], 10, 60000, "--every (ms)");
      }
    } else if (args.size() != 2) {
      throw BadInput{"listen takes DEVICE [--send HEX [--every MS]]"};
    }
    fd = open_serial(args[1]);
    struct sigaction sa = {};
    sa.sa_handler = on_signal;  // no SA_RESTART: read() returns, the loop ends with the summary
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
  } else {
    throw BadInput{"unknown command '" + what + "'"};
  }
  const telemetry::FrameStream stream = decode_fd(fd, send, every_ms, what == "decode");
  std::fprintf(stderr, "wmra-telemetry: %s\n", stream.summary().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "-h" || args[0] == "--help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (!args.empty() && args[0] == "--version") {
    std::printf("%s\n", wmra::version_text("wmra-telemetry").c_str());
    return 0;
  }
  try {
    return run(args);
  } catch (const BadInput& e) {
    std::fprintf(stderr, "wmra-telemetry: %s\n%s", e.message.c_str(), kUsage);
    return 2;
  } catch (const IoError& e) {
    std::fprintf(stderr, "wmra-telemetry: %s\n", e.message.c_str());
    return 3;
  }
}
