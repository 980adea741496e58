#include "calibrate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <unistd.h>

#include "calibration_link.h"
#include "commands.h"
#include "config/motion_config.h"
#include "kinematics/arm_model.h"
#include "serial_port.h"
#include "telemetry_json.h"

namespace wmra {
namespace telemetry_cli {

namespace {

using core::ArmState;
using protocol::ReplyStatus;

constexpr auto kFirstStateWait = std::chrono::seconds(4);  // a Mega's bootloader runs 1-2 s after the reset
constexpr auto kArmingQuietly = std::chrono::seconds(2);   // boot and wait_neutral pass in ~1 s with the stick released
constexpr auto kArmingAtMost = std::chrono::seconds(8);    // and then this long, the person told
constexpr int16_t kJogSpeed_mrad_s = config::kJogSpeed_mrad_s;
constexpr double kJogDefault_s = 1, kJogMin_s = 0.1, kJogMax_s = 20;
// the firmware takes a calibration whose limits' readings are far enough apart (less, and the
// pot turns too little over the joint's range)
constexpr int kMinSpan_counts_x16 = protocol::kPotCalibrationMinSpan_counts_x16;
// Two readings where the joint stands differ by at most an ADC count: the pot's noise makes a
// joint at rest read either count its wiper lies between. More: the joint has moved.
constexpr int kSamePlace_counts_x16 = 16;

std::string format(const char* f, double v) {
  char s[64];
  std::snprintf(s, sizeof s, f, v);
  return s;
}

// A joint's readings at its limits and where they come from: "1459..15564 (set)"
std::string limits_text(const protocol::CalibrationMsg& m, int joint) {
  const int d = joint - 2;
  return std::to_string(m.at_min_counts_x16[d]) + ".." + std::to_string(m.at_max_counts_x16[d]) +
         (m.from_command >> d & 1 ? " (set)" : " (config)");
}

// What to do when the arm is not waiting before homing, the only state a pot is calibrated in
std::string why_not(const protocol::StateMsg& s) {
  const std::string name = telemetry::state_name(s.state);
  switch ((ArmState)s.state) {
    case ArmState::boot:
    case ArmState::wait_neutral:
      return "the arm has not armed (" + name + "): release the joystick (it arms once it reads neutral) and run calibrate again";
    case ArmState::homing:
    case ArmState::to_ready:
      return "the arm is homing (" + name + "): a pot is calibrated before homing, with the drives off; once it has "
             "stopped, switch it off and on (or reset it) and run calibrate again";
    case ArmState::running:
      return "the arm is homed (running): switch it off and on (or reset it) and run calibrate again; a pot is "
             "calibrated before homing";
    case ArmState::stopped:
      return "the arm is stopped: release the safety button and re-arm it (a long press), then run calibrate again "
             "(if it then runs homed, switch it off and on instead)";
    case ArmState::fault:
      return "the arm is faulted (" + fault_list(s.faults) +
             "): deal with the cause (docs/arm-guide.md), re-arm it (a long press) and run calibrate again";
    case ArmState::jog:
      return "a jog is under way (jog): wait for it to end and run calibrate again";
    default:
      return "the arm is in state " + name + ": calibrate needs it waiting before homing (wait_home)";
  }
}

bool is_number(const std::string& word) {
  char* end = nullptr;
  std::strtod(word.c_str(), &end);
  return end != word.c_str() && *end == 0;
}

enum class Step { point1, point2, confirm };

struct Point {
  int reading_counts_x16;
  double angle_deg;  // as the person measured it
};

class Calibration {
 public:
  explicit Calibration(const CalibrateOptions& options)
      : options_(options),
        joint_name_("J" + std::to_string(options.joint)),
        echo_(!isatty(options.input_fd)),
        link_(options.device, options.input_fd, options.joint, [this](const std::string& line) { say(line); }) {}

  int run() {
    try {
      if (!arm_waits_before_homing()) return finish(1);
      guide();
      return finish(status_);
    } catch (const Interrupted&) {
      say(stored_maybe_ ? "interrupted after pot_calibration was sent: `calibration` in a session shows whether it was stored"
                        : "not stored (interrupted)");
      return finish(1);
    }
  }

