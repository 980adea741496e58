// report.html without a browser: the arm the page draws is the one forward kinematics computes,
// the velocities, the data the page embeds, that it needs no network, and its size.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <regex>

#include "armsim/report.h"
#include "kinematics/forward_kinematics.h"
#include "synthetic_run.h"

using namespace wmra;
using armsim::arm_frames;
using armsim::report_html;
using test::synthetic_run;

namespace {

using D = kin::Floating<double>;

std::array<double, 6> random_joints(std::mt19937_64& rng) {
  std::array<double, 6> q;
  for (int j = 0; j < 6; ++j) q[j] = std::uniform_real_distribution<double>(arm::q_min_rad(j), arm::q_max_rad(j))(rng);
  return q;
}

// the numbers of the page's first JSON array after "key": (of a nested one, its first row)
std::vector<double> json_array(const std::string& page, const std::string& key) {
  size_t at = page.find("\"" + key + "\":[");
  if (at == std::string::npos) return {};
  at += key.size() + 4;
  if (page[at] == '[') ++at;
  std::vector<double> out;
  const char* p = page.c_str() + at;
  while (*p != ']') {
    char* end = nullptr;
    out.push_back(std::strtod(p, &end));
    if (end == p) return {};
    p = *end == ',' ? end + 1 : end;
  }
  return out;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(ArmFrames, LastFrameIsForwardKinematics) {
  std::mt19937_64 rng(7);
  double worst = 0;
  for (int n = 0; n < 5000; ++n) {
    const auto q = random_joints(rng);
    kin::JointAngles<D> a;
    for (int j = 0; j < 6; ++j) a.q[j] = q[j];
    const auto pose = kin::forward_kinematics<D>(a);
    const armsim::Frame hand = arm_frames(q)[6];
    worst = std::max({worst, std::abs(hand.p[0] - pose.p_m.x), std::abs(hand.p[1] - pose.p_m.y),
                      std::abs(hand.p[2] - pose.p_m.z)});
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(hand.R[3 * r + c] - pose.R[r][c]));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(ArmFrames, StretchedArmOriginsAreTheLinkLengths) {
  const auto f = arm_frames({0, 0, 0, 0, 0, 0});
  const double x[7] = {0, 0, 0.014, 0.364, 0.714, 0.879, 1.077};
  const double z[7] = {0, 0.187, 0.187, 0.187, 0.187, 0.187, 0.187};
  for (int i = 0; i < 7; ++i) {
    EXPECT_NEAR(f[i].p[0], x[i], 1e-12) << "frame " << i;
    EXPECT_NEAR(f[i].p[1], 0, 1e-12) << "frame " << i;
    EXPECT_NEAR(f[i].p[2], z[i], 1e-12) << "frame " << i;
  }
}

// frame i's origin lies on joint i's axis: turning joint i moves no origin up to frame i
TEST(ArmFrames, EachJointTurnsOnlyTheFramesAfterIt) {
  std::mt19937_64 rng(8);
  for (int n = 0; n < 200; ++n) {
    const auto q = random_joints(rng);
    for (int joint = 0; joint < 6; ++joint) {
      auto turned = q;
      turned[joint] += 0.3;
      const auto a = arm_frames(q), b = arm_frames(turned);
      for (int i = 0; i <= joint + 1; ++i)
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(a[i].p[k], b[i].p[k], 1e-12) << "joint " << joint + 1 << " frame " << i;
    }
  }
}

TEST(SmoothedDerivative, ExactOnRampsAndCentredOnParabolas) {
  std::vector<double> t, ramp, parabola;
  for (int i = 0; i <= 50; ++i) {
    t.push_back(0.01 * i);
    ramp.push_back(3 - 2 * t.back());
    parabola.push_back(t.back() * t.back());
  }
  const auto dr = armsim::smoothed_derivative(t, ramp, 2);
  const auto dp = armsim::smoothed_derivative(t, parabola, 2);
  ASSERT_EQ(dr.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(dr[i], -2, 1e-9) << i;  // the ends too
  for (size_t i = 2; i + 2 < t.size(); ++i) EXPECT_NEAR(dp[i], 2 * t[i], 1e-9) << i;
  EXPECT_EQ(armsim::smoothed_derivative({0.5}, {1.0}, 2), std::vector<double>{0.0});
  EXPECT_TRUE(armsim::smoothed_derivative({}, {}, 2).empty());
}

TEST(ReportHtml, NeedsNoNetwork) {
  const std::string page = report_html(synthetic_run(2, 100, test::waving), test::scenario_until(2), "run");
  EXPECT_EQ(page.find("http"), std::string::npos);
  EXPECT_FALSE(std::regex_search(page, std::regex(R"((src|href)\s*=)", std::regex::icase)));
  EXPECT_FALSE(std::regex_search(page, std::regex(R"(url\s*\(|@import)", std::regex::icase)));
  EXPECT_EQ(page.find("@DATA@"), std::string::npos);
  EXPECT_EQ(page.find("@TITLE@"), std::string::npos);
}

TEST(ReportHtml, EmbedsPlotSamplesAt100HzAndFramesAt30Hz) {
  // rows at 1 kHz, joint 1 at 0.5 rad/s
  const auto run = synthetic_run(2, 1000, [](double t) { return std::array<double, 6>{0.5 * t, 0.5, 1, -1, 0.2, 0}; });
  const std::string page = report_html(run, test::scenario_until(2), "run");
  const auto t = json_array(page, "t");
  ASSERT_EQ(t.size(), 201u);
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], 0.01 * i, 1e-9);
  const auto q1 = json_array(page, "q");
  ASSERT_EQ(q1.size(), 201u);
  EXPECT_NEAR(q1[100], 0.5, 1e-4);
  for (double qd1 : json_array(page, "qd")) EXPECT_NEAR(qd1, 0.5, 1e-3);
  const auto frames = json_array(page, "frames\":{\"t");
  EXPECT_GE(frames.size(), 59u);
  EXPECT_LE(frames.size(), 61u);
  EXPECT_EQ(frames.back(), 2.0);
  // the hand's path as forward kinematics has it, to 0.1 mm
  const auto x = json_array(page, "p");
  ASSERT_EQ(x.size(), 201u);
  EXPECT_NEAR(x[200], run.trajectory.back().p[0], 1e-4);
}

TEST(ReportHtml, ModeAndStateAsTheirChanges) {
  const auto run = synthetic_run(
      1, 100, test::waving, [](double t) { return t < 0.5 ? 0 : 2; }, [](double t) { return t < 0.2 ? 1 : 4; });
  const std::string page = report_html(run, test::scenario_until(1), "run");
  EXPECT_NE(page.find("\"mode\":[[0,0],[0.5,2]]"), std::string::npos);
  EXPECT_NE(page.find("\"state\":[[0,1],[0.2,4]]"), std::string::npos);
  EXPECT_NE(page.find("\"modes\":[\"XY\",\"XZ\",\"R1\",\"R2\",\"gripper\"]"), std::string::npos);
  EXPECT_NE(page.find("\"states\":[\"boot\",\"wait_neutral\",\"homing\",\"to_ready\",\"running\",\"stopped\",\"fault\",\"wait_home\",\"jog\"]"),
            std::string::npos);
}

TEST(ReportHtml, TitleAndNamesCannotBreakThePage) {
  auto run = synthetic_run(1, 100, test::waving);
  run.faults = {"</script><script>alert(1)</script>"};
  const std::string page = report_html(run, test::scenario_until(1), "a </script> & \"b\"");
  EXPECT_EQ(count(page, "</script>"), 3u);  // the page's own: onerror, data, main
  EXPECT_NE(page.find("<title>a &lt;/script&gt; &amp; &quot;b&quot; - armsim report</title>"), std::string::npos);
  EXPECT_NE(page.find("\"title\":\"a \\u003c/script> & \\\"b\\\"\""), std::string::npos);
}

TEST(ReportHtml, SixtySecondsStayUnderTwoMegabytes) {
  for (double hz : {100.0, 1000.0}) {
    const std::string page = report_html(synthetic_run(60, hz, test::waving), test::scenario_until(60), "sixty");
    std::printf("60 s at %.0f rows/s: %zu bytes\n", hz, page.size());
    EXPECT_LT(page.size(), 2000000u);
    EXPECT_EQ(json_array(page, "t").size(), 6001u);
  }
}

TEST(ReportHtml, LongRunsAreThinnedTo20000PlotSamples) {
  const std::string page = report_html(synthetic_run(400, 100, test::waving), test::scenario_until(400), "long");
  const auto t = json_array(page, "t");
  EXPECT_LE(t.size(), 20001u);
  EXPECT_GE(t.size(), 19990u);
  EXPECT_EQ(t.back(), 400.0);
}

TEST(ReportHtml, WriteThrowsWhenTheFileCannotBeWritten) {
  EXPECT_THROW(armsim::write_report_html("/nonexistent/dir/report.html", synthetic_run(1, 100, test::waving),
                                         test::scenario_until(1), "x"),
               std::runtime_error);
}
