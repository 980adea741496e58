#include "scenario.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "kinematics/arm_model.h"

namespace wmra {
namespace armsim {

namespace {

bool number(const std::string& word, double& out) {
  if (word.empty()) return false;
  char* end = nullptr;
  out = std::strtod(word.c_str(), &end);
  return *end == 0 && std::isfinite(out);
}

std::vector<uint8_t> hex_bytes(const std::string& hex, int line) {
  if (hex.empty() || hex.size() % 2) throw ScenarioError(line, "serial wants an even number of hex digits, got '" + hex + "'");
  std::vector<uint8_t> out;
  for (size_t i = 0; i < hex.size(); i += 2) {
    int v = 0;
    for (size_t k = i; k < i + 2; ++k) {
      const char c = hex[k];
      const int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
      if (d < 0) throw ScenarioError(line, std::string("'") + c + "' is not a hex digit in '" + hex + "'");
      v = v * 16 + d;
    }
    out.push_back((uint8_t)v);
  }
  return out;
}

void expect_words(const std::vector<std::string>& w, size_t n, int line, const std::string& form) {
  if (w.size() != n) throw ScenarioError(line, "expected '" + form + "'");
}

}  // namespace

Scenario parse_scenario(const std::string& text) {
  Scenario s;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  bool seen_event = false, ended = false;
  double last_t = 0;
  while (std::getline(in, raw)) {
    ++line;
    const size_t hash = raw.find('#');
    if (hash != std::string::npos) raw.erase(hash);
    std::istringstream words_in(raw);
    std::vector<std::string> w;
    for (std::string word; words_in >> word;) w.push_back(word);
    if (w.empty()) continue;
    if (ended) throw ScenarioError(line, "nothing may follow 'end'");

    if (w[0] == "init") {
      if (seen_event) throw ScenarioError(line, "'init' must be the first line");
      expect_words(w, 7, line, "init Q1 Q2 Q3 Q4 Q5 Q6");
      for (int j = 0; j < 6; ++j) {
        double q;
        if (!number(w[j + 1], q)) throw ScenarioError(line, "'" + w[j + 1] + "' is not a number");
        if (q < arm::q_min_rad(j) - 1e-12 || q > arm::q_max_rad(j) + 1e-12) {
          throw ScenarioError(line, "q" + std::to_string(j + 1) + " = " + w[j + 1] + " rad is outside the joint limits [" +
                                        std::to_string(arm::q_min_rad(j)) + ", " + std::to_string(arm::q_max_rad(j)) + "]");
        }
        s.init_q[j] = q;
      }
      s.has_init = true;
      seen_event = true;
      continue;
    }
    seen_event = true;
    Event e;
    e.line = line;
    if (!number(w[0], e.t_s)) throw ScenarioError(line, "expected a time in seconds or 'init', got '" + w[0] + "'");
    if (e.t_s < 0) throw ScenarioError(line, "negative time " + w[0]);
    if (e.t_s < last_t) throw ScenarioError(line, "time " + w[0] + " s is before the previous event's");
    last_t = e.t_s;
    if (w.size() < 2) throw ScenarioError(line, "an event is missing after the time");
    const std::string& verb = w[1];
    if (verb == "end") {
      expect_words(w, 2, line, "T end");
      s.end_s = e.t_s;
      ended = true;
      continue;
    }
    if (verb == "joystick") {
      expect_words(w, 4, line, "T joystick X Y");
      if (!number(w[2], e.x) || !number(w[3], e.y)) throw ScenarioError(line, "joystick X and Y must be numbers");
      if (std::fabs(e.x) > 1 || std::fabs(e.y) > 1) throw ScenarioError(line, "joystick X and Y must be within [-1, 1]");
      e.kind = Event::Kind::joystick;
    } else if (verb == "button") {
      expect_words(w, 3, line, "T button press|down|up");
      if (w[2] == "press") e.kind = Event::Kind::button_press;
      else if (w[2] == "down") e.kind = Event::Kind::button_down;
      else if (w[2] == "up") e.kind = Event::Kind::button_up;
      else throw ScenarioError(line, "button takes press, down or up, not '" + w[2] + "'");
    } else if (verb == "estop") {
      expect_words(w, 3, line, "T estop down|up");
      if (w[2] == "down") e.kind = Event::Kind::estop_down;
      else if (w[2] == "up") e.kind = Event::Kind::estop_up;
      else throw ScenarioError(line, "estop takes down or up, not '" + w[2] + "'");
    } else if (verb == "pot_fault") {
      expect_words(w, 4, line, "T pot_fault J open|short|ok");
      if (w[2] != "2" && w[2] != "3" && w[2] != "4") throw ScenarioError(line, "pot_fault is for joints 2, 3 and 4, not '" + w[2] + "'");
      e.joint = w[2][0] - '0';
      if (w[3] == "ok") e.fault = 0;
      else if (w[3] == "open") e.fault = 1;
      else if (w[3] == "short") e.fault = 2;
      else throw ScenarioError(line, "pot_fault takes open, short or ok, not '" + w[3] + "'");
      e.kind = Event::Kind::pot_fault;
    } else if (verb == "joystick_fault") {
      expect_words(w, 3, line, "T joystick_fault open|ok");
      if (w[2] == "ok") e.fault = 0;
      else if (w[2] == "open") e.fault = 1;
      else throw ScenarioError(line, "joystick_fault takes open or ok, not '" + w[2] + "'");
      e.kind = Event::Kind::joystick_fault;
    } else if (verb == "serial") {
      expect_words(w, 3, line, "T serial HEX");
      e.bytes = hex_bytes(w[2], line);
      e.kind = Event::Kind::serial;
    } else {
      throw ScenarioError(line, "unknown event '" + verb +
                                    "' (joystick, button, estop, pot_fault, joystick_fault, serial, end)");
    }
    s.events.push_back(e);
  }
  if (!ended) throw ScenarioError(line, "the scenario has no 'T end' line");
  return s;
}

Scenario load_scenario(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read the scenario " + path);
  std::stringstream text;
  text << f.rdbuf();
  return parse_scenario(text.str());
}

}  // namespace armsim
}  // namespace wmra
