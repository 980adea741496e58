#include "avr_core.h"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

#include "atmega2560.h"
#include "avr_extint.h"
#include "avr_uart.h"
#include "probe_ports.h"
#include "sim_elf.h"
#include "sim_io.h"

namespace wmra {
namespace sim {

namespace {

AvrCore* core_of(avr_t* avr) { return avr ? static_cast<AvrCore*>(avr->custom.data) : nullptr; }

// libsimavr reports what it loaded on stdout, which may carry a program's output: mute it
int read_elf_quietly(const std::string& path, elf_firmware_t* firmware) {
  std::fflush(stdout);
  const int saved = dup(STDOUT_FILENO);
  const int null_fd = open("/dev/null", O_WRONLY);
  dup2(null_fd, STDOUT_FILENO);
  const int status = elf_read_firmware(path.c_str(), firmware);
  std::fflush(stdout);
  dup2(saved, STDOUT_FILENO);
  close(null_fd);
  close(saved);
  return status;
}

}  // namespace

AvrCore::AvrCore(const std::string& elf_path) {
  elf_firmware_t firmware;
  std::memset(&firmware, 0, sizeof firmware);
  if (access(elf_path.c_str(), R_OK) != 0 || read_elf_quietly(elf_path, &firmware) != 0) {
    throw std::runtime_error("cannot read the firmware image " + elf_path);
  }
  std::strcpy(firmware.mmcu, "atmega2560");
  firmware.frequency = board::kCpuHz;
  avr_global_logger_set(&AvrCore::logger);
  avr_ = avr_make_mcu_by_name(firmware.mmcu);
  if (!avr_) throw std::runtime_error("simavr has no atmega2560 core");
  avr_init(avr_);
  avr_->custom.data = this;
  avr_load_firmware(avr_, &firmware);
  avr_->vcc = avr_->avcc = avr_->aref = 5000;  // mV: the Mega's 5 V, AVcc is the ADC reference
  static_ram_ = firmware.datasize + firmware.bsssize;
  flash_bytes_ = firmware.flashsize;
  std::free(firmware.flash);
  std::free(firmware.eeprom);
  std::free(firmware.fuse);
  std::free(firmware.lockbits);
  for (uint32_t i = 0; i < firmware.symbolcount; ++i) std::free(firmware.symbol[i]);
  std::free(firmware.symbol);

  avr_->sleep = &AvrCore::sleep_hook;
  run_callback_ = avr_->run;
  core_reset_ = avr_->reset;
  avr_->reset = &AvrCore::reset_hook;
  for (char u = '0'; u <= '3'; ++u) {
    uint32_t flags = 0;
    if (avr_ioctl(avr_, AVR_IOCTL_UART_GET_FLAGS(u), &flags) == 0) {
      flags &= ~(uint32_t)(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
      avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS(u), &flags);
    }
  }
  avr_register_io_write(avr_, WMRA_PROBE_CONSOLE_IO + WMRA_PROBE_DATA_OFFSET, &AvrCore::console_write, this);
  no_level_polling();
  keep_unwritten_timer_flags();
  min_sp_ = m2560::kRamEnd;
}

AvrCore::~AvrCore() {
  if (avr_) {
    avr_->custom.data = nullptr;
    avr_terminate(avr_);
  }
}

void AvrCore::sleep_hook(avr_t* avr, avr_cycle_count_t how_long) {
  // simavr then adds 1 + how_long cycles
  AvrCore* c = core_of(avr);
  if (!c) return;
  c->sleep_cycles_ += 1 + how_long;
  if (c->slept_since_reset_) {
    const uint64_t awake = avr->cycle - c->woke_at_;
    ++c->awake_.count;
    c->awake_.sum += awake;
    if (awake > c->awake_.max) {
      c->awake_.max = awake;
      c->awake_.max_ended_at = avr->cycle;
    }
  }
  c->slept_since_reset_ = true;
  c->woke_at_ = avr->cycle + 1 + how_long;
}

void AvrCore::reset_hook(avr_t* avr) {
  AvrCore* c = core_of(avr);
  if (!c) return;
  if (c->core_reset_) c->core_reset_(avr);
  c->reset_seen_ = true;
  c->slept_since_reset_ = false;
}

void AvrCore::console_write(avr_t*, avr_io_addr_t, uint8_t v, void* param) {
  static_cast<AvrCore*>(param)->console_.push_back((char)v);
}

void AvrCore::logger(avr_t* avr, const int level, const char* format, va_list ap) {
  if (level > LOG_WARNING) return;
  char text[512];
  std::vsnprintf(text, sizeof text, format, ap);
  AvrCore* c = core_of(avr);
  if (c && c->log_.size() < 1000) {
    c->log_.push_back(text);
  } else if (!c) {
    std::fputs(text, stderr);
  }
}

uint32_t AvrCore::stack_high_water_bytes() const { return m2560::kRamEnd - min_sp_; }

// simavr polls a low-level external interrupt pin on every cycle while the pin is low, from the
// moment it goes low in level mode (the mode after reset) and, in 1.6, even after the firmware
// has switched that INT to edge mode: the safety button (INT4, low while not pressed) alone
// halves the simulator's speed. Without the polling a level-mode INT fires once per falling
// edge, like an edge interrupt.
void AvrCore::no_level_polling() {
  for (uint8_t i = 0; i < 8; ++i) avr_extint_set_strict_lvl_trig(avr_, i, 0);
}

// simavr 1.6's TIFRn write clears every pending flag of the timer, where the chip clears only
// those written with a one. The firmware starts a step channel by clearing that channel's stale
// compare flag: another channel's compare that had matched meanwhile (interrupts off) was lost,
// and that stepper stood still until its counter came round again, 262 ms later. A hook after
// simavr's (writers of one address run in the order they were registered) raises again every
// flag that this very write cleared without a one in its bit.
void AvrCore::keep_unwritten_timer_flags() {
  // TIFR1 (the tick and the servo pulse) and TIFR5 (the steps): simavr shares an address among
  // writers in one of only four slots
  static constexpr avr_io_addr_t kTifr[] = {0x36, 0x3A};
  for (avr_io_addr_t tifr : kTifr) {
    bool any = false;
    for (uint8_t i = 0; i < avr_->interrupts.vector_count; ++i) {
      avr_int_vector_t* v = avr_->interrupts.vector[i];
      if (v->raised.reg != tifr) continue;
      timer_flags_.emplace_back(new TimerFlag{this, v, false, 0});
      avr_irq_register_notify(v->irq + AVR_INT_IRQ_PENDING, &AvrCore::on_flag_pending, timer_flags_.back().get());
      any = true;
    }
    if (any) avr_register_io_write(avr_, tifr, &AvrCore::on_tifr_write, this);
  }
}

void AvrCore::on_flag_pending(avr_irq_t*, uint32_t value, void* param) {
  TimerFlag* f = static_cast<TimerFlag*>(param);
  if (f->pending && !value) f->cleared_cycle = f->core->avr_->cycle;
  f->pending = value != 0;
}

void AvrCore::on_tifr_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param) {
  AvrCore* core = static_cast<AvrCore*>(param);
  for (auto& f : core->timer_flags_) {
    if (f->vector->raised.reg != addr || f->pending || f->cleared_cycle != avr->cycle) continue;
    if (!((v >> f->vector->raised.bit) & 1)) avr_raise_interrupt(avr, f->vector);
  }
}

std::string AvrCore::watchdog_cause() const {
  const uint8_t mcusr = avr_->data[m2560::kMcusr];
  return (mcusr & 8) ? "watchdog" : (mcusr & 4) ? "brown-out" : (mcusr & 2) ? "external" : "power-on";
}

void AvrCore::after_reset(const std::string& cause) {
  no_level_polling();  // the reset turned it back on
  active_.clear();
  resets_.push_back({avr_->cycle, cause});
  for (auto& listener : reset_listeners_) listener();
}

void AvrCore::begin_stretch() {
  stretch_.clear();
  in_stretch_ = true;
}

void AvrCore::end_stretch(int bin) {
  in_stretch_ = false;
  if (bin < 0) return;
  StretchBin& b = stretches_[bin];
  if (b.cycles.empty()) b.cycles.assign(kFlashWords, 0);
  for (const auto& [word, cycles] : stretch_) b.cycles[word] += cycles;
  b.count++;
}

int AvrCore::step() {
  const avr_flashaddr_t pc = avr_->pc;
  const bool reti = !active_.empty() && avr_->state == cpu_Running &&
                    (avr_->flash[pc] | (avr_->flash[pc + 1] << 8)) == m2560::kReti;
  reset_seen_ = false;
  const uint64_t cycle_before = avr_->cycle;
  const int state = avr_run(avr_);
  if (avr_->state == cpu_Running) {
    if (!profile_.empty()) profile_[(pc >> 1) % kFlashWords] += avr_->cycle - cycle_before;
    if (in_stretch_) stretch_.push_back({(uint32_t)((pc >> 1) % kFlashWords), (uint32_t)(avr_->cycle - cycle_before)});
  }
  if (reset_seen_) {
    after_reset(watchdog_cause());
    return state;
  }
  if (reti) {
    const Active a = active_.back();
    active_.pop_back();
    IsrStats& s = isr_[a.vector];
    const uint64_t cycles = avr_->cycle - a.entry_cycle + m2560::kInterruptResponseCycles;
    s.count++;
    s.total_cycles += cycles;
    isr_cycles_ += cycles;
    if (cycles > s.max_cycles) s.max_cycles = cycles;
  }
  const avr_flashaddr_t now = avr_->pc;
  if (now == 0) {
    if (pc != 0) {
      active_.clear();
      resets_.push_back({avr_->cycle, "jump to 0"});  // not a reset of the chip: no listeners
    }
  } else if (now < m2560::kVectors * m2560::kVectorBytes && now % m2560::kVectorBytes == 0 && !avr_->sreg[S_I]) {
    active_.push_back({(int)(now / m2560::kVectorBytes), avr_->cycle});
  }
  const uint16_t sp = avr_->data[m2560::kSpl] | (avr_->data[m2560::kSph] << 8);
  if (sp < min_sp_) min_sp_ = sp;
  return state;
}

int AvrCore::run_until(uint64_t cycle) {
  while (avr_->cycle < cycle && avr_->state != cpu_Crashed) {
    if (avr_->state != cpu_Done) {
      step();
      continue;
    }
    // Sleep with interrupts off: the CPU is stopped for good, but on the chip the timers, the
    // PWM and the watchdog run on. Advance time through simavr's cycle timers (the plant's
    // included) until a reset wakes the core or the time is up.
    if (!halted_at_) halted_at_ = avr_->cycle;
    reset_seen_ = false;
    const avr_cycle_count_t next = avr_cycle_timer_process(avr_);
    // simavr's watchdog resets the core from avr_run: it swaps in its own run callback
    if (avr_->run != run_callback_) avr_run(avr_);
    if (reset_seen_) {
      after_reset(watchdog_cause());
      continue;
    }
    avr_->cycle = next && avr_->cycle + next < cycle ? avr_->cycle + next : cycle;
  }
  return avr_->state;
}

}  // namespace sim
}  // namespace wmra
