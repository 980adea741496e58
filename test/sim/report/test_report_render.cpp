// report.html in headless Chromium (scripts/check-report): armsim's page for a run of a test
// image, pages with no data and with every kind of event, render without a script error; pages
// broken on purpose are caught. Without chromium these fail and say to run scripts/test.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sys/wait.h>

#include "armsim/report.h"
#include "synthetic_run.h"
#include "wmra_mega/board.h"

using namespace wmra;
using test::read_text;

namespace {

const std::string kOut = REPORT_OUT;

struct Check {
  int status;
  std::string output;
};

Check check_report(const std::string& page) {
  Check c{-1, ""};
  FILE* p = popen((std::string(CHECK_REPORT) + " " + page + " 2>&1").c_str(), "r");
  if (!p) return c;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) c.output += buf;
  const int status = pclose(p);
  c.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return c;
}

// armsim's report for a short run of the bridges image (DC joints moving, the safety button),
// in a folder of its own (ctest runs the tests in parallel)
std::string armsim_report(const std::string& name) {
  const std::string dir = kOut + "/" + name;
  const std::string scenario = dir + "_scenario.txt";
  std::ofstream(scenario) << "init 0 0.5 1.0 -1.2 0.3 0\n0 joystick 0.2 0\n0.3 button press\n0.5 serial 4f4b\n"
                             "0.6 joystick 0 0.7\n1.0 estop down\n1.2 estop up\n1.5 end\n";
  const std::string cmd = std::string(ARMSIM) + " --scenario " + scenario + " --out " + dir + " --elf " + SIM_IMAGES +
                          "/sim_bridges_avr.elf 2>/dev/null";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0) << cmd;
  return dir + "/report.html";
}

std::string write_copy(const std::string& name, const std::string& text) {
  const std::string path = kOut + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace

TEST(ReportRender, ArmsimsReportRenders) {
  const std::string page = armsim_report("armsim");
  const std::string text = read_text(page);
  std::printf("%s: %zu bytes\n", page.c_str(), text.size());
  EXPECT_EQ(text.find("http"), std::string::npos);
  const Check c = check_report(page);
  EXPECT_EQ(c.status, 0) << c.output;
  // in check-report's 5 s of virtual time the page played the whole 1.5 s run
  EXPECT_NE(c.output.find("played to 1.50 / 1.50 s"), std::string::npos) << c.output;
}

TEST(ReportRender, NoDataRenders) {
  const std::string page = kOut + "/empty.html";
  armsim::write_report_html(page, armsim::RunResult{}, armsim::Scenario{}, "no rows");
  const Check c = check_report(page);
  EXPECT_EQ(c.status, 0) << c.output;
}

TEST(ReportRender, EveryKindOfEventRenders) {
  // modes and states as telemetry will give them, the fault state with its faults, a reset,
  // e-stops with and without their outputs off, a simulator fault, and every kind of input
  auto run = test::synthetic_run(
      4, 100, test::waving, [](double t) { return (int)t % 5; },
      [](double t) { return t < 0.5 ? 1 : t < 1 ? 2 : t < 3 ? 4 : 6; });
  run.faults = {"j3_rail", "tracking"};
  run.measurements.resets.push_back({(uint64_t)(2.5 * (double)board::kCpuHz), "watchdog"});
  run.measurements.estop.push_back({1.5, 1.50004, {}});
  run.measurements.estop.push_back({3.8, -1, {}});
  run.measurements.sim_faults.push_back("core crashed at 3.9 s");
  run.measurements.loop_high.add(2800);
  run.completed = false;
  const auto scenario = armsim::parse_scenario(
      "init 0 0.5 1.0 -1.2 0.3 0\n0 joystick 0.5 -1\n1.0 button press\n1.2 button down\n1.4 button up\n"
      "1.5 estop down\n1.6 estop up\n2.5 pot_fault 3 open\n2.5 joystick_fault open\n2.6 pot_fault 3 ok\n"
      "2.7 joystick_fault ok\n3.0 serial 4f4b0a\n3.8 estop down\n4 end\n");
  const std::string page = kOut + "/events.html";
  armsim::write_report_html(page, run, scenario, "every event");
  const Check c = check_report(page);
  EXPECT_EQ(c.status, 0) << c.output;
}

TEST(ReportRender, AScriptErrorIsCaught) {
  std::string text = read_text(armsim_report("for_broken_script"));
  const size_t end = text.rfind("</body>");
  ASSERT_NE(end, std::string::npos);
  text.insert(end, "<script>undefined_function()</script>");
  const Check c = check_report(write_copy("broken_script.html", text));
  EXPECT_EQ(c.status, 1) << c.output;
  EXPECT_NE(c.output.find("undefined_function is not defined"), std::string::npos) << c.output;
}

TEST(ReportRender, CorruptDataIsCaught) {
  std::string text = read_text(armsim_report("for_broken_data"));
  const size_t at = text.find("\"t\":[");
  ASSERT_NE(at, std::string::npos);
  text.insert(at + 5, ",");
  const Check c = check_report(write_copy("broken_data.html", text));
  EXPECT_EQ(c.status, 1) << c.output;
  EXPECT_NE(c.output.find("JSON"), std::string::npos) << c.output;
}
