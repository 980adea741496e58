// Running a scenario against a firmware image, and the files armsim writes:
//   trajectory.csv  t,q1..q6,x,y,z,r11..r33,mode,state  (true plant angles, pose of frame 6)
//   summary.json    sim_time_s, control_loop_cycles, control_rate_hz, cpu_load, steps,
//                   ram_high_water_bytes, faults, resets, telemetry, and more
//   report.html     the run to look at: the arm in 3D, plots, the summary (report.h)
//   serial_out.bin  what the firmware sent on UART0
//   trace.vcd       with --vcd
//   profile.txt     with --profile
//   profile-over-even.txt, profile-over-odd.txt   with --profile-over CYCLES
// This is the API the scenario tests use: run_scenario() gives the rows and measurements in
// memory, with a callback at every row for checks of their own. armsim --live hands the
// simulator to a LiveHook (live_pty.h) between short slices of simulated time.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "armsim/scenario.h"
#include "plant/arm_plant_config.h"
#include "wiring/arm_simulator.h"

namespace wmra {
namespace armsim {

// What summary.json says of the firmware's telemetry
struct TelemetrySummary {
  uint64_t frames = 0, crc_errors = 0, seq_gaps = 0, replies = 0;
  std::vector<std::string> boot_reset_causes;  // one per boot frame: "watchdog", "power_on+brown_out", "none"
};

// The firmware's telemetry, decoded from its UART output. run_scenario uses
// FirmwareTelemetry (firmware_telemetry.h) unless RunOptions::telemetry names another, for
// instance a FirmwareTelemetry of the test's own, to look at every message afterwards.
class TelemetryDecoder {
 public:
  virtual ~TelemetryDecoder() = default;
  virtual void feed(uint8_t byte) = 0;
  virtual int mode() const = 0;   // -1 until known
  virtual int state() const = 0;  // -1 until known
  virtual std::vector<std::string> faults() const = 0;
  virtual TelemetrySummary summary() const = 0;
};

// Something a run hands the simulator to every slice_s of simulated time, for instance to pace
// it to the wall clock and connect its UART to a host (armsim --live, live_pty.h)
class LiveHook {
 public:
  virtual ~LiveHook() = default;
  virtual double slice_s() const = 0;
  // After each slice; false ends the run there, its files written as at the scenario's end
  virtual bool after_slice(sim::ArmSimulator& sim) = 0;
};

struct RunOptions {
  std::string elf;
  std::string out_dir;   // empty: write no files
  std::string title;     // the report's heading (the scenario's name)
  bool vcd = false;
  bool profile = false;  // write DIR/profile.txt: "0xADDR cycles" per instruction (byte address)
  // > 0: write DIR/profile-over-{even,odd}.txt, profile.txt's lines of the control iterations
  // longer than this many cycles, by the iteration's parity, after a line "# N iterations"
  uint64_t profile_over_cycles = 0;
  double sample_hz = 100;  // trajectory rows per simulated second (>= 100)
  plant::PlantConfig plant;
  TelemetryDecoder* telemetry = nullptr;  // null: a FirmwareTelemetry of run_scenario's own
  std::vector<uint8_t> eeprom;  // what the firmware finds in its EEPROM at power-up (empty: a blank chip)
  LiveHook* live = nullptr;     // null: the run goes as fast as the host computes it
};

struct TrajectoryRow {
  double t_s;
  std::array<double, 6> q;
  std::array<double, 3> p;  // frame-6 origin, base frame, m
  std::array<double, 9> r;  // rotation base <- frame 6, row-major
  int mode, state;
};

struct RunResult {
  std::vector<TrajectoryRow> trajectory;
  sim::Measurements measurements;
  std::vector<std::string> faults;  // reported by the firmware (telemetry)
  TelemetrySummary telemetry;
  std::vector<uint8_t> uart_output;
  bool completed = false;    // ran to the scenario's end (false: the core crashed, or interrupted)
  bool interrupted = false;  // the LiveHook ended it before the scenario's end (a signal)
};

using RowCallback = std::function<void(const sim::ArmSimulator&, const TrajectoryRow&)>;

// Runs the scenario; with out_dir set, creates it (and its parents) first and writes
// trajectory.csv, summary.json, report.html (and trace.vcd) at the end.
// Throws std::runtime_error when the ELF cannot be loaded or the files cannot be written.
RunResult run_scenario(const Scenario& scenario, const RunOptions& options, const RowCallback& on_row = nullptr);

// DIR and its parents, as mkdir -p makes them; throws std::runtime_error saying why not
void make_directories(const std::string& dir);

TrajectoryRow trajectory_row(double t_s, const std::array<double, 6>& q, int mode, int state);
// one event on the simulator now (a button_press as button_down: the caller releases it)
void apply_event(sim::ArmSimulator& sim, const Event& e);
void write_trajectory_csv(const std::string& path, const std::vector<TrajectoryRow>& rows);
void write_summary_json(const std::string& path, const RunResult& result, const Scenario& scenario,
                        const RunOptions& options);

}  // namespace armsim
}  // namespace wmra
