#include "arm_simulator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "atmega2560.h"
#include "wiring/timer_decode.h"
#include "avr_adc.h"
#include "avr_eeprom.h"
#include "avr_ioport.h"
#include "avr_timer.h"
#include "avr_uart.h"
#include "sim_io.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace sim {

namespace b = wmra::board;

// an output of the firmware: the level on the pin is PORT when DDR is output, else what the
// part on the other end pulls it to
struct ArmSimulator::OutPin {
  b::Pin pin;
  avr_irq_t* irq;
  uint16_t ddr, port;
  bool pulled_high;
};

// The chip's output-compare register OCnx of a compare pin: what the pin shows while COMnx
// connects it. simavr 1.6 writes its compare output into the PORT register instead, where a
// read-modify-write of the port by the firmware writes it back: a stale PORT bit then shows
// when the firmware disconnects the compare output (an extra STEP edge, a BTS7960 input left
// high). So the simulator cuts simavr's compare-to-pin connection and keeps OCnx itself.
struct ArmSimulator::Compare {
  ArmSimulator* sim;
  b::ComparePin pin;
  avr_irq_t* compare_irq;
  avr_irq_t* pin_irq;
  bool oc = false;
  // the last high pulse made by compare events (toggle, set, clear), as the pin showed it
  uint64_t rise_cycle = 0, fall_cycle = 0, pulse_cycles = 0;
  // the last compare match (simavr 1.6 can report one twice: see on_compare)
  bool matched = false;
  uint16_t match_ocr = 0;
  uint64_t match_cycle = 0;
};

struct ArmSimulator::Stepper {
  int joint;  // 0, 4, 5
  OutPin en, dir, step;
  Compare* compare;
  bool en_level = true, dir_level = false, step_level = false;
  int vcd_en = -1, vcd_dir = -1, vcd_step = -1;
};

struct ArmSimulator::Bridge {
  int joint;  // 1, 2, 3
  OutPin pin[2];  // left, right
  Compare* compare[2];
  double duty[2] = {0, 0};
  int vcd[2] = {-1, -1};
};

struct ArmSimulator::InPin {
  b::Pin pin;
  avr_irq_t* irq;
  uint16_t pin_reg;
  std::function<bool()> level;  // the level the board puts on the pin now
  int driven = -1;
  int vcd = -1;
};

namespace {

avr_irq_t* pin_irq(avr_t* avr, b::Pin p) {
  return avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(m2560::port_letter(p.port)), p.bit);
}

m2560::TimerSnapshot snapshot(const avr_t* avr, b::Timer timer) {
  const m2560::TimerRegisters& r = m2560::timer_registers(timer);
  auto read = [&](uint16_t a) -> uint16_t {
    if (!a) return 0;
    return r.sixteen_bit ? (uint16_t)(avr->data[a] | (avr->data[a + 1] << 8)) : avr->data[a];
  };
  m2560::TimerSnapshot s;
  s.tccra = avr->data[r.tccra];
  s.tccrb = avr->data[r.tccrb];
  for (int c = 0; c < 3; ++c) s.ocr[c] = read(r.ocr[c]);
  s.icr = read(r.icr);
  s.sixteen_bit = r.sixteen_bit;
  return s;
}

const char* joint_name(int joint) {
  static const char* names[] = {"J1", "J2", "J3", "J4", "J5", "J6"};
  return names[joint];
}

}  // namespace

ArmSimulator::ArmSimulator(const SimConfig& config)
    : config_(config),
      core_(new AvrCore(config.elf)),
      plant_(config.plant),
      step_cycles_((uint64_t)std::llround(plant::kPlantStepS * board::kCpuHz)) {
  plant_.power_up(config.initial_q);
  uart_cycles_x1000_ = (uint64_t)std::llround(1000.0 * board::kCpuHz * 10 / config.serial_baud);
  if (!config.vcd_path.empty()) {
    vcd_.reset(new VcdWriter(config.vcd_path));
    if (!vcd_->ok()) throw std::runtime_error("cannot write " + config.vcd_path);
  }
  if (config.profile) core_->enable_profile();
  wire();
  core_->on_reset([this] { after_reset(); });
  if (config.stock_bootloader) core_->avr()->data[m2560::kMcusr] = 0;
  avr_cycle_timer_register(core_->avr(), step_cycles_, &ArmSimulator::plant_tick, this);
  apply_inputs();
  update_outputs(true, true);
  if (vcd_) {  // every signal's value at time 0
    for (auto& st : steppers_) {
      vcd_->set(st->vcd_en, 0, st->en_level);
      vcd_->set(st->vcd_dir, 0, st->dir_level);
      vcd_->set(st->vcd_step, 0, st->step_level);
    }
    vcd_->set(vcd_probe_, 0, probe_level_);
    for (auto& br : bridges_) {
      vcd_->set(br->vcd[0], 0, 0.0);
      vcd_->set(br->vcd[1], 0, 0.0);
    }
    const plant::Joints q = plant_.q();
    for (int j = 0; j < plant::kJoints; ++j) vcd_->set(vcd_q_[j], 0, q[j]);
  }
}

