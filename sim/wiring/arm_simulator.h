// The virtual arm: a firmware ELF running on the ATmega2560 in simavr, wired through the pin
// map of boards/wmra_mega/board.h to the plant models of sim/plant.
//
//   DRV8825 STEP/DIR/EN  <- the pins (STEP through Timer5's compare outputs or the port)
//   BTS7960 L/R          <- duty decoded from the timer registers (or the port bit)
//   pots, joystick axes  -> the ADC, sampled when the firmware starts a conversion
//   limit switches, buttons -> input pins (interrupts fire as on the chip)
//   UART0                <-> captured output, injected input at 115200 baud
//   D49 timing probe     -> control-loop time and rate
//
// Time: the plant steps every 320 cycles (20 us) on a simavr cycle timer, so it keeps exact
// time while the CPU sleeps. Everything is deterministic for an ELF, a configuration and a
// sequence of inputs: noise is seeded, nothing reads the wall clock.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "wiring/avr_core.h"
#include "wiring/timer_decode.h"
#include "wiring/vcd.h"
#include "plant/arm_plant.h"
#include "wmra_mega/board.h"
#include "sim_irq.h"

namespace wmra {
namespace sim {

struct SimConfig {
  std::string elf;
  plant::PlantConfig plant;
  plant::Joints initial_q{};  // true joint angles at power-up, rad
  uint32_t serial_baud = 115200;
  std::string vcd_path;  // empty: no trace
  bool profile = false;  // count cycles per instruction (AvrCore::profile)
  // > 0: the same of the control iterations (D49 high) longer than this, by the iteration's
  // parity: the loop alternates its jobs (AvrCore::stretch_profile, bin = count % 2 as loop_high)
  uint64_t profile_over_cycles = 0;
  // MCUSR cleared before the firmware runs, at power-up and after every reset, as the Mega's
  // stock stk500v2 bootloader does (its ~1 s wait after a power-on or external reset and its
  // LED blinks on D13 are not modelled)
  bool stock_bootloader = false;
};

struct CycleStats {
  uint64_t count = 0;
  uint64_t sum = 0;
  uint64_t max = 0;
  uint64_t min = UINT64_MAX;
  void add(uint64_t v) {
    count++;
    sum += v;
    if (v > max) max = v;
    if (v < min) min = v;
  }
  double mean() const { return count ? (double)sum / count : 0.0; }
};

struct StepperCounts {
  int64_t commanded = 0;  // STEP rising edges the driver acted on (microsteps)
  int64_t lost = 0;       // microsteps the rotor slipped (4 full steps per slip)
  int64_t ignored = 0;    // STEP edges while the driver was disabled
  int64_t timing_violations = 0;
};

// A stepper's train after the safety button's press: the stop ends it at once, or (above
// its start/stop rate) slows it down to an end, the driver enabled.
struct TrainAfterStop {
  int64_t steps = 0;          // microsteps taken since the press
  double last_step_s = -1;    // the last one's time; < 0: none
  double last_interval_s = -1;
  // an interval more than 1 ms after the press shorter than the one before by more than a
  // Timer5 tick's jitter (4 us): the train sped up instead of slowing down
  bool sped_up = false;
};
struct EstopReaction {
  double pressed_s;
  double bridges_off_s = -1;  // every bridge at duty 0; < 0: not yet
  std::array<TrainAfterStop, 3> trains;  // J1, J5, J6
  // the last step of any train after the press (the press itself when none stepped): the arm's
  // drives at rest, held
  double trains_stopped_s() const {
    double t = pressed_s;
    for (const TrainAfterStop& k : trains) t = k.last_step_s > t ? k.last_step_s : t;
    return t;
  }
};

struct Measurements {
  double sim_time_s = 0;
  uint64_t cycles = 0;
  CycleStats loop_high;    // D49 high: one control iteration, cycles
  // the same by the iteration's number mod 8: the tick plan's eight ticks (app/tick_plan.h), up
  // to a fixed offset (the loop runs its plan by iteration)
  std::array<CycleStats, 8> loop_high_by_plan_tick;
  // D49 high less the interrupt handlers' cycles that landed in it: the iteration's own work.
  // No handler straddles an edge: D49 is written by the loop, never inside a handler.
  CycleStats loop_own;
  CycleStats loop_period;  // D49 rising to rising, cycles
  double control_rate_hz = 0;
  double cpu_load = 0;     // 1 - cycles asleep / all cycles
  // awake from a wake-up to the next sleep: a tick's whole work (the iteration, the serial link,
  // the interrupts that land in it), cycles; start-ups not counted
  CycleStats tick_awake;
  double tick_awake_max_at_s = 0;  // when the longest ended
  std::array<StepperCounts, 3> steps;  // J1, J5, J6
  uint32_t ram_static_bytes = 0;
  uint32_t stack_bytes = 0;
  uint32_t flash_bytes = 0;
  std::vector<ResetEvent> resets;
  std::map<std::string, IsrStats> isr;  // by vector name
  std::vector<EstopReaction> estop;
  uint64_t uart_tx_bytes = 0;
  uint64_t uart_rx_bytes = 0;
  uint64_t uart_rx_dropped = 0;  // injected while the receiver was off or simavr's buffer full
  std::vector<std::string> sim_faults;  // what the simulator saw go wrong (crash, halt, ...)
  std::map<std::string, int> simavr_log;  // simavr's warnings, with their counts
};

class ArmSimulator {
 public:
  explicit ArmSimulator(const SimConfig& config);
  ~ArmSimulator();
  ArmSimulator(const ArmSimulator&) = delete;
  ArmSimulator& operator=(const ArmSimulator&) = delete;

