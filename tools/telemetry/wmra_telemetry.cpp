// wmra-telemetry: the firmware's serial protocol from the command line (docs/telemetry.md).
//
//   wmra-telemetry decode [FILE]              raw UART bytes (stdin without FILE) -> one JSON line per frame
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
//
// decode and listen end with a summary line on stderr (frames, errors, seq gaps).
// Exit status: 0 done; 2 a bad command line (the message says what); 3 a file or port that
// cannot be opened, read or written.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include "kinematics/arm_model.h"
#include "telemetry_json.h"

using namespace wmra;
using protocol::MsgType;

namespace {

struct BadInput {
  std::string message;
};
struct IoError {
  std::string message;
};

const char kUsage[] =
    "usage: wmra-telemetry decode [FILE]\n"
    "       wmra-telemetry encode COMMAND [ARG...] [--seq N]\n"
    "         COMMAND: stop | rearm | home | mode xy|xz|r1|r2|gripper | speed PCT | goto SLOT | store SLOT\n"
    "                  | velocity VX VY VZ WX WY WZ   (m/s, rad/s, base frame)\n"
    "                  | info | jog J RAD_S   (J 1..6; one frame: a jog goes on while they keep coming)\n"
    "                  | stick-centre store|forget\n"
    "                  | calibration | calibrate J AT_MIN AT_MAX   (J 2..4; pot counts x 16; 0 0: the config's)\n"
    "                  | calibrate-from J READING1 DEG1 READING2 DEG2   (two readings at measured angles)\n"
    "       wmra-telemetry listen DEVICE [--send HEX [--every MS]]\n";

// a whole number in [lo, hi]
long parse_int(const std::string& word, long lo, long hi, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(word.c_str(), &end, 10);
  if (word.empty() || *end || errno == ERANGE || v < lo || v > hi) {
    throw BadInput{what + " must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                   ", not '" + word + "'"};
  }
  return v;
}

// a speed in m/s or rad/s, to the nearest mm/s or mrad/s, within int16_t
int16_t parse_milli(const std::string& word, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end || errno == ERANGE || !std::isfinite(v) || std::fabs(v) > 32.767) {
    throw BadInput{what + " must be a number within +-32.767, not '" + word + "'"};
  }
  return (int16_t)std::lround(v * 1000);
}

std::vector<uint8_t> parse_hex(const std::string& hex) {
  if (hex.empty() || hex.size() % 2) throw BadInput{"--send wants an even number of hex digits"};
  std::vector<uint8_t> bytes;
  for (size_t i = 0; i < hex.size(); i += 2) {
    const std::string pair = hex.substr(i, 2);
    char* end = nullptr;
    const unsigned long b = std::strtoul(pair.c_str(), &end, 16);
    if (*end || !std::isxdigit((unsigned char)pair[0])) throw BadInput{"--send: '" + pair + "' is not a hex byte"};
    bytes.push_back((uint8_t)b);
  }
  return bytes;
}

// a number (an angle in degrees), finite
double parse_double(const std::string& word, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end || errno == ERANGE || !std::isfinite(v)) throw BadInput{what + " must be a number, not '" + word + "'"};
  return v;
}

constexpr long kMaxReading_counts_x16 = 1023 * 16;

// calibrate J AT_MIN AT_MAX
protocol::PotCalibrationCmd pot_calibration(const std::vector<std::string>& words) {
  return protocol::PotCalibrationCmd{(uint8_t)parse_int(words[1], 2, 4, "J (the joint)"),
                                     (int16_t)parse_int(words[2], 0, kMaxReading_counts_x16, "AT_MIN (pot counts x 16)"),
                                     (int16_t)parse_int(words[3], 0, kMaxReading_counts_x16, "AT_MAX (pot counts x 16)")};
}