ArmSimulator::~ArmSimulator() {
  if (vcd_) vcd_->end_at(core_->cycle());
}

void ArmSimulator::watch(avr_irq_t* irq, bool steppers, bool probe) {
  watches_.emplace_back(new Watch{this, irq->value, steppers, probe});
  avr_irq_register_notify(irq, &ArmSimulator::on_output_irq, watches_.back().get());
}

void ArmSimulator::wire() {
  avr_t* avr = core_->avr();
  // outputs: `watched` pins re-evaluate the steppers' or the probe's levels when they change
  enum Watched { none, stepper, probe };
  auto out_pin = [&](b::Pin p, bool pulled_high, Watched watched) {
    OutPin o{p, pin_irq(avr, p), m2560::ddr_register(p.port), m2560::port_register(p.port), pulled_high};
    if (watched != none) watch(o.irq, watched == stepper, watched == probe);
    return o;
  };
  auto compare = [&](b::ComparePin p) {
    std::unique_ptr<Compare> c(new Compare{this, p,
                                           avr_io_getirq(avr, AVR_IOCTL_TIMER_GETIRQ('0' + (int)p.timer),
                                                         TIMER_IRQ_OUT_COMP + (int)p.channel),
                                           pin_irq(avr, p.pin)});
    avr_unconnect_irq(c->compare_irq, c->pin_irq);
    avr_irq_register_notify(c->compare_irq, &ArmSimulator::on_compare, c.get());
    compares_.push_back(std::move(c));
    return compares_.back().get();
  };
  // the ports of the outputs: a DDR change re-evaluates the levels
  bool port_watched[11] = {};
  auto watch_port = [&](b::Port port) {
    if (port_watched[(int)port]) return;
    port_watched[(int)port] = true;
    watch(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(m2560::port_letter(port)), IOPORT_IRQ_DIRECTION_ALL), true, true);
  };

  // steppers: DRV8825 EN has a pull-up (disabled until driven low), STEP and DIR pull-downs
  const b::StepperPins* pins[3] = {&b::kStepperJ1, &b::kStepperJ5, &b::kStepperJ6};
  for (int slot = 0; slot < 3; ++slot) {
    const b::StepperPins& p = *pins[slot];
    std::unique_ptr<Stepper> s(new Stepper{plant::kStepperJoints[slot], out_pin(p.enable, true, stepper),
                                           out_pin(p.dir, false, stepper), out_pin(p.step.pin, false, stepper),
                                           compare(p.step)});
    for (b::Port port : {p.enable.port, p.dir.port, p.step.pin.port}) watch_port(port);
    if (p.step.timer != b::Timer::t5) throw std::logic_error("the simulator models the STEP outputs on Timer5");
    if (vcd_) {
      const std::string scope = std::string("stepper_") + joint_name(s->joint);
      s->vcd_en = vcd_->wire(scope, "EN_n");
      s->vcd_dir = vcd_->wire(scope, "DIR");
      s->vcd_step = vcd_->wire(scope, "STEP");
    }
    steppers_.push_back(std::move(s));
  }
  const m2560::TimerRegisters& t5 = m2560::timer_registers(b::Timer::t5);
  avr_register_io_write(avr, t5.tccra, &ArmSimulator::on_timer5_write, this);
  avr_register_io_write(avr, t5.tccrc, &ArmSimulator::on_timer5_write, this);

  // BTS7960 inputs have pull-downs
  const b::BridgePins* bridges[3] = {&b::kBridgeJ2, &b::kBridgeJ3, &b::kBridgeJ4};
  for (int i = 0; i < 3; ++i) {
    std::unique_ptr<Bridge> br(new Bridge{plant::kDcJoints[i],
                                          {out_pin(bridges[i]->left.pin, false, none), out_pin(bridges[i]->right.pin, false, none)},
                                          {compare(bridges[i]->left), compare(bridges[i]->right)}});
    if (vcd_) {
      const std::string scope = std::string("bridge_") + joint_name(br->joint);
      br->vcd[0] = vcd_->real(scope, "duty_L");
      br->vcd[1] = vcd_->real(scope, "duty_R");
    }
    bridges_.push_back(std::move(br));
  }

  gripper_ = compare(b::kGripperServo);
  probe_.reset(new OutPin(out_pin(b::kTimingProbe, false, probe)));
  watch_port(b::kTimingProbe.port);
  if (vcd_) vcd_probe_ = vcd_->wire("board", "D49_probe");

  // inputs: limit switches and the joystick button read low while closed; the safety button
  // is normally closed to ground, so it reads high while pressed
  auto in_pin = [&](b::Pin p, const std::string& name, std::function<bool()> level) {
    std::unique_ptr<InPin> in(new InPin{p, pin_irq(avr, p), m2560::pin_register(p.port), std::move(level)});
    if (vcd_) in->vcd = vcd_->wire("inputs", name);
    inputs_.push_back(std::move(in));
  };
  for (int j = 0; j < plant::kJoints; ++j) {
    const b::LimitPins& l = b::kLimits[j];
    const std::string name = std::string(joint_name(j)) + (l.has_high ? "_low_limit" : "_zero");
    in_pin(l.low, name, [this, j] { return !plant_.limit_closed(j, false); });
    if (l.has_high) in_pin(l.high, std::string(joint_name(j)) + "_high_limit", [this, j] { return !plant_.limit_closed(j, true); });
  }
  in_pin(b::kJoystickButton, "joystick_button", [this] { return !plant_.button_closed(); });
  in_pin(b::kSafetyButton, "safety_button", [this] { return plant_.estop_pressed(); });

  if (vcd_) {
    for (int j = 0; j < plant::kJoints; ++j) vcd_q_[j] = vcd_->real("plant", std::string("q") + std::to_string(j + 1));
  }

  adc_irq_ = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, 0);
  avr_irq_register_notify(adc_irq_ + ADC_IRQ_OUT_TRIGGER, &ArmSimulator::on_adc_trigger, this);

  uart_irq_ = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), 0);
  avr_irq_register_notify(uart_irq_ + UART_IRQ_OUTPUT, &ArmSimulator::on_uart_out, this);
  avr_irq_register_notify(uart_irq_ + UART_IRQ_OUT_XON, &ArmSimulator::on_uart_flow, this);
  avr_irq_register_notify(uart_irq_ + UART_IRQ_OUT_XOFF, &ArmSimulator::on_uart_flow, this);
}