 private:
  // --- the arm's state

  bool arm_waits_before_homing() {
    say("calibrate " + joint_name_ + " on " + options_.device + ": waiting for the arm (a Mega resets when its port is opened)");
    if (!link_.wait_for_state(kFirstStateWait)) {
      if (stop_requested()) throw Interrupted{};
      throw IoError{options_.device + ": no state frame in 4 s (the firmware running? the right port?)"};
    }
    if (passing(link_.wait_while_passing(kArmingQuietly))) {
      const bool arming = link_.arm_state() != ArmState::jog;
      say("the arm is in " + telemetry::state_name(link_.state().state) + ": waiting up to 8 s for it to wait before homing" +
          (arming ? " (release the joystick)" : ""));
      link_.wait_while_passing(kArmingAtMost);
    }
    if (stop_requested()) throw Interrupted{};
    if (link_.arm_state() != ArmState::wait_home) {
      std::fprintf(stderr, "wmra-telemetry: %s; nothing sent\n", why_not(link_.state()).c_str());
      return false;
    }
    link_.watch();
    if (link_.state().faults) say("faults: " + fault_list(link_.state().faults));
    return true;
  }

  // --- the dialog

  void guide() {
    say("the arm waits before homing (wait_home): " + joint_name_ + " may be jogged and its pot calibrated");
    show(link_.read_pot());
    say("calibration now: " + joint_name_ + " " + limits_text(link_.calibration(), options_.joint));
    say("jog " + joint_name_ + " with + or - [SECONDS] (0.1 rad/s, 1 s unless given), measure its angle (an inclinometer) "
        "and type it in deg;");
    say("do that at two angles at least 10 deg apart, then store. q quits, nothing stored.");
    std::vector<std::string> words;
    for (;;) {
      prompt();
      if (!next_answer(words)) {
        if (stop_requested()) throw Interrupted{};
        say("not stored: the input ended before yes");
        status_ = 1;
        return;
      }
      if (words.size() == 1 && (words[0] == "q" || words[0] == "quit")) {
        say("not stored (quit)");
        status_ = 1;
        return;
      }
      try {
        if (step_ == Step::confirm ? confirm(words) : point(words)) return;
      } catch (const BadInput& e) {
        ++bad_lines_;
        std::fprintf(stderr, "wmra-telemetry: line %d: %s\n", line_number_, e.message.c_str());
      }
    }
  }

  void prompt() {
    if (step_ == Step::point1) {
      say("point 1: + / - [SECONDS] jogs " + joint_name_ + ", an angle in deg takes the point here");
    } else if (step_ == Step::point2) {
      say("point 2 (at least 10 deg from " + format("%g", first_.angle_deg) + "): + / - [SECONDS] jogs " + joint_name_ +
          ", an angle in deg takes the point here");
    } else {
      say("store? (yes/no)");
    }
  }

  // The next answer's words, blank lines and # comments skipped; false at the input's end
  bool next_answer(std::vector<std::string>& words) {
    std::string line;
    while (link_.next_line(line)) {
      ++line_number_;
      words = split_words(line.substr(0, line.find('#')));
      if (words.empty()) continue;
      if (echo_) say("> " + line);  // a script's answers in the transcript, as a person's show on the terminal
      return true;
    }
    return false;
  }

  // At point 1 or 2: a jog or a measured angle. Whether the dialog is over (never).
  bool point(const std::vector<std::string>& words) {
    if (words[0] == "+" || words[0] == "-") {
      if (words.size() > 2) throw BadInput{words[0] + " takes at most SECONDS"};
      const double seconds = words.size() == 2 ? parse_number(words[1], kJogMin_s, kJogMax_s, "SECONDS (of the jog)") : kJogDefault_s;
      jog(words[0] == "+" ? kJogSpeed_mrad_s : (int16_t)-kJogSpeed_mrad_s, seconds);
      return false;
    }
    if (words.size() == 1 && words[0][0] == '+') {  // "+2" would be an angle of 2 deg where a jog was meant
      throw BadInput{"'" + words[0] + "': a jog is + or - with a space before SECONDS, an angle has no + sign"};
    }
    if (words.size() != 1 || !is_number(words[0])) {
      std::string line = words[0];
      for (size_t i = 1; i < words.size(); ++i) line += " " + words[i];
      throw BadInput{"type + or - [SECONDS] to jog " + joint_name_ + ", the angle you measure in deg, or q to quit; not '" + line + "'"};
    }
    const int j = options_.joint - 1;
    take_point(parse_number(words[0], arm::q_min_deg[j], arm::q_max_deg[j], "the angle (deg, within " + joint_name_ + "'s limits)"));
    return false;
  }

