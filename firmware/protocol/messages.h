// The messages on the serial link (docs/telemetry.md): what the firmware reports and
// what a host may command, and their payloads. Every field goes on the wire little-endian,
// byte by byte, in the order its message's fields() lists it: the same bytes on the AVR and
// on the host, whatever either does with struct layout. docs/telemetry.md has the offsets.
#pragma once

#include <stdint.h>

#include "config/modes_config.h"
#include "protocol/frame.h"

namespace wmra {
namespace protocol {

enum class MsgType : uint8_t {
  state = 0x01, reply = 0x02, boot = 0x03, calibration = 0x04, info = 0x05,  // firmware -> host
  cmd_stop = 0x10, cmd_rearm = 0x11, cmd_mode = 0x12, cmd_speed_scale = 0x13, cmd_home = 0x14,
  cmd_goto_pose = 0x15, cmd_store_pose = 0x16, cmd_velocity = 0x17, cmd_pot_calibration = 0x18,
  cmd_get_calibration = 0x19, cmd_stick_centre = 0x1A, cmd_info = 0x1B, cmd_jog = 0x1C,  // host -> firmware
};

// refused: the arm's state does not allow the command now; safety_held: a re-arm while the
// safety button is held (released first, then re-armed)
enum class ReplyStatus : uint8_t { ok = 0, unknown_command = 1, bad_length = 2, bad_argument = 3, refused = 4, safety_held = 5 };

// BootMsg::calibration: where the firmware's calibration came from (bits 0..6), and in bit 7
// whether J6's angle at rest was recorded (set: J6 homes to the turn it implies; clear: none was,
// J6 homes by sweeps that take it to be within half a turn of 0)
enum class Calibration : uint8_t { eeprom = 0, defaults_blank = 1, defaults_bad_crc = 2, defaults_other_version = 3 };
constexpr uint8_t kBootJ6AngleRecorded = 0x80;

constexpr uint16_t kStatePeriod_ms = 20;       // state frames at 50 Hz
constexpr uint16_t kVelocityTimeout_ms = 100;  // the firmware stops when streamed velocity pauses this long
constexpr uint8_t kPoseSlots = 4;              // goto_pose / store_pose slots 0..3
constexpr uint8_t kModeValues = (uint8_t)config::Mode::gripper + 1;  // config::Mode values 0..4

namespace wire {
// Io for fields(): writes each field little-endian
struct Put {
  uint8_t* out;
  uint8_t n;
  template <class T>
  void operator()(T v) {
    uint32_t u = (uint32_t)v;  // shifts by whole bytes only: cheap on the AVR
    for (uint8_t i = 0; i < sizeof(T); ++i, u >>= 8) out[n++] = (uint8_t)u;
  }
};
// reads each field back (a negative field's two's complement comes back through the cast)
struct Get {
  const uint8_t* in;
  uint8_t n;
  template <class T>
  void operator()(T& v) {
    uint32_t u = 0;
    for (uint8_t i = sizeof(T); i-- > 0;) u = (u << 8) | in[n + i];
    n = (uint8_t)(n + sizeof(T));
    v = (T)u;
  }
};
// counts the bytes, at compile time
struct Count {
  uint8_t n;
  template <class T>
  constexpr void operator()(const T&) {
    n = (uint8_t)(n + sizeof(T));
  }
};
}  // namespace wire

// Each message lists its fields once, in wire order, for every Io of wire:: (Self is the
// message, const when encoding).
struct StateMsg {  // every kStatePeriod_ms
  uint32_t t_ms;              // since boot
  uint8_t state;              // core::ArmState value (firmware/core/supervisor.h)
  uint8_t mode;               // config::Mode value (firmware/config/modes_config.h)
  uint32_t faults;            // core::FaultBit bits (firmware/core/faults.h)
  uint8_t slowed_by;          // core::SlowReason bits (firmware/core/resolved_rate.h)
  uint8_t reset_cause;        // MCUSR at boot: bit0 power-on, 1 external, 2 brown-out, 3 watchdog
  uint16_t switches;          // closed limit switches: bit 2j = J(j+1) low, 2j+1 = high (J6: bit 10 its zero switch)
  int16_t q_mrad[6];          // the firmware's joint angles (steppers from steps, DC from pots)
  int16_t qd_mrad_s[6];       // commanded joint velocities
  int16_t p_0p1mm[3];         // hand (frame-6 origin) position from the firmware's FK, 0.1 mm
  int16_t stick_permille[2];  // shaped stick x, y in [-1000, 1000]
  uint8_t speed_scale_pct;    // 0..100
  uint16_t loop_cycles_max;   // longest control iteration since the previous state frame, CPU cycles
  uint16_t rx_crc_errors, rx_framing_errors, rx_rejected;  // the firmware's counters (rejected = replies != ok)
  uint16_t rx_overruns;       // bytes the firmware never read: its receive buffer full, or the UART's own overrun