  // --- the operator's inputs, effective now
  void set_joystick(double x, double y);
  void set_button(bool down);
  void set_estop(bool down);
  void set_joystick_unplugged(bool open);
  void set_pot_fault(int joint, plant::PotFault fault);  // joint index 1..3 (J2..J4)
  // a knock on a stepper joint (0, 4, 5): its rotor turned through whole electrical periods
  void slip_stepper(int joint, int periods) { plant_.slip_stepper(joint, periods); }
  void send_serial(const std::vector<uint8_t>& bytes);   // queued, sent at the line's baud rate
  // The chip's EEPROM from address 0, as an earlier firmware left it (before the first run)
  void set_eeprom(const std::vector<uint8_t>& bytes);
  // The chip's whole EEPROM as it is now (what a board powered off now would find at power-up)
  std::vector<uint8_t> eeprom() const;

  // --- time
  // Runs until the simulated time reaches t_s (or the core stops: halted or crashed).
  int run_until(double t_s);
  double time_s() const;
  uint64_t cycle() const { return core_->cycle(); }
  // calls f at every multiple of period_s, at exact plant-step times (period: a multiple of 20 us)
  void every(double period_s, std::function<void(const ArmSimulator&)> f);

  // --- what there is to see
  plant::Joints q() const { return plant_.q(); }
  const plant::ArmPlant& plant() const { return plant_; }
  const AvrCore& core() const { return *core_; }
  const std::vector<uint8_t>& uart_output() const { return uart_tx_; }
  double bridge_duty(int joint, bool left) const;  // DC joint 1..3, last applied
  bool outputs_off() const;  // every bridge at 0 and every DRV8825 disabled (a hang's cut)
  bool bridges_off() const;  // every bridge at 0 (braking: both sides low)
  bool drivers_enabled() const;  // every DRV8825 enabled (holding its motor)
  double gripper_pulse_us() const;  // the servo pulse on D13 (Timer1 OC1C), 0 when off
  Measurements measurements() const;
  // tick_awake counts from now on (a test's window)
  void reset_tick_awake();

 private:
  struct OutPin;
  struct Compare;
  struct InPin;
  struct Stepper;
  struct Bridge;

  static avr_cycle_count_t plant_tick(avr_t* avr, avr_cycle_count_t when, void* param);
  static avr_cycle_count_t uart_tick(avr_t* avr, avr_cycle_count_t when, void* param);
  static void on_output_irq(avr_irq_t* irq, uint32_t value, void* param);
  static void on_compare(avr_irq_t* irq, uint32_t value, void* param);
  static void on_timer5_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param);
  static void on_adc_trigger(avr_irq_t* irq, uint32_t value, void* param);
  static void on_uart_out(avr_irq_t* irq, uint32_t value, void* param);
  static void on_uart_flow(avr_irq_t* irq, uint32_t value, void* param);

  void wire();
  void watch(avr_irq_t* irq, bool steppers, bool probe);
  void after_reset();
  void plant_step(uint64_t when);
  void update_outputs(bool steppers, bool probe);
  void apply_inputs();
  void declare_external(board::Port port);
  void check_estop();
  void note_step_after_estop(int joint, double t_s);
  bool out_level(const OutPin& p) const;
  bool compare_level(const OutPin& p, const Compare& c, const m2560::TimerSnapshot& timer) const;
  double compare_duty(const Bridge& b, bool left) const;

  SimConfig config_;
  std::unique_ptr<AvrCore> core_;
  plant::ArmPlant plant_;
  uint64_t step_cycles_;
  std::vector<std::unique_ptr<Compare>> compares_;
  Compare* gripper_ = nullptr;
  std::vector<std::unique_ptr<Stepper>> steppers_;
  std::vector<std::unique_ptr<Bridge>> bridges_;
  std::vector<std::unique_ptr<InPin>> inputs_;
  std::unique_ptr<OutPin> probe_;
  struct Watch {
    ArmSimulator* sim;
    uint32_t last;
    bool steppers, probe;  // what a change re-evaluates
  };
  std::vector<std::unique_ptr<Watch>> watches_;
  bool probe_level_ = false;
  bool probe_seen_ = false;
  uint64_t first_rise_ = 0, last_rise_ = 0;
  uint64_t isr_cycles_at_rise_ = 0;
  CycleStats loop_high_, loop_own_, loop_period_;
  std::array<CycleStats, 8> loop_high_by_plan_tick_;
  avr_irq_t* adc_irq_ = nullptr;
  avr_irq_t* uart_irq_ = nullptr;
  bool uart_xoff_ = false;
  std::vector<uint8_t> uart_tx_;
  std::vector<uint8_t> uart_queue_;
  size_t uart_next_ = 0;
  uint64_t uart_rx_ = 0, uart_dropped_ = 0;
  uint64_t uart_cycles_x1000_;  // cycles per byte (10 bits), x1000 for exact pacing
  uint64_t uart_origin_ = 0, uart_sent_ = 0;
  bool uart_armed_ = false;
  std::vector<EstopReaction> estop_;
  struct Periodic {
    uint64_t period_cycles;
    uint64_t next_cycle;
    std::function<void(const ArmSimulator&)> f;
  };
  std::vector<Periodic> periodic_;
  std::unique_ptr<VcdWriter> vcd_;
  std::array<int, plant::kJoints> vcd_q_{};
  int vcd_probe_ = -1;
};

}  // namespace sim
}  // namespace wmra