  void jog(int16_t speed_mrad_s, double seconds) {
    const JogReplies r = link_.jog(speed_mrad_s, seconds);
    std::string line = "jog " + joint_name_ + " at " + format("%+.1f", speed_mrad_s / 1000.0) + " rad/s for " +
                       format("%g", seconds) + " s: " + std::to_string(r.frames) + " frames:";
    for (const auto& [status, count] : r.by_status) line += " " + std::to_string(count) + " " + telemetry::status_name(status) + ",";
    if (r.unanswered) line += " " + std::to_string(r.unanswered) + " no reply,";
    line.pop_back();
    say(line);
    for (const auto& [status, count] : r.by_status) {
      if (status != (uint8_t)ReplyStatus::ok) say("  " + telemetry::status_name(status) + ": " + jog_refusal(status));
    }
    if (r.unanswered) say("  no reply: the firmware did not answer those frames (the link? the firmware running?)");
    show(link_.read_pot());
  }

  std::string jog_refusal(uint8_t status) const {
    switch ((ReplyStatus)status) {
      case ReplyStatus::refused:
        return "the firmware jogs a joint only while the arm waits before homing (wait_home) or runs with the stick "
               "neutral; it is " + telemetry::state_name(link_.state().state) + " now, faults: " +
               fault_list(link_.state().faults);
      case ReplyStatus::bad_argument: return "the firmware does not take this joint or speed";
      case ReplyStatus::unknown_command:
      case ReplyStatus::bad_length: return "the firmware does not know the jog command: it is older than this tool";
      case ReplyStatus::safety_held: return "the safety button is held: release it";
      default: return "a status this tool does not know";
    }
  }

  // The point is the typed angle and the reading shown, where the person measured; a fresh
  // reading checks that the joint has not moved since. Not a fresh reading itself: between two
  // counts, one reading may give the one and the next the other, and a count at a point tilts
  // the line through both points by tens of counts x 16 at the limits.
  void take_point(double angle_deg) {
    const PotReading here = link_.read_pot();
    if (std::abs(here.counts_x16 - shown_.counts_x16) > kSamePlace_counts_x16) {
      say(joint_name_ + " has moved since it was read:");
      show(here);
      say("measure its angle there and type it again");
      return;
    }
    const Point p{shown_.counts_x16, angle_deg};
    const std::string n = step_ == Step::point1 ? "1" : "2";
    say("point " + n + ": " + std::to_string(p.reading_counts_x16) + " at " + format("%g", angle_deg) +
        " deg (the firmware's angle " + format("%.2f", shown_.angle_deg) + " deg)");
    if (step_ == Step::point1) {
      first_ = p;
      step_ = Step::point2;
      return;
    }
    if (std::fabs(p.angle_deg - first_.angle_deg) < kMinPointsApart_deg) {
      say("point 2 is " + format("%.1f", std::fabs(p.angle_deg - first_.angle_deg)) +
          " deg from point 1: the points must be at least 10 deg apart; jog further and type the angle there");
      return;
    }
    try {
      computed_ = pot_calibration_from(options_.joint, first_.reading_counts_x16, first_.angle_deg, p.reading_counts_x16, p.angle_deg);
      if (computed_.at_max_counts_x16 - computed_.at_min_counts_x16 < kMinSpan_counts_x16) {
        throw BadInput{"the limits' readings come out only " +
                       std::to_string(computed_.at_max_counts_x16 - computed_.at_min_counts_x16) +
                       " apart, the firmware takes 9600 (600 counts) or more: the pot turns too little over the joint's "
                       "range (its gear? its wiring?)"};
      }
    } catch (const BadInput& e) {
      say("these points make no calibration: " + e.message);
      say("take the two points again");
      step_ = Step::point1;
      return;
    }
    const int j = options_.joint - 1;
    const double then_deg =
        pot_angle_deg(options_.joint, p.reading_counts_x16, computed_.at_min_counts_x16, computed_.at_max_counts_x16);
    say("limits: " + joint_name_ + " " + std::to_string(computed_.at_min_counts_x16) + ".." +
        std::to_string(computed_.at_max_counts_x16) + " (counts x 16 at " + std::to_string(arm::q_min_deg[j]) + ".." +
        std::to_string(arm::q_max_deg[j]) + " deg), now " + limits_text(link_.calibration(), options_.joint));
    say("with it the firmware reads " + format("%.2f", then_deg) + " deg here (now " + format("%.2f", shown_.angle_deg) + " deg)");
    step_ = Step::confirm;
  }