// --- outputs

bool ArmSimulator::out_level(const OutPin& p) const {
  const uint8_t* d = core_->avr()->data;
  if (!((d[p.ddr] >> p.pin.bit) & 1)) return p.pulled_high;
  return (d[p.port] >> p.pin.bit) & 1;
}

bool ArmSimulator::compare_level(const OutPin& p, const Compare& c, const m2560::TimerSnapshot& timer) const {
  const avr_t* avr = core_->avr();
  if (!((avr->data[p.ddr] >> p.pin.bit) & 1)) return p.pulled_high;
  const m2560::PinDrive drive = m2560::compare_pin_drive(timer, c.pin.channel);
  if (drive.source == m2560::PinDrive::Source::port) return (avr->data[p.port] >> p.pin.bit) & 1;
  return c.oc;
}

void ArmSimulator::update_outputs(bool steppers, bool probe_pin) {
  const uint64_t cycle = core_->cycle();
  const double t = (double)cycle / board::kCpuHz;
  bool enable_changed = false;
  const m2560::TimerSnapshot timer5 = snapshot(core_->avr(), b::Timer::t5);
  for (auto& s : steppers_) {
    if (!steppers) break;
    const bool en = out_level(s->en), dir = out_level(s->dir), step = compare_level(s->step, *s->compare, timer5);
    if (en == s->en_level && dir == s->dir_level && step == s->step_level) continue;
    enable_changed |= en != s->en_level;
    // DIR before STEP: the driver samples DIR on the STEP edge
    if (vcd_) {
      vcd_->set(s->vcd_en, cycle, en);
      vcd_->set(s->vcd_dir, cycle, dir);
      vcd_->set(s->vcd_step, cycle, step);
    }
    s->en_level = en;
    s->dir_level = dir;
    s->step_level = step;
    if (plant_.set_stepper_pins(s->joint, en, dir, step, t) != 0) note_step_after_estop(s->joint, t);
  }
  const bool probe = out_level(*probe_);
  if (probe_pin && probe != probe_level_) {
    probe_level_ = probe;
    if (vcd_) vcd_->set(vcd_probe_, cycle, probe);
    if (probe) {
      if (probe_seen_) {
        loop_period_.add(cycle - last_rise_);
      } else {
        first_rise_ = cycle;
        probe_seen_ = true;
      }
      last_rise_ = cycle;
      isr_cycles_at_rise_ = core_->isr_cycles();
      if (config_.profile_over_cycles) core_->begin_stretch();
    } else if (probe_seen_) {
      loop_high_by_plan_tick_[loop_high_.count % 8].add(cycle - last_rise_);
      loop_high_.add(cycle - last_rise_);
      loop_own_.add(cycle - last_rise_ - (core_->isr_cycles() - isr_cycles_at_rise_));
      if (config_.profile_over_cycles)
        core_->end_stretch(cycle - last_rise_ > config_.profile_over_cycles ? (int)(loop_high_.count % 2) : -1);
    }
  }
  if (enable_changed) check_estop();
}

