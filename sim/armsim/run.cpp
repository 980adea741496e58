#include "run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <system_error>

#include "armsim/firmware_telemetry.h"
#include "armsim/json.h"
#include "armsim/report.h"
#include "kinematics/forward_kinematics.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace armsim {

namespace {

using D = kin::Floating<double>;

FILE* open_for_writing(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  return f;
}

// "0xADDR cycles" per instruction that took any (byte address), after the header
void write_profile(const std::string& path, const std::vector<uint64_t>& cycles, const std::string& header) {
  FILE* f = open_for_writing(path);
  std::fputs(header.c_str(), f);
  for (size_t word = 0; word < cycles.size(); ++word)
    if (cycles[word]) std::fprintf(f, "0x%zx %llu\n", 2 * word, (unsigned long long)cycles[word]);
  if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + path);
}

// one summary.json line: "  \"key\": [\"a\", \"b\"],"
void write_string_list(FILE* f, const char* key, const std::vector<std::string>& list) {
  std::fprintf(f, "  \"%s\": [", key);
  for (size_t i = 0; i < list.size(); ++i) std::fprintf(f, "%s%s", i ? ", " : "", json_string(list[i]).c_str());
  std::fprintf(f, "],\n");
}

}  // namespace

void apply_event(sim::ArmSimulator& sim, const Event& e) {
  switch (e.kind) {
    case Event::Kind::joystick: sim.set_joystick(e.x, e.y); break;
    case Event::Kind::button_press:
    case Event::Kind::button_down: sim.set_button(true); break;
    case Event::Kind::button_up: sim.set_button(false); break;
    case Event::Kind::estop_down: sim.set_estop(true); break;
    case Event::Kind::estop_up: sim.set_estop(false); break;
    case Event::Kind::pot_fault:
      sim.set_pot_fault(e.joint - 1, e.fault == 1 ? plant::PotFault::open
                                     : e.fault == 2 ? plant::PotFault::shorted
                                                    : plant::PotFault::ok);
      break;
    case Event::Kind::joystick_fault: sim.set_joystick_unplugged(e.fault == 1); break;
    case Event::Kind::serial: sim.send_serial(e.bytes); break;
  }
}

void make_directories(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create " + dir + ": " + error.message());
  if (!std::filesystem::is_directory(dir)) throw std::runtime_error("cannot create " + dir + ": a file of that name is in the way");
}

TrajectoryRow trajectory_row(double t_s, const std::array<double, 6>& q, int mode, int state) {
  kin::JointAngles<D> a;
  for (int j = 0; j < 6; ++j) a.q[j] = q[j];
  const auto pose = kin::forward_kinematics<D>(a);
  TrajectoryRow row{t_s, q, {pose.p_m.x, pose.p_m.y, pose.p_m.z}, {}, mode, state};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) row.r[3 * r + c] = pose.R[r][c];
  return row;
}

