#include "armsim/report.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "armsim/json.h"
#include "armsim/report_page.h"
#include "config/modes_config.h"
#include "core/supervisor.h"
#include "kinematics/arm_model.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace armsim {

namespace {

constexpr double kPlotStepS = 0.01;          // plot samples: 100 Hz of simulated time,
constexpr size_t kMaxPlotSamples = 20000;    // fewer on runs longer than 200 s
constexpr double kFrameStepS = 1.0 / 30;     // animation frames
constexpr int kDerivativeHalfWidth = 2;      // +-20 ms at 100 Hz: smooths microstep quantisation
constexpr double kCpuHz = board::kCpuHz;

const char* mode_name(config::Mode m) {
  switch (m) {
    case config::Mode::xy: return "XY";
    case config::Mode::xz: return "XZ";
    case config::Mode::r1: return "R1";
    case config::Mode::r2: return "R2";
    case config::Mode::gripper: return "gripper";
  }
  return nullptr;
}

std::string format(const char* f, ...) {
  char buf[512];
  va_list args;
  va_start(args, f);
  std::vsnprintf(buf, sizeof buf, f, args);
  va_end(args);
  return buf;
}

// indices of the rows at least step_s apart, the first and the last always in
std::vector<size_t> sample_indices(const std::vector<TrajectoryRow>& rows, double step_s) {
  std::vector<size_t> out;
  double next = -1e300;
  for (size_t i = 0; i < rows.size(); ++i) {
    // rows sit at nominal times, so a tolerance keeps an exact multiple of the step in
    if (rows[i].t_s >= next - 1e-9) {
      out.push_back(i);
      next = rows[i].t_s + step_s;
    }
  }
  if (!rows.empty() && out.back() != rows.size() - 1) out.push_back(rows.size() - 1);
  return out;
}

class Json {
 public:
  void raw(const char* s) { out_ += s; }
  void key(const char* k) {
    if (out_.back() != '{') out_ += ',';
    out_ += json_string(k);
    out_ += ':';
  }
  void string(const std::string& s) { out_ += json_string(s); }
  void number(double v, int decimals) { append_json_number(out_, v, decimals); }
  void numbers(const std::vector<double>& v, int decimals) {
    out_ += '[';
    for (size_t i = 0; i < v.size(); ++i) {
      if (i) out_ += ',';
      number(v[i], decimals);
    }
    out_ += ']';
  }
  template <class Container>
  void strings(const Container& names) {
    out_ += '[';
    bool first = true;
    for (const auto& n : names) {
      if (!first) out_ += ',';
      out_ += json_string(n);
      first = false;
    }
    out_ += ']';
  }
  void field(const char* k, const std::vector<double>& v, int decimals) {
    key(k);
    numbers(v, decimals);
  }
  void field(const char* k, const std::vector<std::vector<double>>& cols, int decimals) {
    key(k);
    out_ += '[';
    for (size_t c = 0; c < cols.size(); ++c) {
      if (c) out_ += ',';
      numbers(cols[c], decimals);
    }
    out_ += ']';
  }
  const std::string& text() const { return out_; }

 private:
  std::string out_;
};

// [[t, value], ...] at the rows where the value changes
void segments(Json& j, const std::vector<TrajectoryRow>& rows, int TrajectoryRow::*field) {
  j.raw("[");
  bool first = true;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (i > 0 && rows[i].*field == rows[i - 1].*field) continue;
    j.raw(first ? "[" : ",[");
    j.number(rows[i].t_s, 4);
    j.raw(",");
    j.number(rows[i].*field, 0);
    j.raw("]");
    first = false;
  }
  j.raw("]");
}