double ArmSimulator::compare_duty(const Bridge& br, bool left) const {
  const int i = left ? 0 : 1;
  const OutPin& p = br.pin[i];
  const Compare& c = *br.compare[i];
  const avr_t* avr = core_->avr();
  if (!((avr->data[p.ddr] >> p.pin.bit) & 1)) return 0.0;  // input: the BTS7960 pulls it low
  const m2560::PinDrive drive = m2560::compare_pin_drive(snapshot(avr, c.pin.timer), c.pin.channel);
  switch (drive.source) {
    case m2560::PinDrive::Source::port: return (avr->data[p.port] >> p.pin.bit) & 1;
    case m2560::PinDrive::Source::pwm: return drive.duty;
    default: return c.oc ? 1.0 : 0.0;
  }
}

double ArmSimulator::bridge_duty(int joint, bool left) const { return bridges_[joint - 1]->duty[left ? 0 : 1]; }

bool ArmSimulator::bridges_off() const {
  for (const auto& br : bridges_) {
    if (compare_duty(*br, true) != 0 || compare_duty(*br, false) != 0) return false;
  }
  return true;
}

bool ArmSimulator::drivers_enabled() const {
  for (const auto& s : steppers_) {
    if (out_level(s->en)) return false;
  }
  return true;
}

bool ArmSimulator::outputs_off() const {
  if (!bridges_off()) return false;
  for (const auto& s : steppers_) {
    if (!out_level(s->en)) return false;
  }
  return true;
}

double ArmSimulator::gripper_pulse_us() const {
  const avr_t* avr = core_->avr();
  const b::ComparePin& g = gripper_->pin;
  if (!((avr->data[m2560::ddr_register(g.pin.port)] >> g.pin.bit) & 1)) return 0;
  const m2560::TimerSnapshot t = snapshot(avr, g.timer);
  const m2560::PinDrive drive = m2560::compare_pin_drive(t, g.channel);
  if (drive.source == m2560::PinDrive::Source::pwm) {
    static const int prescale[8] = {0, 1, 8, 64, 256, 1024, 0, 0};
    const m2560::TimerMode mode = m2560::timer_mode(t);
    const double tick_us = prescale[t.tccrb & 7] * 1e6 / board::kCpuHz;
    const double period_us = (mode.wave == m2560::Wave::fast_pwm ? mode.top + 1.0 : 2.0 * mode.top) * tick_us;
    return drive.duty * period_us;
  }
  // pulses timed by compare events: the last one measured, while the frames keep coming (a
  // hobby servo's frame is 20 ms; one missing frame and a half means the pulse has stopped)
  constexpr double kFrameTimeout_s = 0.03;
  const uint64_t last_edge = std::max(gripper_->rise_cycle, gripper_->fall_cycle);
  if (gripper_->pulse_cycles == 0 || core_->cycle() - last_edge > (uint64_t)(kFrameTimeout_s * board::kCpuHz)) return 0;
  return gripper_->pulse_cycles * 1e6 / board::kCpuHz;
}