RunResult run_scenario(const Scenario& scenario, const RunOptions& options, const RowCallback& on_row) {
  if (options.sample_hz < 100) throw std::invalid_argument("trajectory rows: at least 100 per simulated second");
  if (!options.out_dir.empty()) make_directories(options.out_dir);
  sim::SimConfig config;
  config.elf = options.elf;
  config.plant = options.plant;
  if (scenario.has_init) config.initial_q = scenario.init_q;
  if (options.vcd && !options.out_dir.empty()) config.vcd_path = options.out_dir + "/trace.vcd";
  config.profile = options.profile && !options.out_dir.empty();
  if (!options.out_dir.empty()) config.profile_over_cycles = options.profile_over_cycles;

  RunResult result;
  sim::ArmSimulator sim(config);
  if (!options.eeprom.empty()) sim.set_eeprom(options.eeprom);
  FirmwareTelemetry own_telemetry;
  TelemetryDecoder& telemetry = options.telemetry ? *options.telemetry : own_telemetry;
  size_t uart_fed = 0;
  auto feed_telemetry = [&](const std::vector<uint8_t>& out) {
    for (; uart_fed < out.size(); ++uart_fed) telemetry.feed(out[uart_fed]);
  };
  auto row_now = [&](const sim::ArmSimulator& s) {
    feed_telemetry(s.uart_output());
    // the row's time is the nominal sample time: rows come at exact plant steps
    const double t_s = std::round(s.time_s() * options.sample_hz) / options.sample_hz;
    result.trajectory.push_back(trajectory_row(t_s, s.q(), telemetry.mode(), telemetry.state()));
    if (on_row) on_row(s, result.trajectory.back());
  };
  sim.every(1.0 / options.sample_hz, row_now);

  std::vector<Event> events = scenario.events;
  // "button press": down now, up 150 ms later (kept in time order)
  for (size_t i = 0; i < events.size(); ++i) {
    if (events[i].kind != Event::Kind::button_press) continue;
    Event up = events[i];
    up.kind = Event::Kind::button_up;
    up.t_s += plant::kButtonPressS;
    size_t at = i + 1;
    while (at < events.size() && events[at].t_s <= up.t_s) ++at;
    events.insert(events.begin() + at, up);
  }
  // Runs the simulator to t_s: at once, or slice by slice through the live hook, which may end
  // the run on the way
  enum class Reached { time, crash, interruption };
  auto advance = [&](double t_s) {
    const uint64_t end_cycle = (uint64_t)std::llround(t_s * board::kCpuHz);
    if (!options.live) return sim.run_until(t_s) == cpu_Crashed ? Reached::crash : Reached::time;
    const uint64_t slice_cycles = std::max<uint64_t>(1, (uint64_t)std::llround(options.live->slice_s() * board::kCpuHz));
    while (sim.cycle() < end_cycle) {
      const uint64_t next_cycle = std::min(end_cycle, sim.cycle() + slice_cycles);
      if (sim.run_until((double)next_cycle / board::kCpuHz) == cpu_Crashed) return Reached::crash;
      if (!options.live->after_slice(sim)) return Reached::interruption;
    }
    return Reached::time;
  };
  Reached reached = Reached::time;
  for (const Event& e : events) {
    if (e.t_s > scenario.end_s) break;
    if ((reached = advance(e.t_s)) != Reached::time) break;
    apply_event(sim, e);
  }
  if (reached == Reached::time) reached = advance(scenario.end_s);
  result.completed = reached == Reached::time;
  result.interrupted = reached == Reached::interruption;
  result.measurements = sim.measurements();
  result.uart_output = sim.uart_output();
  feed_telemetry(result.uart_output);  // what came after the last row
  result.faults = telemetry.faults();
  result.telemetry = telemetry.summary();

  if (!options.out_dir.empty()) {
    FILE* serial = open_for_writing(options.out_dir + "/serial_out.bin");
    std::fwrite(result.uart_output.data(), 1, result.uart_output.size(), serial);
    std::fclose(serial);
    write_trajectory_csv(options.out_dir + "/trajectory.csv", result.trajectory);
    write_summary_json(options.out_dir + "/summary.json", result, scenario, options);
    // an interrupted run's report ends where the run did, with the events that took place
    Scenario ran = scenario;
    if (result.interrupted) {
      ran.end_s = result.measurements.sim_time_s;
      ran.events.erase(std::remove_if(ran.events.begin(), ran.events.end(), [&](const Event& e) { return e.t_s > ran.end_s; }),
                       ran.events.end());
    }
    write_report_html(options.out_dir + "/report.html", result, ran,
                      options.title.empty() ? "armsim run" : options.title);
    if (config.profile) write_profile(options.out_dir + "/profile.txt", sim.core().profile(), "");
    if (config.profile_over_cycles) {
      for (int bin = 0; bin < 2; ++bin) {
        const std::string header = "# " + std::to_string(sim.core().stretches(bin)) + " iterations\n";
        write_profile(options.out_dir + (bin == 0 ? "/profile-over-even.txt" : "/profile-over-odd.txt"),
                      sim.core().stretch_profile(bin), header);
      }
    }
  }
  return result;
}

