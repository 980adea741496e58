#include "app/link.h"

#include <avr/pgmspace.h>

#include "build_identity.h"
#include "config/control_config.h"
#include "config/motion_config.h"
#include "config/version.h"
#include "kinematics/arm_model.h"
#include "core/faults.h"
#include "core/joint_map.h"
#include "core/stream_limit.h"
#include "drivers/inputs.h"
#include "drivers/system_tick.h"
#include "drivers/uart.h"
#include "protocol/frame.h"
#include "protocol/messages.h"
#include "protocol/parser.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace app {
namespace link {

namespace {

using protocol::MsgType;
using protocol::ReplyStatus;

protocol::Parser g_parser;
uint8_t g_seq;
uint8_t g_reset_cause;
uint16_t g_rejected;
uint32_t g_next_state_ms;  // the next state frame is due at this tick::now_ms()
uint16_t g_velocity_age_ms = 0xFFFF;  // since the last velocity command, accepted or refused
uint8_t g_jog_age_ms = 0xFF;          // since the last jog command, accepted or refused (saturating)
// A jog refused (a stop, the stick taking over, a state that does not allow it) has ended: its
// commands are refused until none has come for the timeout, so that a host still sending them
// does not set the joint off again after a re-arm or when the stick is let go (as a stream)
bool g_jog_ended;
// The stream is over: its velocity commands are refused until none has come for the timeout,
// so that the host must pause and begin a new one. Any stop ends it (the state leaves
// running), and so does the stick: at a rail, deflected, or taking it over.
bool g_stream_ended;
uint8_t g_arrived;  // uart::arrived() at the last poll
uint8_t g_quiet_ms;  // whole ticks since the line last brought a byte (saturating)
uint16_t g_loop_cycles_max;
// frames that follow a command's reply (on a later tick if the transmit buffer is full)
constexpr uint8_t kSendCalibration = 0x01, kSendInfo = 0x02;
uint8_t g_send_after_reply;

constexpr uint16_t kMaxHand_mm_s = (uint16_t)(config::kMaxHandSpeed_m_s.num * 1000 / config::kMaxHandSpeed_m_s.den);
constexpr uint16_t kMaxWrist_mrad_s = (uint16_t)(config::kMaxWristSpeed_rad_s.num * 1000 / config::kMaxWristSpeed_rad_s.den);

// What this firmware is and the numbers a technician checks against the arm (the info frame),
// all constants, in flash
constexpr protocol::Identity kIdentity{{config::kProductVersion.major, config::kProductVersion.minor, config::kProductVersion.patch},
                                       WMRA_BUILD_COMMIT_BYTES,
                                       WMRA_BUILD_FLAGS,
                                       WMRA_CONFIG_HASH};
constexpr int16_t soft_limit_mrad(int16_t limit_deg, int16_t inwards_deg) {
  return (int16_t)((limit_deg + inwards_deg) * 3141.592653589793 / 180 + (limit_deg + inwards_deg < 0 ? -0.5 : 0.5));
}
constexpr int16_t soft_min_mrad(uint8_t j) { return soft_limit_mrad(arm::q_min_deg[j], config::kSoftLimitMargin_deg); }
constexpr int16_t soft_max_mrad(uint8_t j) { return soft_limit_mrad(arm::q_max_deg[j], (int16_t)-config::kSoftLimitMargin_deg); }
constexpr uint16_t speed_mrad_s(uint8_t j) { return (uint16_t)(config::kJointSpeedLimit_crad_s[j] * 10); }
const protocol::InfoMsg kInfoInFlash PROGMEM = {
    kIdentity,
    kMaxHand_mm_s,
    kMaxWrist_mrad_s,
    {speed_mrad_s(0), speed_mrad_s(1), speed_mrad_s(2), speed_mrad_s(3), speed_mrad_s(4), speed_mrad_s(5)},
    {soft_min_mrad(0), soft_min_mrad(1), soft_min_mrad(2), soft_min_mrad(3), soft_min_mrad(4), soft_min_mrad(5)},
    {soft_max_mrad(0), soft_max_mrad(1), soft_max_mrad(2), soft_max_mrad(3), soft_max_mrad(4), soft_max_mrad(5)},
    config::kLoopHz};
static_assert(sizeof(protocol::InfoMsg) == protocol::payload_bytes<protocol::InfoMsg>(), "no padding: the struct is the payload");

int16_t to_i16(int32_t v) { return (int16_t)(v > 32767 ? 32767 : v < -32767 ? -32767 : v); }

// One function per unit, each with its constant scale (a shift by whole bytes and a few bits)
int16_t mrad(fx::Angle a) {
  constexpr core::Scale kMrad = core::scale_for(1000.0 / core::kAngleCountsPerRad);
  return to_i16(core::apply(kMrad, a.raw));
}
int16_t mrad_s(fx::Real r) {
  constexpr core::Scale kMradPerS = core::scale_for(1000.0 / core::kRealPerRad);
  return to_i16(core::apply(kMradPerS, r.raw));
}
int16_t tenth_mm(fx::Real r) {
  constexpr core::Scale kTenthMm = core::scale_for(10000.0 / core::kRealPerRad);
  return to_i16(core::apply(kTenthMm, r.raw));
}

// a Q15 fraction in thousandths, rounded (x 2000 / 2^16: a byte shift, where / 32767 was a
// 32-bit division of ~600 cycles); +-32767 gives +-1000
int16_t permille(int16_t q15) { return (int16_t)(((int32_t)q15 * 2000 + 32768) >> 16); }

// The frame being sent, one at a time, its payload in place (at kPayload). A global: its
// bytes are stored directly (on the stack, 60 to 120 bytes into the frame, each store moved
// the frame pointer). A state message is written straight into it, field by field: the AVR
// lays a message out as the wire does (protocol::encode), so it needs no copy (a message on
// the stack, zeroed and copied, took ~800 cycles a frame).
union FrameBuffer {
  uint8_t bytes[protocol::kMaxFrameBytes];
  struct {
    uint8_t header[protocol::kHeaderBytes];
    protocol::StateMsg msg;
  } state;
};
static_assert(sizeof(protocol::StateMsg) == protocol::kStatePayloadBytes, "no padding: the struct is the payload");
FrameBuffer g_frame;
uint8_t* const kPayload = g_frame.bytes + protocol::kHeaderBytes;

// g_frame, its payload of `length` bytes in place, to the transmit buffer; false when that had
// no room: the frame is dropped whole. Its number is used up either way, so that the host sees
// a gap for every frame dropped (docs/telemetry.md). Once a state frame has been dropped,
// replies and the other frames leave room for the next ones (keep_room_for_state()): commands
// at the line's full rate need more of the line for their replies than it has (10 bytes out for
// every 8 in), and would otherwise starve the telemetry; a short burst of them costs one frame
// and no reply.
bool keep_room_for_state();
constexpr uint8_t kStateFrameBytes = protocol::kFrameOverhead + sizeof(protocol::StateMsg);
bool send(MsgType type, uint8_t length) {
  const uint8_t n = protocol::write_frame((uint8_t)type, g_seq++, kPayload, length, g_frame.bytes);
  return uart::write(g_frame.bytes, n, keep_room_for_state() ? kStateFrameBytes : 0);
}

void reply(const protocol::Frame& f, ReplyStatus status) {
  if (status != ReplyStatus::ok && g_rejected != 0xFFFF) ++g_rejected;
  const protocol::ReplyMsg r{f.type, f.seq, (uint8_t)status};
  send(MsgType::reply, protocol::encode(r, kPayload));
}

#ifdef WMRA_TEST_HOOKS
// test builds only: a command that hangs the main loop, for the watchdog scenario (S10), and
// one that stalls it for payload[0] ms (under watchdog::kStallCut_ms), for the receive ring's
// overruns: a loop that keeps its ticks reads faster than the line
constexpr uint8_t kTestHangCommand = 0x7F;
constexpr uint8_t kTestStallCommand = 0x7E;
#endif

// a streamed velocity or a move may go on: running, with a stick the person can take it over with
bool motion_allowed(core::ArmState state, uint32_t faults) {
  return state == core::ArmState::running && !(faults & core::fault_mask(core::kFaultBitStickInvalid));
}

ReplyStatus handle(const protocol::Frame& f, Requests& rq) {
#ifdef WMRA_TEST_HOOKS
  if (f.type == kTestHangCommand) {
    for (;;) {
    }
  }
  if (f.type == kTestStallCommand && f.len == 1) {
    const uint32_t end_ms = tick::now_ms() + f.payload[0];
    while ((int32_t)(tick::now_ms() - end_ms) < 0) {
    }
    return ReplyStatus::ok;
  }
#endif
  const ReplyStatus check = protocol::check_command(f);
  if (check != ReplyStatus::ok) return check;
  switch ((MsgType)f.type) {
    case MsgType::cmd_stop:
      rq.stop = true;
      return ReplyStatus::ok;
    case MsgType::cmd_rearm: {
      const core::ArmState state = condition().state;
      if (state != core::ArmState::stopped && state != core::ArmState::fault) return ReplyStatus::refused;
      if (inputs::safety_pressed()) return ReplyStatus::safety_held;  // the supervisor would stay stopped
      rq.rearm = true;
      return ReplyStatus::ok;
    }
    case MsgType::cmd_mode:
      return select_mode((config::Mode)f.payload[0]) ? ReplyStatus::ok : ReplyStatus::refused;
    case MsgType::cmd_speed_scale:
      set_speed_scale(f.payload[0]);
      return ReplyStatus::ok;
    case MsgType::cmd_home:
      if (!core::accepts_home(condition().state)) return ReplyStatus::refused;
      rq.home = true;
      return ReplyStatus::ok;
    case MsgType::cmd_goto_pose: {
      // not from a closed limit switch: a move would not keep off it (the stick drives off it)
      const Condition c = condition();
      if (!motion_allowed(c.state, c.faults) || (c.switches & kSwitchesArmed) || !pose_valid(f.payload[0]))
        return ReplyStatus::refused;
      rq.goto_slot = (int8_t)f.payload[0];
      return ReplyStatus::ok;
    }
    case MsgType::cmd_store_pose:
      return store_pose(f.payload[0]) ? ReplyStatus::ok : ReplyStatus::refused;
    case MsgType::cmd_velocity: {
      // every command keeps its stream arriving, a refused one too: a stream ended stays ended
      // while its commands come (with the stick deflected it would be taken over at once)
      g_velocity_age_ms = 0;
      const Condition c = condition();
      if (!motion_allowed(c.state, c.faults) || c.stick_q15[0] != 0 || c.stick_q15[1] != 0) g_stream_ended = true;
      if (g_stream_ended) return ReplyStatus::refused;
      protocol::VelocityCmd v;
      protocol::decode(f, v);  // (check_command has checked its length)
      core::limit_length(v.v_mm_s, kMaxHand_mm_s);
      core::limit_length(v.w_mrad_s, kMaxWrist_mrad_s);
      for (uint8_t i = 0; i < 3; ++i) {
        rq.v_mm_s[i] = v.v_mm_s[i];
        rq.w_mrad_s[i] = v.w_mrad_s[i];
      }
      return ReplyStatus::ok;
    }
    case MsgType::cmd_jog: {
      // before homing (the arm waits for the person), or running with nothing else under way;
      // the stick neutral throughout (deflected, it ends the jog: no command is accepted then);
      // one joint a jog (another's command waits until this one is over)
      protocol::JogCmd jog{};
      protocol::decode(f, jog);
      g_jog_age_ms = 0;
      const Condition c = condition();
      const bool stick_rests = c.stick_q15[0] == 0 && c.stick_q15[1] == 0 && !(c.faults & core::fault_mask(core::kFaultBitStickInvalid));
      const bool jogging = c.state == core::ArmState::jog;
      const bool may = c.state == core::ArmState::wait_home || (c.state == core::ArmState::running && !c.busy) ||
                       (jogging && jog.joint == rq.jog_joint);
      // (another joint's command while a jog goes on waits for it to end: no jog of its own ended)
      g_jog_ended |= !stick_rests || (!may && !jogging);
      if (g_jog_ended || !may) return ReplyStatus::refused;
      rq.jog_joint = jog.joint;
      rq.jog_mrad_s = jog.speed_mrad_s;
      rq.jog_new = true;
      return ReplyStatus::ok;
    }
    case MsgType::cmd_pot_calibration: {
      protocol::PotCalibrationCmd c{};
      protocol::decode(f, c);
      const CalibrationChange change = calibrate_pot(c.joint, c.at_min_counts_x16, c.at_max_counts_x16);
      if (change == CalibrationChange::ok) g_send_after_reply |= kSendCalibration;
      return change == CalibrationChange::ok        ? ReplyStatus::ok
             : change == CalibrationChange::refused ? ReplyStatus::refused
                                                    : ReplyStatus::bad_argument;
    }
    case MsgType::cmd_get_calibration:
      g_send_after_reply |= kSendCalibration;
      return ReplyStatus::ok;
    case MsgType::cmd_info:
      g_send_after_reply |= kSendInfo;
      return ReplyStatus::ok;
    case MsgType::cmd_stick_centre:
      return store_stick_centre(f.payload[0] != 0) ? ReplyStatus::ok : ReplyStatus::refused;
    default:
      break;
  }
  return ReplyStatus::unknown_command;
}

// The state frame is built over three ticks, from the report of the first: built at once it took
// about 8,000 cycles on top of that tick's iteration (the report ~1,500, the fields' conversions
// ~3,500, the CRC and the transmit buffer ~2,800), more than a tick's budget leaves (docs/performance.md).
//   gather   the report copied (one tick's state), the time
//   convert  the fields into the message, in a frame buffer of its own (replies go meanwhile)
//   send     the CRC and the transmit buffer
enum class StateStage : uint8_t { idle, convert, send };
StateStage g_state_stage = StateStage::idle;
Status g_state;            // the report the frame carries
uint32_t g_state_t_ms;     // and when it was taken
FrameBuffer g_state_frame;

// After a state frame was dropped, for kStateRoomHold_ms: room kept for each next one from
// kStateRoomLead_ms before it is due until it is sent (the line drains a frame in 6 ms)
constexpr uint8_t kStateRoomLead_ms = 8;
constexpr uint16_t kStateRoomHold_ms = 5000;
static_assert(kStateRoomLead_ms * board::kSerialBaud / 10 / 1000 >= kStateFrameBytes + 10, "the lead drains a state frame and a reply");
uint16_t g_state_room_ms;  // > 0: a state frame was dropped this recently
bool keep_room_for_state() {
  return g_state_room_ms != 0 &&
         (g_state_stage != StateStage::idle || (int32_t)(tick::now_ms() + kStateRoomLead_ms - g_next_state_ms) >= 0);
}

void gather_state() {
  g_state = status();
  g_state_t_ms = tick::now_ms();
  if (!motion_allowed(g_state.state, g_state.faults)) g_stream_ended = true;  // a stop between two commands of the stream
}

void convert_state() {
  const Status& s = g_state;
  protocol::StateMsg& m = g_state_frame.state.msg;  // every field is set below
  m.t_ms = g_state_t_ms;
  m.state = (uint8_t)s.state;
  m.mode = (uint8_t)s.mode;
  m.faults = s.faults;
  m.slowed_by = s.slowed_by;
  m.reset_cause = g_reset_cause;
  m.switches = s.switches;
  for (uint8_t j = 0; j < 6; ++j) {
    m.q_mrad[j] = mrad(s.q_measured[j]);
    m.qd_mrad_s[j] = mrad_s(s.qd_rad_s[j]);
  }
  m.p_0p1mm[0] = tenth_mm(s.p_m.x);
  m.p_0p1mm[1] = tenth_mm(s.p_m.y);
  m.p_0p1mm[2] = tenth_mm(s.p_m.z);
  m.stick_permille[0] = permille(s.stick_q15[0]);
  m.stick_permille[1] = permille(s.stick_q15[1]);
  m.speed_scale_pct = s.speed_scale_pct;
  m.loop_cycles_max = g_loop_cycles_max;
  m.rx_crc_errors = g_parser.crc_errors();
  m.rx_framing_errors = g_parser.framing_errors();
  m.rx_rejected = g_rejected;
  m.rx_overruns = uart::rx_overruns();
  g_loop_cycles_max = 0;
}

void send_state() {
  const uint8_t n = protocol::write_frame((uint8_t)MsgType::state, g_seq++, g_state_frame.bytes + protocol::kHeaderBytes,
                                          (uint8_t)sizeof(protocol::StateMsg), g_state_frame.bytes);
  if (!uart::write(g_state_frame.bytes, n)) g_state_room_ms = kStateRoomHold_ms;
}

// the calibration frame, then the info frame, as asked; one not sent is sent on a later tick,
// nothing is lost, so it gives its number back (no gap)
void send_after_reply() {
  if (g_send_after_reply & kSendCalibration) {
    if (!send(MsgType::calibration, protocol::encode(calibration(), kPayload))) {
      --g_seq;
      return;
    }
    g_send_after_reply &= (uint8_t)~kSendCalibration;
  }
  if (g_send_after_reply & kSendInfo) {
    memcpy_P(kPayload, &kInfoInFlash, sizeof(protocol::InfoMsg));
    if (!send(MsgType::info, (uint8_t)sizeof(protocol::InfoMsg))) {
      --g_seq;
      return;
    }
    g_send_after_reply &= (uint8_t)~kSendInfo;
  }
}

// At most kMaxRxStepsPerTick of the parser's steps a tick, each a byte from the receive ring
// (kMaxRxBytesPerTick of them at most) or one held again after a failed frame: a rescan leaves
// the line's bytes waiting in the ring, it does not lengthen the tick. With every byte read and
// looked at, the line's silence drops a partial frame (kByteGap_ms).
void receive(Requests& rq) {
  if (!uart::received()) g_parser.line_quiet(g_quiet_ms);
  uint8_t bytes = config::kMaxRxBytesPerTick, byte;
  for (uint8_t n = config::kMaxRxStepsPerTick; n > 0; --n) {
    bool complete;
    if (g_parser.caught_up()) {
      if (bytes == 0 || !uart::read(byte)) return;
      --bytes;
      complete = g_parser.feed(byte);
    } else {
      complete = g_parser.step();
    }
    if (complete) reply(g_parser.frame(), handle(g_parser.frame(), rq));
  }
}

}  // namespace

void start(uint8_t reset_cause, uint8_t calibration) {
  g_reset_cause = reset_cause;
  protocol::BootMsg b;
  b.reset_cause = reset_cause;
  b.calibration = calibration;
  memcpy_P(&b.identity, &kInfoInFlash.identity, sizeof b.identity);  // (a constant copied would take RAM)
  send(MsgType::boot, protocol::encode(b, kPayload));
}

// receive(), handle() and send_state() are not inlined here: the registers they need (the
// parser's, inlined in receive()) would be saved and restored on every tick, for a command or
// a frame that comes every few ticks at most.
void poll(Requests& rq, uint8_t ticks, uint16_t loop_cycles) {
  if (loop_cycles > g_loop_cycles_max) g_loop_cycles_max = loop_cycles;
  // the line's silence: a byte came in (poll before, poll now], or none for these ticks
  const uint8_t arrived = uart::arrived();
  g_quiet_ms = arrived != g_arrived ? 0 : (uint8_t)(g_quiet_ms + ticks < 0xFF ? g_quiet_ms + ticks : 0xFF);
  g_arrived = arrived;
  if (uart::received() || g_parser.holding()) receive(rq);
  if (g_send_after_reply) send_after_reply();
  g_state_room_ms = g_state_room_ms > ticks ? (uint16_t)(g_state_room_ms - ticks) : 0;
  if (g_velocity_age_ms < 0xFF00) g_velocity_age_ms = (uint16_t)(g_velocity_age_ms + ticks);
  const bool arriving = g_velocity_age_ms < protocol::kVelocityTimeout_ms;
  g_stream_ended = (g_stream_ended | rq.stream_taken_over) & arriving;
  rq.stream_taken_over = false;
  rq.velocity_fresh = arriving & !g_stream_ended;
  g_jog_age_ms = g_jog_age_ms > 0xFF - ticks ? (uint8_t)0xFF : (uint8_t)(g_jog_age_ms + ticks);
  const bool jogs_arriving = g_jog_age_ms < protocol::kVelocityTimeout_ms;
  g_jog_ended &= jogs_arriving;
  rq.jog_fresh = jogs_arriving & !g_jog_ended;
  // one frame per period, after the first iteration at or past its start (every 20 ms from
  // boot, so the frames keep their phase whatever the iterations' lengths): the state of the
  // iteration just run, one tick's, sent two ticks later; a period missed whole is skipped, not
  // sent twice
  if (g_state_stage == StateStage::convert) {
    convert_state();
    g_state_stage = StateStage::send;
  } else if (g_state_stage == StateStage::send) {
    send_state();
    g_state_stage = StateStage::idle;
  }
  const uint32_t now_ms = tick::now_ms();
  if (g_state_stage == StateStage::idle && (int32_t)(now_ms - g_next_state_ms) >= 0) {
    g_next_state_ms += protocol::kStatePeriod_ms;
    if ((int32_t)(now_ms - g_next_state_ms) >= 0) g_next_state_ms = now_ms - now_ms % protocol::kStatePeriod_ms + protocol::kStatePeriod_ms;
    gather_state();
    g_state_stage = StateStage::convert;
  }
}

}  // namespace link
}  // namespace app
}  // namespace wmra