// --- inputs

void ArmSimulator::apply_inputs() {
  const uint64_t cycle = core_->cycle();
  bool changed[11] = {};
  for (auto& in : inputs_) {
    const int level = in->level() ? 1 : 0;
    if (level == in->driven) continue;
    in->driven = level;
    changed[(int)in->pin.port] = true;
    if (vcd_) vcd_->set(in->vcd, cycle, level != 0);
  }
  for (int port = 0; port < 11; ++port) {
    if (changed[port]) declare_external((b::Port)port);
  }
  for (auto& in : inputs_) {
    if (changed[(int)in->pin.port]) avr_raise_irq(in->irq, in->driven);
  }
}

// simavr 1.6 raises an input pin with PORT = 1 (pull-up on) to 1 whenever the firmware writes the
// port, whatever drives it from outside, unless the port's "external" state names the pin: so
// every pin the board drives is declared there with its level.
void ArmSimulator::declare_external(b::Port port) {
  avr_ioport_external_t e{};
  e.name = m2560::port_letter(port);
  unsigned mask = 0, value = 0;
  for (const auto& in : inputs_) {
    if (in->pin.port != port || in->driven < 0) continue;
    mask |= 1u << in->pin.bit;
    value |= (unsigned)in->driven << in->pin.bit;
  }
  e.mask = mask;
  e.value = value;
  avr_ioctl(core_->avr(), AVR_IOCTL_IOPORT_SET_EXTERNAL(e.name), &e);
}

void ArmSimulator::set_joystick(double x, double y) { plant_.set_stick(x, y); }
void ArmSimulator::set_joystick_unplugged(bool open) {
  plant_.set_stick_unplugged(open);
  apply_inputs();
}
void ArmSimulator::set_pot_fault(int joint, plant::PotFault fault) { plant_.set_pot_fault(joint, fault); }
void ArmSimulator::set_button(bool down) {
  plant_.set_button(down);
  apply_inputs();
}
void ArmSimulator::set_estop(bool down) {
  plant_.set_estop(down);
  apply_inputs();
  if (down) {
    EstopReaction e;
    e.pressed_s = time_s();
    estop_.push_back(e);
  }
  check_estop();
}

void ArmSimulator::check_estop() {
  if (!estop_.empty() && estop_.back().bridges_off_s < 0 && bridges_off()) estop_.back().bridges_off_s = time_s();
}

void ArmSimulator::note_step_after_estop(int joint, double t_s) {
  if (estop_.empty()) return;
  EstopReaction& e = estop_.back();
  TrainAfterStop& k = e.trains[joint == 0 ? 0 : joint == 4 ? 1 : 2];
  ++k.steps;
  if (k.last_step_s >= 0) {
    const double interval = t_s - k.last_step_s;
    if (k.last_interval_s >= 0 && t_s > e.pressed_s + 1e-3 && interval < k.last_interval_s - 4.5e-6) k.sped_up = true;
    k.last_interval_s = interval;
  }
  k.last_step_s = t_s;
}

void ArmSimulator::send_serial(const std::vector<uint8_t>& bytes) {
  uart_queue_.insert(uart_queue_.end(), bytes.begin(), bytes.end());
  if (!uart_armed_ && uart_next_ < uart_queue_.size()) {
    uart_armed_ = true;
    uart_origin_ = core_->cycle();
    uart_sent_ = 0;
    avr_cycle_timer_register(core_->avr(), 1, &ArmSimulator::uart_tick, this);
  }
}

// --- simavr callbacks

void ArmSimulator::on_output_irq(avr_irq_t*, uint32_t value, void* param) {
  // simavr notifies every pin of a port on each write to it: act on what changed
  Watch* w = static_cast<Watch*>(param);
  if (w->last == value) return;
  w->last = value;
  w->sim->update_outputs(w->steppers, w->probe);
}