void write_trajectory_csv(const std::string& path, const std::vector<TrajectoryRow>& rows) {
  FILE* f = open_for_writing(path);
  std::fputs("t,q1,q2,q3,q4,q5,q6,x,y,z,r11,r12,r13,r21,r22,r23,r31,r32,r33,mode,state\n", f);
  for (const auto& r : rows) {
    std::fprintf(f, "%.5f", r.t_s);
    for (double v : r.q) std::fprintf(f, ",%.7f", v);
    for (double v : r.p) std::fprintf(f, ",%.7f", v);
    for (double v : r.r) std::fprintf(f, ",%.7f", v);
    std::fprintf(f, ",%d,%d\n", r.mode, r.state);
  }
  if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + path);
}

void write_summary_json(const std::string& path, const RunResult& result, const Scenario& scenario,
                        const RunOptions& options) {
  const sim::Measurements& m = result.measurements;
  FILE* f = open_for_writing(path);
  std::fprintf(f, "{\n");
  std::fprintf(f, "  \"elf\": %s,\n", json_string(options.elf).c_str());
  std::fprintf(f, "  \"completed\": %s,\n", result.completed ? "true" : "false");
  std::fprintf(f, "  \"interrupted\": %s,\n", result.interrupted ? "true" : "false");
  std::fprintf(f, "  \"sim_time_s\": %.6f,\n", m.sim_time_s);
  std::fprintf(f, "  \"scenario_end_s\": %.6f,\n", scenario.end_s);
  std::fprintf(f, "  \"cycles\": %llu,\n", (unsigned long long)m.cycles);
  std::fprintf(f, "  \"control_loop_cycles\": {\"mean\": %.1f, \"max\": %llu, \"min\": %llu, \"count\": %llu},\n",
               m.loop_high.mean(), (unsigned long long)m.loop_high.max,
               (unsigned long long)(m.loop_high.count ? m.loop_high.min : 0), (unsigned long long)m.loop_high.count);
  std::fprintf(f, "  \"control_loop_own_cycles\": {\"mean\": %.1f, \"max\": %llu},\n", m.loop_own.mean(),
               (unsigned long long)m.loop_own.max);
  std::fprintf(f, "  \"tick_awake_cycles\": {\"mean\": %.1f, \"max\": %llu, \"max_at_s\": %.4f, \"count\": %llu},\n",
               m.tick_awake.mean(), (unsigned long long)m.tick_awake.max, m.tick_awake_max_at_s,
               (unsigned long long)m.tick_awake.count);
  std::fprintf(f, "  \"control_period_cycles\": {\"mean\": %.1f, \"max\": %llu, \"min\": %llu},\n", m.loop_period.mean(),
               (unsigned long long)m.loop_period.max,
               (unsigned long long)(m.loop_period.count ? m.loop_period.min : 0));
  std::fprintf(f, "  \"control_rate_hz\": %.3f,\n", m.control_rate_hz);
  std::fprintf(f, "  \"cpu_load\": %.4f,\n", m.cpu_load);
  static const char* names[3] = {"J1", "J5", "J6"};
  std::fprintf(f, "  \"steps\": {");
  for (int i = 0; i < 3; ++i) {
    const sim::StepperCounts& s = m.steps[i];
    std::fprintf(f,
                 "%s\n    \"%s\": {\"commanded\": %lld, \"lost\": %lld, \"ignored_while_disabled\": %lld, "
                 "\"timing_violations\": %lld}",
                 i ? "," : "", names[i], (long long)s.commanded, (long long)s.lost, (long long)s.ignored,
                 (long long)s.timing_violations);
  }
  std::fprintf(f, "\n  },\n");
  std::fprintf(f, "  \"ram_high_water_bytes\": %u,\n", m.ram_static_bytes + m.stack_bytes);
  std::fprintf(f, "  \"ram_static_bytes\": %u,\n", m.ram_static_bytes);
  std::fprintf(f, "  \"stack_high_water_bytes\": %u,\n", m.stack_bytes);
  std::fprintf(f, "  \"flash_bytes\": %u,\n", m.flash_bytes);
  write_string_list(f, "faults", result.faults);
  write_string_list(f, "sim_faults", m.sim_faults);
  const TelemetrySummary& t = result.telemetry;
  std::fprintf(f, "  \"telemetry\": {\"frames\": %llu, \"crc_errors\": %llu, \"seq_gaps\": %llu, \"replies\": %llu},\n",
               (unsigned long long)t.frames, (unsigned long long)t.crc_errors, (unsigned long long)t.seq_gaps,
               (unsigned long long)t.replies);
  write_string_list(f, "boot_reset_causes", t.boot_reset_causes);
  std::fprintf(f, "  \"resets\": %zu,\n", m.resets.size());
  std::fprintf(f, "  \"reset_log\": [");
  for (size_t i = 0; i < m.resets.size(); ++i) {
    std::fprintf(f, "%s{\"t_s\": %.6f, \"cause\": %s}", i ? ", " : "", m.resets[i].cycle / (double)board::kCpuHz,
                 json_string(m.resets[i].cause).c_str());
  }
  std::fprintf(f, "],\n");
  std::fprintf(f, "  \"isr_cycles\": {");
  bool first = true;
  for (const auto& [name, s] : m.isr) {
    std::fprintf(f, "%s\n    \"%s\": {\"count\": %llu, \"max\": %llu, \"mean\": %.1f}", first ? "" : ",", name.c_str(),
                 (unsigned long long)s.count, (unsigned long long)s.max_cycles, (double)s.total_cycles / s.count);
    first = false;
  }
  std::fprintf(f, "%s},\n", first ? "" : "\n  ");
  std::fprintf(f, "  \"estop\": [");
  for (size_t i = 0; i < m.estop.size(); ++i) {
    const sim::EstopReaction& e = m.estop[i];
    std::fprintf(f, "%s{\"pressed_s\": %.6f, ", i ? ", " : "", e.pressed_s);
    if (e.bridges_off_s >= 0) {
      std::fprintf(f, "\"bridges_off_s\": %.6f, \"reaction_s\": %.6f, ", e.bridges_off_s, e.bridges_off_s - e.pressed_s);
    } else {
      std::fprintf(f, "\"bridges_off_s\": null, \"reaction_s\": null, ");
    }
    std::fprintf(f, "\"trains_stopped_s\": %.6f, \"steps_after\": [%lld, %lld, %lld]}", e.trains_stopped_s(),
                 (long long)e.trains[0].steps, (long long)e.trains[1].steps, (long long)e.trains[2].steps);
  }
  std::fprintf(f, "],\n");
  std::fprintf(f, "  \"uart\": {\"tx_bytes\": %llu, \"rx_bytes\": %llu, \"rx_dropped\": %llu},\n",
               (unsigned long long)m.uart_tx_bytes, (unsigned long long)m.uart_rx_bytes,
               (unsigned long long)m.uart_rx_dropped);
  std::fprintf(f, "  \"trajectory_rows\": %zu,\n", result.trajectory.size());
  std::fprintf(f, "  \"seed\": %llu,\n", (unsigned long long)options.plant.seed);
  std::fprintf(f, "  \"simavr_log\": {");
  first = true;
  for (const auto& [line, count] : m.simavr_log) {
    std::fprintf(f, "%s\n    %s: %d", first ? "" : ",", json_string(line).c_str(), count);
    first = false;
  }
  std::fprintf(f, "%s}\n}\n", first ? "" : "\n  ");
  if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + path);
}

}  // namespace armsim
}  // namespace wmra