std::string event_label(const Event& e) {
  switch (e.kind) {
    case Event::Kind::joystick: return format("stick %.2f %.2f", e.x, e.y);
    case Event::Kind::button_press: return "button press";
    case Event::Kind::button_down: return "button down";
    case Event::Kind::button_up: return "button up";
    case Event::Kind::estop_down: return "e-stop down";
    case Event::Kind::estop_up: return "e-stop up";
    case Event::Kind::pot_fault:
      return format("pot J%d %s", e.joint, e.fault == 1 ? "open" : e.fault == 2 ? "short" : "ok");
    case Event::Kind::joystick_fault: return e.fault == 1 ? "stick unplugged" : "stick ok";
    case Event::Kind::serial: return format("serial %zu B", e.bytes.size());
  }
  return "?";
}

// the scenario's inputs: the stick as steps, everything else as labelled instants
void inputs(Json& j, const Scenario& scenario) {
  j.key("stick");
  j.raw("[[0,0,0]");
  for (const Event& e : scenario.events) {
    if (e.kind != Event::Kind::joystick) continue;
    j.raw(",[");
    j.number(e.t_s, 4);
    j.raw(",");
    j.number(e.x, 3);
    j.raw(",");
    j.number(e.y, 3);
    j.raw("]");
  }
  j.raw("]");
  j.key("inputs");
  j.raw("[");
  bool first = true;
  for (const Event& e : scenario.events) {
    if (e.kind == Event::Kind::joystick) continue;
    j.raw(first ? "[" : ",[");
    j.number(e.t_s, 4);
    j.raw(",");
    j.string(event_label(e));
    j.raw("]");
    first = false;
  }
  j.raw("]");
}

// [label, value] rows of the summary table
std::vector<std::array<std::string, 2>> summary_rows(const RunResult& result, const Scenario& scenario) {
  const sim::Measurements& m = result.measurements;
  std::vector<std::array<std::string, 2>> rows;
  rows.push_back({"ran to the end", result.completed     ? "yes"
                                    : result.interrupted ? "no: ended by a signal (armsim --live)"
                                                         : "no: the simulated core stopped"});
  rows.push_back({"simulated time", format("%.3f s of %.3f s", m.sim_time_s, scenario.end_s)});
  if (m.loop_high.count) {
    rows.push_back({"control loop", format("%.0f mean, %llu max cycles (%.0f / %.0f us)", m.loop_high.mean(),
                                           (unsigned long long)m.loop_high.max, m.loop_high.mean() / 16,
                                           m.loop_high.max / 16.0)});
    rows.push_back({"control loop less interrupts",
                    format("%.0f mean, %llu max cycles", m.loop_own.mean(), (unsigned long long)m.loop_own.max)});
  } else {
    rows.push_back({"control loop", "no iteration seen on D49"});
  }
  rows.push_back({"control rate", format("%.1f Hz", m.control_rate_hz)});
  rows.push_back({"CPU load", format("%.1f %%", 100 * m.cpu_load)});
  static const char* steppers[3] = {"J1", "J5", "J6"};
  for (int i = 0; i < 3; ++i) {
    const sim::StepperCounts& s = m.steps[i];
    std::string v = format("%lld commanded, %lld lost", (long long)s.commanded, (long long)s.lost);
    if (s.ignored) v += format(", %lld while disabled", (long long)s.ignored);
    if (s.timing_violations) v += format(", %lld timing violations", (long long)s.timing_violations);
    rows.push_back({std::string("steps ") + steppers[i], v});
  }
  rows.push_back({"RAM high-water", format("%u B (static %u + stack %u)", m.ram_static_bytes + m.stack_bytes,
                                           m.ram_static_bytes, m.stack_bytes)});
  std::string faults;
  for (const auto& f : result.faults) faults += (faults.empty() ? "" : ", ") + f;
  rows.push_back({"faults", faults.empty() ? "none reported" : faults});
  std::string resets = format("%zu", m.resets.size());
  for (const auto& r : m.resets) resets += format("; %.3f s %s", r.cycle / kCpuHz, r.cause.c_str());
  rows.push_back({"resets", resets});
  for (const auto& e : m.estop) {
    rows.push_back({format("e-stop at %.3f s", e.pressed_s),
                    e.bridges_off_s >= 0
                        ? format("bridges braking after %.1f us, steppers held at rest after %.1f ms", 1e6 * (e.bridges_off_s - e.pressed_s),
                                 1e3 * (e.trains_stopped_s() - e.pressed_s))
                        : std::string("bridges not braking by the end")});
  }
  rows.push_back({"UART", format("%llu B out, %llu B in", (unsigned long long)m.uart_tx_bytes,
                                 (unsigned long long)m.uart_rx_bytes)});
  for (const auto& f : m.sim_faults) rows.push_back({"simulator", f});
  return rows;
}