void ArmSimulator::on_compare(avr_irq_t*, uint32_t value, void* param) {
  Compare* c = static_cast<Compare*>(param);
  const avr_t* avr = c->sim->core_->avr();
  const m2560::TimerSnapshot t = snapshot(avr, c->pin.timer);
  if (m2560::compare_pin_drive(t, c->pin.channel).source == m2560::PinDrive::Source::events) {
    // simavr 1.6 reschedules every compare of a timer on any OCRnx write, and a compare that
    // matched earlier in the same timer count fires again: another channel's OCR write within
    // 64 cycles of a step edge toggled that STEP pin a second time (2 cycles after its rise),
    // and the pin ran inverted until the next such coincidence (the 20 kHz budget test: 125 ns
    // pulses and an extra step). The chip matches once per count: the repeat is dropped.
    static constexpr uint16_t kPrescale[8] = {0, 1, 8, 64, 256, 1024, 0, 0};
    const uint64_t now = c->sim->core_->cycle();
    const uint16_t ocr = t.ocr[(int)c->pin.channel];
    if (c->matched && ocr == c->match_ocr && now - c->match_cycle < kPrescale[t.tccrb & 7]) return;
    c->matched = true;
    c->match_ocr = ocr;
    c->match_cycle = now;
    // the chip's OCnx: toggle, clear or set on the match (COM = 1, 2, 3)
    const int com = (t.tccra >> m2560::com_shift(c->pin.channel)) & 3;
    const bool was = c->oc;
    c->oc = com == 1 ? !c->oc : com == 3;
    if (c->oc && !was) c->rise_cycle = now;
    if (!c->oc && was) {
      c->pulse_cycles = now - c->rise_cycle;
      c->fall_cycle = now;
    }
  } else {
    c->oc = value & 1;  // PWM modes: simavr's own waveform
  }
  if (c->pin.timer == b::Timer::t5) c->sim->update_outputs(true, false);
}

void ArmSimulator::on_timer5_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param) {
  ArmSimulator* sim = static_cast<ArmSimulator*>(param);
  avr->data[addr] = v;
  const m2560::TimerRegisters& t5 = m2560::timer_registers(b::Timer::t5);
  if (addr == t5.tccrc) {
    // FOC5x: a forced compare applies the COM action to OC5x at once, outside PWM modes
    const m2560::TimerSnapshot t = snapshot(avr, b::Timer::t5);
    for (auto& s : sim->steppers_) {
      Compare& c = *s->compare;
      if (!((v >> (7 - (int)c.pin.channel)) & 1)) continue;
      if (m2560::compare_pin_drive(t, c.pin.channel).source != m2560::PinDrive::Source::events) continue;
      const int com = (t.tccra >> m2560::com_shift(c.pin.channel)) & 3;
      c.oc = com == 1 ? !c.oc : com == 3;
    }
    avr->data[addr] = v & 0x1F;  // FOC bits read as zero
  }
  sim->update_outputs(true, false);
}

void ArmSimulator::on_adc_trigger(avr_irq_t*, uint32_t value, void* param) {
  ArmSimulator* sim = static_cast<ArmSimulator*>(param);
  avr_adc_mux_t mux{};  // simavr raises the mux's first 32 bits (a union with a uint32_t)
  std::memcpy(&mux, &value, sizeof value);
  if (mux.kind != ADC_MUX_SINGLE || mux.src > 7) return;
  const int ch = mux.src;
  double mv = 0;
  if (ch == b::kAdcJoystickX) mv = sim->plant_.sample_stick_mv(0);
  else if (ch == b::kAdcJoystickY) mv = sim->plant_.sample_stick_mv(1);
  else if (ch == b::kAdcPotJ2) mv = sim->plant_.sample_pot_mv(1);
  else if (ch == b::kAdcPotJ3) mv = sim->plant_.sample_pot_mv(2);
  else if (ch == b::kAdcPotJ4) mv = sim->plant_.sample_pot_mv(3);
  avr_raise_irq(sim->adc_irq_ + ADC_IRQ_ADC0 + ch, (uint32_t)std::lround(mv));
}

void ArmSimulator::on_uart_out(avr_irq_t*, uint32_t value, void* param) {
  static_cast<ArmSimulator*>(param)->uart_tx_.push_back((uint8_t)value);
}