  static constexpr MsgType kType = MsgType::state;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    io(m.t_ms);
    io(m.state);
    io(m.mode);
    io(m.faults);
    io(m.slowed_by);
    io(m.reset_cause);
    io(m.switches);
    for (auto& v : m.q_mrad) io(v);
    for (auto& v : m.qd_mrad_s) io(v);
    for (auto& v : m.p_0p1mm) io(v);
    for (auto& v : m.stick_permille) io(v);
    io(m.speed_scale_pct);
    io(m.loop_cycles_max);
    io(m.rx_crc_errors);
    io(m.rx_framing_errors);
    io(m.rx_rejected);
    io(m.rx_overruns);
  }
};

struct ReplyMsg {  // to every command; the frame's own seq is the firmware's count
  uint8_t command_type;  // the command's MsgType
  uint8_t command_seq;   // the command frame's seq
  uint8_t status;        // ReplyStatus

  static constexpr MsgType kType = MsgType::reply;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    io(m.command_type);
    io(m.command_seq);
    io(m.status);
  }
};

// What the firmware is, in the boot and info frames: its version (config/version.h), the git
// commit it was built from and the configuration headers' hash (cmake/build_identity.cmake)
constexpr uint8_t kBuildTreeChanged = 0x01;    // Identity::build_flags: built with changes beside the commit
constexpr uint8_t kBuildCommitUnknown = 0x02;  // not built from a git checkout (commit all zeros)
struct Identity {
  uint8_t version[3];   // major, minor, patch
  uint8_t commit[6];    // the commit's first 12 hex digits, two a byte
  uint8_t build_flags;  // kBuildTreeChanged | kBuildCommitUnknown
  uint32_t config_hash;  // the first 32 bits of the SHA-256 of firmware/config/*.h

  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    for (auto& v : m.version) io(v);
    for (auto& v : m.commit) io(v);
    io(m.build_flags);
    io(m.config_hash);
  }
};

struct BootMsg {  // once at start-up, before the first state frame
  uint8_t reset_cause;  // MCUSR, as in StateMsg
  uint8_t calibration;  // Calibration, | kBootJ6AngleRecorded
  Identity identity;

  Calibration settings() const { return (Calibration)(calibration & ~kBootJ6AngleRecorded); }
  bool j6_angle_recorded() const { return (calibration & kBootJ6AngleRecorded) != 0; }

  static constexpr MsgType kType = MsgType::boot;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    io(m.reset_cause);
    io(m.calibration);
    Identity::fields(io, m.identity);
  }
};

// After cmd_info: the identity and the numbers a technician checks against the arm
// (firmware/config): the stick's top speeds, each joint's speed limit and soft limits (where the
// motion slows to a stop, kSoftLimitMargin_deg inside the joint's limits), the control rate.
struct InfoMsg {
  Identity identity;
  uint16_t hand_speed_mm_s;     // at full stick in XY and XZ
  uint16_t wrist_speed_mrad_s;  // in R1 and R2
  uint16_t joint_speed_mrad_s[6];
  int16_t soft_min_mrad[6];
  int16_t soft_max_mrad[6];
  uint16_t loop_hz;