std::string data_json(const RunResult& result, const Scenario& scenario, const std::string& title) {
  const std::vector<TrajectoryRow>& rows = result.trajectory;
  const sim::Measurements& m = result.measurements;
  Json j;
  j.raw("{");
  j.key("title");
  j.string(title);
  j.key("end_s");
  j.number(std::max(scenario.end_s, rows.empty() ? 0.0 : rows.back().t_s), 4);
  j.key("completed");
  j.raw(result.completed ? "true" : "false");
  j.key("interrupted");
  j.raw(result.interrupted ? "true" : "false");

  std::vector<std::string> modes, states;
  for (int i = 0; i < config::kModeCount; ++i) modes.push_back(mode_name(static_cast<config::Mode>(i)));
  // the state names up to the first value the supervisor has no name for
  for (int i = 0; i < 256 && std::string(core::to_string(static_cast<core::ArmState>(i))) != "?"; ++i)
    states.push_back(core::to_string(static_cast<core::ArmState>(i)));
  j.key("modes");
  j.strings(modes);
  j.key("states");
  j.strings(states);
  j.key("mode");
  segments(j, rows, &TrajectoryRow::mode);
  j.key("state");
  segments(j, rows, &TrajectoryRow::state);

  const double span = rows.empty() ? 0 : rows.back().t_s - rows.front().t_s;
  const std::vector<size_t> plot = sample_indices(rows, std::max(kPlotStepS, span / kMaxPlotSamples));
  std::vector<double> t;
  std::vector<std::vector<double>> q(6), qd, p(3), v;
  for (size_t i : plot) {
    t.push_back(rows[i].t_s);
    for (int k = 0; k < 6; ++k) q[k].push_back(rows[i].q[k]);
    for (int k = 0; k < 3; ++k) p[k].push_back(rows[i].p[k]);
  }
  for (const auto& x : q) qd.push_back(smoothed_derivative(t, x, kDerivativeHalfWidth));
  for (const auto& x : p) v.push_back(smoothed_derivative(t, x, kDerivativeHalfWidth));
  j.field("t", t, 4);
  j.field("q", q, 4);
  j.field("qd", qd, 3);
  j.field("p", p, 4);
  j.field("v", v, 4);

  // animation frames: the seven frame origins, then frame 6's rotation
  std::vector<double> ft, origins, hand;
  for (size_t i : sample_indices(rows, kFrameStepS)) {
    ft.push_back(rows[i].t_s);
    const auto frames = arm_frames(rows[i].q);
    for (const Frame& f : frames) origins.insert(origins.end(), f.p.begin(), f.p.end());
    hand.insert(hand.end(), frames[6].R.begin(), frames[6].R.end());
  }
  j.key("frames");
  j.raw("{");
  j.field("t", ft, 4);
  j.field("origins", origins, 4);
  j.field("hand", hand, 3);
  j.raw("}");

  inputs(j, scenario);
  j.key("estop");
  j.raw("[");
  for (size_t i = 0; i < m.estop.size(); ++i) {
    j.raw(i ? ",[" : "[");
    j.number(m.estop[i].pressed_s, 6);
    j.raw(",");
    if (m.estop[i].bridges_off_s >= 0) {
      j.number(m.estop[i].bridges_off_s, 6);
    } else {
      j.raw("null");
    }
    j.raw("]");
  }
  j.raw("]");
  j.key("resets");
  j.raw("[");
  for (size_t i = 0; i < m.resets.size(); ++i) {
    j.raw(i ? ",[" : "[");
    j.number(m.resets[i].cycle / kCpuHz, 6);
    j.raw(",");
    j.string(m.resets[i].cause);
    j.raw("]");
  }
  j.raw("]");
  j.key("faults");
  j.strings(result.faults);
  j.key("summary");
  j.raw("[");
  bool first = true;
  for (const auto& row : summary_rows(result, scenario)) {
    if (!first) j.raw(",");
    j.strings(row);
    first = false;
  }
  j.raw("]}");
  return j.text();
}