void ArmSimulator::on_uart_flow(avr_irq_t* irq, uint32_t, void* param) {
  ArmSimulator* sim = static_cast<ArmSimulator*>(param);
  sim->uart_xoff_ = irq == sim->uart_irq_ + UART_IRQ_OUT_XOFF;
}

avr_cycle_count_t ArmSimulator::uart_tick(avr_t* avr, avr_cycle_count_t, void* param) {
  ArmSimulator* sim = static_cast<ArmSimulator*>(param);
  if (sim->uart_next_ >= sim->uart_queue_.size()) {
    sim->uart_armed_ = false;
    return 0;
  }
  const uint8_t byte = sim->uart_queue_[sim->uart_next_++];
  const bool receiver_on = (avr->data[m2560::kUcsr0b] >> 4) & 1;
  if (receiver_on && !sim->uart_xoff_) {
    avr_raise_irq(sim->uart_irq_ + UART_IRQ_INPUT, byte);
    sim->uart_rx_++;
  } else {
    sim->uart_dropped_++;
  }
  if (sim->uart_next_ == sim->uart_queue_.size()) {
    sim->uart_queue_.clear();
    sim->uart_next_ = 0;
  }
  sim->uart_sent_++;
  // a byte every 10 bit times of the line, paced from when the burst began
  return sim->uart_origin_ + 1 + sim->uart_sent_ * sim->uart_cycles_x1000_ / 1000;
}

avr_cycle_count_t ArmSimulator::plant_tick(avr_t*, avr_cycle_count_t when, void* param) {
  ArmSimulator* sim = static_cast<ArmSimulator*>(param);
  sim->plant_step(when);
  return when + sim->step_cycles_;
}

void ArmSimulator::plant_step(uint64_t when) {
  for (auto& br : bridges_) {
    for (int i = 0; i < 2; ++i) {
      br->duty[i] = compare_duty(*br, i == 0);
      if (vcd_) vcd_->set(br->vcd[i], when, br->duty[i]);
    }
    plant_.set_bridge_duty(br->joint, br->duty[0], br->duty[1]);
  }
  plant_.step((double)step_cycles_ / board::kCpuHz);
  apply_inputs();
  check_estop();
  for (auto& p : periodic_) {
    while (when >= p.next_cycle) {
      p.f(*this);
      p.next_cycle += p.period_cycles;
    }
  }
  if (vcd_ && when % (step_cycles_ * 50) == 0) {  // every millisecond
    const plant::Joints q = plant_.q();
    for (int j = 0; j < plant::kJoints; ++j) vcd_->set(vcd_q_[j], when, q[j]);
  }
}

void ArmSimulator::set_eeprom(const std::vector<uint8_t>& bytes) {
  std::vector<uint8_t> copy(bytes);
  avr_eeprom_desc_t d;
  d.ee = copy.data();
  d.offset = 0;
  d.size = (uint32_t)copy.size();
  // simavr 1.6 answers -1 when it took the image and -2 when it did not
  if (avr_ioctl(core_->avr(), AVR_IOCTL_EEPROM_SET, &d) == -2) throw std::runtime_error("simavr refused the EEPROM image");
}

std::vector<uint8_t> ArmSimulator::eeprom() const {
  avr_t* avr = core_->avr();
  std::vector<uint8_t> bytes(avr->e2end + 1u);
  avr_eeprom_desc_t d;
  d.ee = bytes.data();
  d.offset = 0;
  d.size = (uint32_t)bytes.size();
  if (avr_ioctl(avr, AVR_IOCTL_EEPROM_GET, &d) == -2) throw std::runtime_error("simavr gave no EEPROM image");
  return bytes;
}

void ArmSimulator::after_reset() {
  avr_t* avr = core_->avr();
  if (config_.stock_bootloader) avr->data[m2560::kMcusr] = 0;  // the reset's own cause is in measurements()
  // simavr's reset cancelled every cycle timer and cleared the PIN registers
  avr_cycle_timer_register(avr, step_cycles_ - avr->cycle % step_cycles_, &ArmSimulator::plant_tick, this);
  if (uart_armed_) avr_cycle_timer_register(avr, 1, &ArmSimulator::uart_tick, this);
  bool ports[11] = {};
  for (auto& in : inputs_) {
    if (in->driven < 0) continue;
    uint8_t& reg = avr->data[in->pin_reg];
    reg = (uint8_t)((reg & ~(1u << in->pin.bit)) | ((unsigned)in->driven << in->pin.bit));
    ports[(int)in->pin.port] = true;
  }
  for (int port = 0; port < 11; ++port) {
    if (ports[port]) declare_external((b::Port)port);
  }
  for (auto& c : compares_) {
    c->oc = false;
    avr_unconnect_irq(c->compare_irq, c->pin_irq);  // simavr's timer reset connected them again
  }
  update_outputs(true, true);
}