  static constexpr MsgType kType = MsgType::info;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    Identity::fields(io, m.identity);
    io(m.hand_speed_mm_s);
    io(m.wrist_speed_mrad_s);
    for (auto& v : m.joint_speed_mrad_s) io(v);
    for (auto& v : m.soft_min_mrad) io(v);
    for (auto& v : m.soft_max_mrad) io(v);
    io(m.loop_hz);
  }
};

struct VelocityCmd {  // hand twist in the base frame; the firmware stops if none arrives for kVelocityTimeout_ms
  int16_t v_mm_s[3];
  int16_t w_mrad_s[3];

  static constexpr MsgType kType = MsgType::cmd_velocity;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    for (auto& v : m.v_mm_s) io(v);
    for (auto& v : m.w_mrad_s) io(v);
  }
};

// The DC joints' potentiometer calibration (J2, J3, J4), after a cmd_get_calibration or a
// cmd_pot_calibration: a person reads the pot where a joint sits at a limit, then sets it.
struct CalibrationMsg {
  int16_t at_min_counts_x16[3];  // ADC counts x 16 at each joint's lower limit
  int16_t at_max_counts_x16[3];  // and at its upper limit
  int16_t reading_counts_x16[3];  // what each pot reads now
  uint8_t from_command;           // bit d: joint d's two values were set by cmd_pot_calibration (else joints_config.h)

  static constexpr MsgType kType = MsgType::calibration;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    for (auto& v : m.at_min_counts_x16) io(v);
    for (auto& v : m.at_max_counts_x16) io(v);
    for (auto& v : m.reading_counts_x16) io(v);
    io(m.from_command);
  }
};

// Sets one DC joint's pot calibration, kept in EEPROM; both values 0 return the joint to
// joints_config.h. Refused while the drives are on: the joint's measured angle jumps with it,
// and (bad_argument) unless both readings are within the 10-bit ADC's range and the upper
// limit's at least kPotCalibrationMinSpan_counts_x16 above the lower's (firmware/app/settings.cpp).
constexpr int32_t kPotCalibrationMinSpan_counts_x16 = 600 * 16;
struct PotCalibrationCmd {
  uint8_t joint;  // 2, 3 or 4 (J2..J4)
  int16_t at_min_counts_x16;
  int16_t at_max_counts_x16;

  static constexpr MsgType kType = MsgType::cmd_pot_calibration;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    io(m.joint);
    io(m.at_min_counts_x16);
    io(m.at_max_counts_x16);
  }
};

// Turns one joint at a speed while these keep coming (each within kVelocityTimeout_ms of the
// last), to check a motor's direction or a pot in bring-up (docs/arm-guide.md). The firmware caps
// the speed (config::kJogSpeed_mrad_s; a stepper before homing at kJogUnhomedSpeed_mrad_s) and
// refuses it where the arm's state does not allow it.
struct JogCmd {
  uint8_t joint;  // 1..6
  int16_t speed_mrad_s;

  static constexpr MsgType kType = MsgType::cmd_jog;
  template <class Io, class Self>
  static constexpr void fields(Io& io, Self& m) {
    io(m.joint);
    io(m.speed_mrad_s);
  }
};

template <class Msg>
constexpr uint8_t payload_bytes() {
  wire::Count count{0};
  Msg m{};
  Msg::fields(count, m);
  return count.n;
}

constexpr uint8_t kStatePayloadBytes = payload_bytes<StateMsg>();
constexpr uint8_t kVelocityPayloadBytes = payload_bytes<VelocityCmd>();
static_assert(kStatePayloadBytes <= kMaxPayload, "a state frame fits one frame");
// the documented layouts (docs/telemetry.md): a change here is a change of kVersion
static_assert(kStatePayloadBytes == 59 && kVelocityPayloadBytes == 12, "payload sizes as documented");
static_assert(payload_bytes<ReplyMsg>() == 3 && payload_bytes<BootMsg>() == 16 && payload_bytes<InfoMsg>() == 56,
              "payload sizes as documented");