// calibrate-from J READING1 DEG1 READING2 DEG2: the pot is linear in the joint angle, so the
// readings at the limits (lib/kinematics/arm_model.h) lie on the line through the two points.
// The soft limits keep a joint 3 deg inside its limits, so a joint cannot be driven there to be
// read; two readings at angles measured with an inclinometer can be taken anywhere.
protocol::PotCalibrationCmd pot_calibration_from(const std::vector<std::string>& words) {
  const int joint = (int)parse_int(words[1], 2, 4, "J (the joint)");
  const double r1 = (double)parse_int(words[2], 0, kMaxReading_counts_x16, "READING1 (pot counts x 16)");
  const double a1 = parse_double(words[3], "DEG1");
  const double r2 = (double)parse_int(words[4], 0, kMaxReading_counts_x16, "READING2 (pot counts x 16)");
  const double a2 = parse_double(words[5], "DEG2");
  if (std::fabs(a2 - a1) < 10) throw BadInput{"DEG1 and DEG2 must be at least 10 deg apart"};
  const double per_deg = (r2 - r1) / (a2 - a1);
  const long at_min = std::lround(r1 + (arm::q_min_deg[joint - 1] - a1) * per_deg);
  const long at_max = std::lround(r1 + (arm::q_max_deg[joint - 1] - a1) * per_deg);
  if (per_deg < 0)  // the firmware refuses it (bad_argument): its servo works in units that rise with the angle
    throw BadInput{"the pot's reading falls as the joint's angle rises: it is wired reversed, swap its two outer wires "
                   "(docs/arm-guide.md) and read it again"};
  if (at_min < 0 || at_max > kMaxReading_counts_x16 || at_max <= at_min) {
    throw BadInput{"the limits' readings come out at " + std::to_string(at_min) + " and " + std::to_string(at_max) +
                   ": outside 0.." + std::to_string(kMaxReading_counts_x16) + " or the wrong way round (check the pot's wiring)"};
  }
  return protocol::PotCalibrationCmd{(uint8_t)joint, (int16_t)at_min, (int16_t)at_max};
}

// The command frame for "COMMAND ARG..." (--seq already taken out)
std::string encode(const std::vector<std::string>& words, uint8_t seq) {
  struct Command {
    const char* word;
    MsgType type;
    uint8_t args;
  };
  static const Command kCommands[] = {
      {"stop", MsgType::cmd_stop, 0},         {"rearm", MsgType::cmd_rearm, 0},    {"home", MsgType::cmd_home, 0},
      {"mode", MsgType::cmd_mode, 1},         {"speed", MsgType::cmd_speed_scale, 1}, {"goto", MsgType::cmd_goto_pose, 1},
      {"store", MsgType::cmd_store_pose, 1}, {"velocity", MsgType::cmd_velocity, 6},
      {"calibration", MsgType::cmd_get_calibration, 0}, {"calibrate", MsgType::cmd_pot_calibration, 3},
      {"calibrate-from", MsgType::cmd_pot_calibration, 5}, {"stick-centre", MsgType::cmd_stick_centre, 1},
      {"info", MsgType::cmd_info, 0},         {"jog", MsgType::cmd_jog, 2},
  };
  if (words.empty()) throw BadInput{"encode wants a command"};
  const std::string& word = words[0];
  const Command* c = nullptr;
  for (const Command& k : kCommands) {
    if (word == k.word) c = &k;
  }
  if (!c) throw BadInput{"unknown command '" + word + "'"};
  if (words.size() != 1u + c->args) {
    throw BadInput{word + " takes " + std::to_string(c->args) + " argument" + (c->args == 1 ? "" : "s") + ", got " +
                   std::to_string(words.size() - 1)};
  }
  uint8_t payload[protocol::kMaxPayload];
  uint8_t len = c->args ? 1 : 0;
  switch (c->type) {
    case MsgType::cmd_mode:
      payload[0] = protocol::kModeValues;
      for (uint8_t m = 0; m < protocol::kModeValues; ++m) {
        if (words[1] == telemetry::mode_name(m)) payload[0] = m;
      }
      if (payload[0] == protocol::kModeValues) throw BadInput{"mode must be xy, xz, r1, r2 or gripper, not '" + words[1] + "'"};
      break;
    case MsgType::cmd_speed_scale: payload[0] = (uint8_t)parse_int(words[1], 0, 100, "speed (percent)"); break;
    case MsgType::cmd_stick_centre:
      if (words[1] != "store" && words[1] != "forget") throw BadInput{"stick-centre must be store or forget, not '" + words[1] + "'"};
      payload[0] = words[1] == "store";
      break;
    case MsgType::cmd_goto_pose:
    case MsgType::cmd_store_pose:
      payload[0] = (uint8_t)parse_int(words[1], 0, protocol::kPoseSlots - 1, word + " (slot)");
      break;
    case MsgType::cmd_velocity: {
      static const char* kNames[] = {"VX (m/s)", "VY (m/s)", "VZ (m/s)", "WX (rad/s)", "WY (rad/s)", "WZ (rad/s)"};
      protocol::VelocityCmd v;
      for (int i = 0; i < 3; ++i) {
        v.v_mm_s[i] = parse_milli(words[1 + i], kNames[i]);
        v.w_mrad_s[i] = parse_milli(words[4 + i], kNames[3 + i]);
      }
      len = protocol::encode(v, payload);
      break;
    }
    case MsgType::cmd_jog: {
      const protocol::JogCmd j{(uint8_t)parse_int(words[1], 1, 6, "J (the joint)"), parse_milli(words[2], "RAD_S (rad/s)")};
      len = protocol::encode(j, payload);
      break;
    }
    case MsgType::cmd_pot_calibration: {
      const protocol::PotCalibrationCmd p = c->args == 3 ? pot_calibration(words) : pot_calibration_from(words);
      len = protocol::encode(p, payload);
      break;
    }
    default: break;  // no argument
  }
  uint8_t frame[protocol::kMaxFrameBytes];
  return telemetry::to_hex(frame, protocol::write_frame((uint8_t)c->type, seq, payload, len, frame));
}