// --- time

double ArmSimulator::time_s() const { return (double)core_->cycle() / board::kCpuHz; }

int ArmSimulator::run_until(double t_s) {
  return core_->run_until((uint64_t)std::llround(t_s * board::kCpuHz));
}

void ArmSimulator::every(double period_s, std::function<void(const ArmSimulator&)> f) {
  const uint64_t period = (uint64_t)std::llround(period_s * board::kCpuHz);
  if (period == 0 || period % step_cycles_) throw std::invalid_argument("period must be a multiple of the plant step");
  const uint64_t now = core_->cycle();
  periodic_.push_back({period, (now / period + (now % period ? 1 : 0)) * period, std::move(f)});
  if (periodic_.back().next_cycle == 0) {  // time 0 itself: call now
    periodic_.back().f(*this);
    periodic_.back().next_cycle = period;
  }
}

// --- measurements

void ArmSimulator::reset_tick_awake() { core_->reset_awake(); }

Measurements ArmSimulator::measurements() const {
  Measurements m;
  m.cycles = core_->cycle();
  m.sim_time_s = time_s();
  m.loop_high = loop_high_;
  m.loop_high_by_plan_tick = loop_high_by_plan_tick_;
  m.loop_own = loop_own_;
  {
    const AvrCore::AwakeStats& a = core_->awake();
    m.tick_awake.count = a.count;
    m.tick_awake.sum = a.sum;
    m.tick_awake.max = a.max;
    m.tick_awake_max_at_s = (double)a.max_ended_at / board::kCpuHz;
  }
  m.loop_period = loop_period_;
  if (loop_period_.count && last_rise_ > first_rise_) {
    m.control_rate_hz = (double)loop_period_.count * board::kCpuHz / (double)(last_rise_ - first_rise_);
  }
  m.cpu_load = m.cycles ? 1.0 - (double)core_->sleep_cycles() / (double)m.cycles : 0.0;
  for (int slot = 0; slot < 3; ++slot) {
    const int j = plant::kStepperJoints[slot];
    m.steps[slot].commanded = plant_.driver(j).steps_taken();
    m.steps[slot].lost = plant_.stepper(j).microsteps_lost();
    m.steps[slot].ignored = plant_.driver(j).steps_ignored();
    m.steps[slot].timing_violations = plant_.driver(j).timing_violations();
  }
  m.ram_static_bytes = core_->static_ram_bytes();
  m.stack_bytes = core_->stack_high_water_bytes();
  m.flash_bytes = core_->flash_bytes();
  m.resets = core_->resets();
  for (int v = 1; v < m2560::kVectors; ++v) {
    if (core_->isr(v).count) m.isr[m2560::kVectorNames[v]] = core_->isr(v);
  }
  m.estop = estop_;
  m.uart_tx_bytes = uart_tx_.size();
  m.uart_rx_bytes = uart_rx_;
  m.uart_rx_dropped = uart_dropped_;
  if (core_->state() == cpu_Crashed) m.sim_faults.push_back("the core crashed (simavr state crashed)");
  if (core_->halted_at()) {
    m.sim_faults.push_back("the firmware halted (sleep with interrupts off) at " +
                           std::to_string((double)core_->halted_at() / board::kCpuHz) + " s");
  }
  if (core_->min_stack_pointer() < m2560::kRamStart + core_->static_ram_bytes()) {
    m.sim_faults.push_back("stack overflow into static data");
  }
  for (const auto& line : core_->log()) {
    std::string l = line;
    while (!l.empty() && (l.back() == '\n' || l.back() == '\r')) l.pop_back();
    m.simavr_log[l]++;
  }
  return m;
}

}  // namespace sim
}  // namespace wmra