  // At store?: yes stores, no ends. Whether the dialog is over.
  bool confirm(const std::vector<std::string>& words) {
    if (words.size() != 1 || (words[0] != "yes" && words[0] != "no")) throw BadInput{"type yes or no (q quits)"};
    if (words[0] == "no") {
      say("not stored");
      status_ = 1;
      return true;
    }
    stored_maybe_ = true;
    const StoreReply r = link_.store(computed_);
    if (!r.replied) {
      throw IoError{options_.device + ": no reply to pot_calibration in 1 s: `calibration` in `wmra-telemetry session` "
                                      "shows whether it was stored"};
    }
    if (r.status != (uint8_t)ReplyStatus::ok) {
      say("not stored: the firmware answers " + telemetry::status_name(r.status) + ": " + store_refusal(r.status));
      status_ = 1;
      return true;
    }
    if (!r.reported) {
      say("stored (no calibration frame came to show it: `calibration` in `wmra-telemetry session` does)");
    } else {
      say("stored: " + joint_name_ + " " + limits_text(r.calibration, options_.joint));
      show(link_.read_pot());
    }
    status_ = 0;
    return true;
  }

  std::string store_refusal(uint8_t status) const {
    switch ((ReplyStatus)status) {
      case ReplyStatus::refused:
        return "the drives are on (" + telemetry::state_name(link_.state().state) +
               "): a pot is calibrated with them off, before homing";
      case ReplyStatus::bad_argument:
        return "it takes readings within 0..16368, at least 9600 apart, the joint's reading now within 320 of them";
      default: return "the firmware does not take pot_calibration";
    }
  }

  // "J3 reads 8123 (counts x 16), the firmware's angle 35.20 deg"
  void show(const PotReading& r) {
    shown_ = r;
    say(joint_name_ + " reads " + std::to_string(r.counts_x16) + " (counts x 16), the firmware's angle " +
        format("%.2f", r.angle_deg) + " deg");
  }

  void say(const std::string& line) {
    std::fputs((line + "\n").c_str(), stdout);
    std::fflush(stdout);
  }

  int finish(int status) {
    if (!bad_lines_) return status;
    std::fprintf(stderr, "wmra-telemetry: lines not used: %d\n", bad_lines_);
    return 2;
  }

  const CalibrateOptions& options_;
  const std::string joint_name_;  // "J3"
  const bool echo_;               // the answers come from a script: shown after their prompts
  Step step_ = Step::point1;
  Point first_{};
  PotReading shown_{};  // the reading the person saw last
  protocol::PotCalibrationCmd computed_{};
  bool stored_maybe_ = false;  // pot_calibration was sent
  int status_ = 1;
  int bad_lines_ = 0, line_number_ = 0;
  CalibrationLink link_;  // last: its notes reach the members above
};

}  // namespace

int run_calibrate(const CalibrateOptions& options) {
  Calibration calibration(options);
  catch_stop_signals();
  return calibration.run();
}

}  // namespace telemetry_cli
}  // namespace wmra