void replace(std::string& text, const std::string& marker, const std::string& with) {
  const size_t at = text.find(marker);
  if (at == std::string::npos) throw std::logic_error("report page: no " + marker);
  text.replace(at, marker.size(), with);
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::array<Frame, 7> arm_frames(const std::array<double, 6>& q) {
  // Craig: i-1 -> i is RotX(alpha_{i-1}) TransX(a_{i-1}) RotZ(theta_i) TransZ(d_i)
  const double alpha[6] = {0, arm::kPi / 2, 0, 0, arm::kPi / 2, -arm::kPi / 2};
  const double a[6] = {0, arm::a1_m, arm::a2_m, arm::a3_m, arm::a4_m, 0};
  const double d[6] = {arm::d1_m, 0, 0, 0, 0, arm::d6_m};
  const double theta_offset[6] = {0, 0, 0, 0, -arm::kPi / 2, 0};

  std::array<Frame, 7> frames;
  frames[0] = {{0, 0, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1}};
  for (int i = 0; i < 6; ++i) {
    const double ca = std::cos(alpha[i]), sa = std::sin(alpha[i]);
    const double ct = std::cos(q[i] + theta_offset[i]), st = std::sin(q[i] + theta_offset[i]);
    // the link transform's rotation (row-major) and translation
    const double r[9] = {ct, -st, 0, st * ca, ct * ca, -sa, st * sa, ct * sa, ca};
    const double o[3] = {a[i], -sa * d[i], ca * d[i]};
    const Frame& prev = frames[i];
    Frame& next = frames[i + 1];
    for (int row = 0; row < 3; ++row) {
      next.p[row] = prev.p[row];
      for (int k = 0; k < 3; ++k) next.p[row] += prev.R[3 * row + k] * o[k];
      for (int col = 0; col < 3; ++col) {
        next.R[3 * row + col] = 0;
        for (int k = 0; k < 3; ++k) next.R[3 * row + col] += prev.R[3 * row + k] * r[3 * k + col];
      }
    }
  }
  return frames;
}

std::vector<double> smoothed_derivative(const std::vector<double>& t, const std::vector<double>& x, int half_width) {
  const int n = (int)std::min(t.size(), x.size());
  std::vector<double> out(n, 0.0);
  for (int i = 0; i < n; ++i) {
    const int lo = std::max(0, i - half_width), hi = std::min(n - 1, i + half_width);
    if (hi > lo && t[hi] > t[lo]) out[i] = (x[hi] - x[lo]) / (t[hi] - t[lo]);
  }
  return out;
}

std::string report_html(const RunResult& result, const Scenario& scenario, const std::string& title) {
  std::string data = data_json(result, scenario, title);
  // '<' stands only inside JSON strings, where \u003c means the same, and a "</script>" in a
  // title or fault name cannot close the page's data element
  std::string safe;
  for (char c : data) {
    if (c == '<') {
      safe += "\\u003c";
    } else {
      safe += c;
    }
  }
  // the data first: the page's <title> comes before it, so the title's marker is found there
  // even when the data holds the marker's text
  std::string page = kReportPage;
  replace(page, "@DATA@", safe);
  replace(page, "@TITLE@", html_escape(title));
  return page;
}

void write_report_html(const std::string& path, const RunResult& result, const Scenario& scenario,
                       const std::string& title) {
  std::ofstream f(path, std::ios::binary);
  f << report_html(result, scenario, title);
  f.close();
  if (!f) throw std::runtime_error("cannot write " + path);
}

}  // namespace armsim
}  // namespace wmra
