// An ATmega2560 at 16 MHz in libsimavr (Debian's simavr 1.6), with what can be measured from
// outside the firmware: cycles asleep (CPU load), every interrupt handler's cycles from its
// vector to its RETI, the stack pointer's low-water mark, resets and their causes.
//
// simavr facts handled here (see README, "simavr 1.6"):
//   - its default sleep callback usleep()s to keep real time: replaced, sleep costs no wall time;
//   - its UARTs poll-sleep and print lines on the console by default: both flags cleared;
//   - avr_reset() (a watchdog bite) cancels every cycle timer and clears the PIN registers: the
//     reset listeners re-arm what they need (see ArmSimulator);
//   - its external interrupts poll a low pin every cycle in level mode: turned off (see
//     no_level_polling);
//   - writing a one to one flag of a timer's TIFRn clears its other pending flags as well (the
//     chip clears only the flags written with a one): put right, see keep_unwritten_timer_flags;
//   - one avr_run() call executes one instruction (or one sleep interval up to the next cycle
//     timer), then services interrupts: interrupt entry is seen as the PC landing on a vector.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sim_avr.h"
#include "sim_interrupts.h"

namespace wmra {
namespace sim {

struct IsrStats {
  uint64_t count = 0;
  uint64_t total_cycles = 0;
  uint64_t max_cycles = 0;  // vector to the end of RETI, plus the 5-cycle interrupt response
};

struct ResetEvent {
  uint64_t cycle;
  std::string cause;  // "watchdog", "external", "brown-out", "power-on", "jump to 0"
};

class AvrCore {
 public:
  // loads the ELF (exits the process on failure is not an option: throws std::runtime_error)
  explicit AvrCore(const std::string& elf_path);
  ~AvrCore();
  AvrCore(const AvrCore&) = delete;
  AvrCore& operator=(const AvrCore&) = delete;

  avr_t* avr() const { return avr_; }
  uint64_t cycle() const { return avr_->cycle; }
  int state() const { return avr_->state; }
  bool stopped() const { return avr_->state == cpu_Done || avr_->state == cpu_Crashed; }

  // One instruction (or one sleep interval) with the measurements.
  int step();
  // Steps until the cycle counter reaches `cycle` or the core crashes; returns the state. A core
  // halted by sleep with interrupts off keeps its timers (and the watchdog) running.
  int run_until(uint64_t cycle);
  // the cycle the firmware first halted (sleep with interrupts off), 0 if never
  uint64_t halted_at() const { return halted_at_; }

  // --- measurements
  uint64_t sleep_cycles() const { return sleep_cycles_; }
  // Each stretch awake between two sleeps (from the wake-up to the next sleep instruction): in
  // the firmware one tick's work, the interrupts that land in it included. Stretches from a
  // reset to the first sleep (the start-up) are not counted.
  struct AwakeStats {
    uint64_t count = 0, sum = 0, max = 0;
    uint64_t max_ended_at = 0;  // the cycle the longest stretch ended
  };
  const AwakeStats& awake() const { return awake_; }
  void reset_awake() { awake_ = AwakeStats{}; }
  const IsrStats& isr(int vector) const { return isr_[vector]; }
  uint64_t isr_cycles() const { return isr_cycles_; }  // all handlers' cycles, counted at each RETI
  uint16_t min_stack_pointer() const { return min_sp_; }
  uint32_t static_ram_bytes() const { return static_ram_; }  // .data + .bss
  uint32_t stack_high_water_bytes() const;
  uint32_t flash_bytes() const { return flash_bytes_; }
  const std::vector<ResetEvent>& resets() const { return resets_; }
  const std::string& console() const { return console_; }  // bytes written to GPIOR0
  const std::vector<std::string>& log() const { return log_; }  // simavr's warnings and errors

  // Cycles spent at each instruction (indexed by word address), counted from the call on; for
  // finding where the firmware's time goes (armsim --profile, scripts/profile-firmware).
  void enable_profile() { profile_.assign(kFlashWords, 0); }
  const std::vector<uint64_t>& profile() const { return profile_; }
  // The same, of chosen stretches of the run only, summed into one of two bins (armsim
  // --profile-over: the control iterations longer than a budget, by their parity): a stretch
  // runs from begin_stretch() to end_stretch(bin), which keeps it, or drops it with bin -1.
  void begin_stretch();
  void end_stretch(int bin);
  const std::vector<uint64_t>& stretch_profile(int bin) const { return stretches_[bin].cycles; }
  uint64_t stretches(int bin) const { return stretches_[bin].count; }

  // called after each reset (watchdog or jump to 0), once the core is ready to run again
  void on_reset(std::function<void()> listener) { reset_listeners_.push_back(std::move(listener)); }

 private:
  static void sleep_hook(avr_t* avr, avr_cycle_count_t how_long);
  static void reset_hook(avr_t* avr);
  static void console_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param);
  static void logger(avr_t* avr, const int level, const char* format, va_list ap);
  void after_reset(const std::string& cause);
  std::string watchdog_cause() const;
  void no_level_polling();
  void keep_unwritten_timer_flags();
  static void on_flag_pending(avr_irq_t* irq, uint32_t value, void* param);
  static void on_tifr_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param);

  avr_t* avr_ = nullptr;
  void (*core_reset_)(avr_t*) = nullptr;
  avr_run_t run_callback_ = nullptr;
  uint64_t sleep_cycles_ = 0;
  AwakeStats awake_;
  uint64_t woke_at_ = 0;
  bool slept_since_reset_ = false;
  uint64_t isr_cycles_ = 0;
  IsrStats isr_[64];
  struct Active {
    int vector;
    uint64_t entry_cycle;
  };
  std::vector<Active> active_;
  uint16_t min_sp_ = 0xFFFF;
  uint32_t static_ram_ = 0;
  uint32_t flash_bytes_ = 0;
  bool reset_seen_ = false;
  uint64_t halted_at_ = 0;
  std::vector<ResetEvent> resets_;
  std::vector<std::function<void()>> reset_listeners_;
  std::string console_;
  std::vector<std::string> log_;
  std::vector<uint64_t> profile_;
  struct StretchBin {
    std::vector<uint64_t> cycles;  // by word address, as profile_
    uint64_t count = 0;
  };
  StretchBin stretches_[2];
  bool in_stretch_ = false;
  std::vector<std::pair<uint32_t, uint32_t>> stretch_;  // the open stretch: (word address, cycles) per instruction
  struct TimerFlag {
    AvrCore* core;
    avr_int_vector_t* vector;
    bool pending;
    uint64_t cleared_cycle;  // the last time it went from pending to not
  };
  std::vector<std::unique_ptr<TimerFlag>> timer_flags_;
  static constexpr size_t kFlashWords = 128 * 1024;
};

}  // namespace sim
}  // namespace wmra