static_assert(payload_bytes<CalibrationMsg>() == 19 && payload_bytes<PotCalibrationCmd>() == 5 && payload_bytes<JogCmd>() == 3,
              "payload sizes as documented");

// Fills payload (room for kMaxPayload) and returns its length. The AVR lays a message out as
// the wire does (no padding: every type is byte-aligned; little-endian; the fields in their
// order of declaration, which fields() follows), so there its bytes are the payload: a copy,
// where the fields one by one took ~1,700 cycles a state frame. test_avr_protocol compares
// the AVR's frames with the host's byte for byte.
template <class Msg>
uint8_t encode(const Msg& m, uint8_t* payload) {
#ifdef __AVR__
  static_assert(sizeof(Msg) == payload_bytes<Msg>(), "no padding: the struct is the payload");
  __builtin_memcpy(payload, &m, sizeof(Msg));
  return (uint8_t)sizeof(Msg);
#else
  wire::Put put{payload, 0};
  Msg::fields(put, m);
  return put.n;
#endif
}

// false, leaving m as it was, when the frame is not a Msg or its length is wrong
template <class Msg>
bool decode(const Frame& f, Msg& m) {
  if (f.type != (uint8_t)Msg::kType || f.len != payload_bytes<Msg>()) return false;
  wire::Get get{f.payload, 0};
  Msg::fields(get, m);
  return true;
}

// The whole frame of a message into out (room for kMaxFrameBytes); returns its size. The
// payload is encoded in place, so no second buffer is needed on the AVR's stack.
template <class Msg>
uint8_t write_message(const Msg& m, uint8_t seq, uint8_t* out) {
  uint8_t* payload = out + kHeaderBytes;
  return write_frame((uint8_t)Msg::kType, seq, payload, encode(m, payload), out);
}

// Whether a command frame may be acted on: its type, its payload length, and the range of
// its one-byte argument (mode < kModeValues, percent <= 100, slot < kPoseSlots). What the
// arm's state allows (ReplyStatus::refused) is the firmware's to decide.
inline ReplyStatus check_command(const Frame& f) {
  uint8_t len = 0, limit = 0;  // payload length; the one-byte argument's bound (0: none)
  switch ((MsgType)f.type) {
    case MsgType::cmd_stop:
    case MsgType::cmd_rearm:
    case MsgType::cmd_home:
    case MsgType::cmd_get_calibration:
    case MsgType::cmd_info:
      break;
    case MsgType::cmd_mode:
      len = 1;
      limit = kModeValues;
      break;
    case MsgType::cmd_speed_scale:
      len = 1;
      limit = 101;
      break;
    case MsgType::cmd_goto_pose:
    case MsgType::cmd_store_pose:
      len = 1;
      limit = kPoseSlots;
      break;
    case MsgType::cmd_stick_centre:  // 1: store the stick's centre now, 0: forget the stored one
      len = 1;
      limit = 2;
      break;
    case MsgType::cmd_velocity:
      len = kVelocityPayloadBytes;
      break;
    case MsgType::cmd_pot_calibration:
      len = payload_bytes<PotCalibrationCmd>();
      break;
    case MsgType::cmd_jog:  // joint 1..6
      len = payload_bytes<JogCmd>();
      limit = 7;
      break;
    default:
      return ReplyStatus::unknown_command;
  }
  if (f.len != len) return ReplyStatus::bad_length;
  if (limit && f.payload[0] >= limit) return ReplyStatus::bad_argument;
  if ((MsgType)f.type == MsgType::cmd_jog && f.payload[0] == 0) return ReplyStatus::bad_argument;
  return ReplyStatus::ok;
}

}  // namespace protocol
}  // namespace wmra