// Decodes bytes from fd to stdout until the end of input (or a signal); sends `send` once
// the first frame has arrived, and then every every_ms if that is not 0. Returns the stream, for
// the summary.
volatile std::sig_atomic_t g_stop = 0;

telemetry::FrameStream decode_fd(int fd, const std::vector<uint8_t>& send, int every_ms) {
  telemetry::FrameStream stream;
  uint8_t buf[4096];
  bool sent = false;
  auto send_now = [&] {
    if (write(fd, send.data(), send.size()) != (ssize_t)send.size()) {
      throw IoError{std::string("write: ") + std::strerror(errno)};
    }
    sent = true;
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
    for (ssize_t i = 0; i < n; ++i) {
      stream.push(buf[i]);
      while (stream.next()) {
        std::printf("%s\n", telemetry::to_json(stream.frame()).c_str());
        if (!send.empty() && !sent) send_now();
      }
    }
    std::fflush(stdout);
  }
  return stream;
}

int open_serial(const std::string& device) {
  const int fd = open(device.c_str(), O_RDWR | O_NOCTTY);
  if (fd < 0) throw IoError{device + ": " + std::strerror(errno)};
  termios t;
  if (tcgetattr(fd, &t) != 0) throw IoError{device + ": not a serial port (" + std::strerror(errno) + ")"};
  cfmakeraw(&t);  // 8 data bits, no parity, no echo, no line editing
  t.c_cflag &= ~(tcflag_t)(CSTOPB | CRTSCTS);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, B115200) != 0 || cfsetospeed(&t, B115200) != 0 || tcsetattr(fd, TCSANOW, &t) != 0) {
    throw IoError{device + ": cannot set 115200 8N1 (" + std::strerror(errno) + ")"};
  }
  tcflush(fd, TCIOFLUSH);
  return fd;
}

void on_signal(int) { g_stop = 1; }

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
    return 0;
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
      send = parse_hex(args[3]);
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
  const telemetry::FrameStream stream = decode_fd(fd, send, every_ms);
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
