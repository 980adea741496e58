// Seed 1's rank-1 pole placement (lib/control/pole_placement.h), checked independently: the
// closed-loop poles are the eigenvalues (Eigen) of the closed-loop state matrix built from the
// designed gains, not the polynomial the method solved for.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "control/pid.h"
#include "control/pole_placement.h"

using namespace wmra;
using namespace wmra::control;
using namespace wmra::control::design;
using cd = std::complex<double>;

namespace {

std::vector<cd> eigenvalues(const Matrix& m) {
  Eigen::MatrixXd e(m.rows, m.cols);
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) e(i, j) = m(i, j);
  Eigen::EigenSolver<Eigen::MatrixXd> s(e);
  std::vector<cd> out;
  for (int i = 0; i < m.rows; ++i) out.push_back(s.eigenvalues()[i]);
  return out;
}

std::vector<cd> damping_roots(const std::vector<std::pair<double, double>>& zo) {
  std::vector<cd> r;
  for (const auto& p : zo) {
    const cd d = std::sqrt(cd(p.first * p.first - 1, 0));
    r.push_back(p.second * (-p.first + d));
    r.push_back(p.second * (-p.first - d));
  }
  return r;
}

// largest distance from each wanted root to the nearest unused eigenvalue, relative to |root|
double worst_match(std::vector<cd> got, const std::vector<cd>& want) {
  double worst = 0;
  for (const cd& w : want) {
    auto it = std::min_element(got.begin(), got.end(), [&](const cd& a, const cd& b) { return std::abs(a - w) < std::abs(b - w); });
    worst = std::max(worst, std::abs(*it - w) / std::max(1.0, std::abs(w)));
    got.erase(it);
  }
  return worst;
}

double max_real(const std::vector<cd>& v) {
  double m = -1e300;
  for (const cd& c : v) m = std::max(m, c.real());
  return m;
}

// Seed 1's 2-link model (Manutec R3 links 2-3, Chapter 3), linearised hanging down, g = 9.8
struct Model {
  Matrix a, b, c;
};
// the same with the thesis's printed (rounded) A and B (3.38-3.40)
Model manutec_printed() {
  return Model{Matrix(4, 4, {0, 0, 1, 0, 0, 0, 0, 1, -26.858, 15.257, 0, 0, 34.313, -51.065, 0, 0}),
               Matrix(4, 2, {0, 0, 0, 0, 0.157, -0.319, -0.319, 0.860}), Matrix(2, 4, {1, 0, 0, 0, 0, 1, 0, 0})};
}
Model manutec() {
  const double l1 = 0.5, l2 = 0.73, m1 = 56.5, m2 = 26.4, g = 9.8;
  const double a1 = m1 * l1 * l1 / 3 + m2 * l2 * l2 / 3 + m2 * l1 * l1, a2 = m2 * l1 * l2, a3 = m2 * l2 * l2 / 3;
  const double a4 = (m1 / 2 + m2) * g * l1, a5 = m2 * g * l2 / 2;
  const double d11 = a1 + a2, d12 = a3 + a2 / 2, d22 = a3, det = d11 * d22 - d12 * d12;
  const double i11 = d22 / det, i12 = -d12 / det, i22 = d11 / det;  // D^-1
  const double c11 = a4 + a5, c12 = a5, c22 = a5;                    // dG/dtheta
  const double k11 = -(i11 * c11 + i12 * c12), k12 = -(i11 * c12 + i12 * c22);
  const double k21 = -(i12 * c11 + i22 * c12), k22 = -(i12 * c12 + i22 * c22);
  return Model{Matrix(4, 4, {0, 0, 1, 0, 0, 0, 0, 1, k11, k12, 0, 0, k21, k22, 0, 0}),
               Matrix(4, 2, {0, 0, 0, 0, i11, i12, i12, i22}), Matrix(2, 4, {1, 0, 0, 0, 0, 1, 0, 0})};
}

}  // namespace

TEST(PolePlacement, OpenLoopModelMatchesTheThesis) {
  const Model m = manutec();
  const Resolvent r = resolvent(m.a);
  // F(s) = s^4 + 77.923 s^2 + 847.990 (b.4)
  EXPECT_NEAR(r.f[3], 0, 1e-9);
  EXPECT_NEAR(r.f[2], 77.923, 0.01);
  EXPECT_NEAR(r.f[1], 0, 1e-9);
  EXPECT_NEAR(r.f[0], 847.99, 0.1);
  // the open-loop poles are +-8.053i and +-3.616i (the thesis prints +-8.3422i)
  EXPECT_LT(worst_match(eigenvalues(m.a), {cd(0, 8.053), cd(0, -8.053), cd(0, 3.616), cd(0, -3.616)}), 1e-3);
}

// Annex b: omega 5 and 8, zeta 1.2 and 0.886, k = (1 1)
TEST(PolePlacement, RankOnePdPutsThePolesWhereAsked) {
  const Model m = manutec();
  const std::vector<double> want = poly_from_damping({{1.2, 5}, {0.886, 8}});
  EXPECT_NEAR(want[3], 26.176, 1e-3);  // (b.6)
  EXPECT_NEAR(want[2], 259.112, 1e-2);
  EXPECT_NEAR(want[1], 1122.4, 1e-1);
  EXPECT_NEAR(want[0], 1600, 1e-6);
  const PdDesign d = place_pd_rank1(m.a, m.b, m.c, {1, 1}, want);
  ASSERT_TRUE(d.ok);
  std::printf("PD: p = (%.2f, %.2f), r = (%.2f, %.2f)\n", d.p[0], d.p[1], d.r[0], d.r[1]);
  const std::vector<cd> poles = eigenvalues(closed_loop_pd(m.a, m.b, m.c, d.P, d.R));
  EXPECT_LT(worst_match(poles, damping_roots({{1.2, 5}, {0.886, 8}})), 1e-8);
  // on the thesis's rounded model, the exact solution of the same equations:
  // p = (-848.67, 80.79), r = (258.66, 125.84) (the gains are sensitive to that rounding)
  const Model mp = manutec_printed();
  const PdDesign dp = place_pd_rank1(mp.a, mp.b, mp.c, {1, 1}, want);
  ASSERT_TRUE(dp.ok);
  EXPECT_NEAR(dp.p[0], -848.67, 1.0);
  EXPECT_NEAR(dp.p[1], 80.79, 0.3);
  EXPECT_NEAR(dp.r[0], 258.66, 0.3);
  EXPECT_NEAR(dp.r[1], 125.84, 0.3);
  // the printed gains (3.95-3.96) are close: stable, poles near the target
  const Matrix pp = outer({-848.769, 81.271}, {1, 1}), rp = outer({258.553, 126.255}, {1, 1});
  const std::vector<cd> printed = eigenvalues(closed_loop_pd(mp.a, mp.b, mp.c, pp, rp));
  EXPECT_LT(max_real(printed), -2.0);
  EXPECT_LT(worst_match(printed, {cd(-2.643, 0), cd(-10.724, 0), cd(-6.526, 3.743), cd(-6.526, -3.743)}), 0.02);
}

// Annex c: the PID poles of [39]/[40] (zeta2 = 0.387, not the printed 0.087), qhat = I, k = (1 1)
TEST(PolePlacement, RankOnePidPutsThePolesWhereAskedAndThePrintedGainsAreUnstable) {
  const Model m = manutec();
  const std::vector<std::pair<double, double>> zo = {{1.685, 1.948}, {0.387, 3.516}, {0.809, 6.65}};
  const std::vector<double> want = poly_from_damping(zo);
  EXPECT_NEAR(want[5], 20.045, 2e-3);  // (c.26)
  EXPECT_NEAR(want[0], 2074.526, 0.5);
  const PidDesign d = place_pid_rank1(m.a, m.b, m.c, {1, 1}, Matrix::identity(2), want);
  ASSERT_TRUE(d.ok);
  std::printf("PID: p = (%.2f, %.2f), q = (%.1f, %.2f), r = (%.2f, %.2f)\n", d.p[0], d.p[1], d.q[0], d.q[1], d.r[0],
              d.r[1]);
  const std::vector<cd> poles = eigenvalues(closed_loop_pid(m.a, m.b, m.c, d.P, d.Q, d.R));
  EXPECT_LT(worst_match(poles, damping_roots(zo)), 1e-6);
  // on the rounded model, the exact solution: p = (-53.63, 169.22), q = (61661.2, 712.64),
  // r = (3811.71, 1178.45)
  const Model mp = manutec_printed();
  const PidDesign dp = place_pid_rank1(mp.a, mp.b, mp.c, {1, 1}, Matrix::identity(2), want);
  ASSERT_TRUE(dp.ok);
  std::printf("PID on the printed model: p = (%.2f, %.2f), q = (%.1f, %.2f), r = (%.2f, %.2f)\n", dp.p[0], dp.p[1],
              dp.q[0], dp.q[1], dp.r[0], dp.r[1]);
  EXPECT_NEAR(dp.p[0] / -53.63, 1.0, 0.01);
  EXPECT_NEAR(dp.q[0] / 61661.2, 1.0, 0.01);
  EXPECT_NEAR(dp.r[0] / 3811.71, 1.0, 0.01);
  EXPECT_NEAR(dp.r[1] / 1178.45, 1.0, 0.01);
  // the thesis's printed gains (3.103-3.105): unstable, with or without qhat
  const Matrix pp = outer({-226.85, -985.2829}, {1, 1}), rp = outer({-31.0388, 77.9294}, {1, 1});
  const Matrix qp = outer({-1105.77, 4237.74}, {1, 1});
  const double printed = max_real(eigenvalues(closed_loop_pid(m.a, m.b, m.c, pp, qp, rp)));
  const double printed_qhat = max_real(eigenvalues(closed_loop_pid(m.a, m.b, m.c, pp, qp + Matrix::identity(2), rp)));
  std::printf("printed PID gains: largest real part %.2f (with qhat %.2f)\n", printed, printed_qhat);
  EXPECT_GT(printed, 1.0);
  EXPECT_GT(printed_qhat, 1.0);
}

// For a DC joint (G = K / (s (tau s + 1)), duty -> counts): the designed PID puts the three
// poles where asked; converted to the firmware's fixed-point gains and run in pid.h at 1 kHz
// on the plant, a small step (no saturation) follows the continuous design's response
TEST(PolePlacement, DcJointPidDesignRunsInTheFixedPointPid) {
  const double k = 400, tau = 0.05;
  const std::vector<cd> poles = {cd(-15, 0), cd(-20, 0), cd(-25, 0)};
  const DcPidGains g = design_dc_joint_pid(k, tau, poles);
  ASSERT_TRUE(g.ok);
  std::printf("DC joint: Kp %.4f /count, Ki %.4f /(count s), Kd %.6f s/count\n", g.kp, g.ki, g.kd);
  const DcJointModel mdl = dc_joint_model(k, tau);
  const std::vector<cd> got = eigenvalues(closed_loop_pid(mdl.a, mdl.b, mdl.c, Matrix(1, 1, {g.kp}), Matrix(1, 1, {g.ki}),
                                                          Matrix(1, 1, {g.kd})));
  EXPECT_LT(worst_match(got, poles), 1e-8);

  const int rate = 1000, units = 16;
  const PidGainsResult fixed = to_pid_gains(g, rate, units);
  ASSERT_TRUE(fixed.ok);
  Pid pid;
  ASSERT_EQ(pid.configure(PidConfig{fixed.gains, 32767, 32767, 0, 0}), PidStatus::ok);
  const double step = 4;  // counts: Kp * 4 = 0.59 duty, inside the linear range
  double pos = 0, vel = 0;                  // the firmware's loop
  double lpos = 0, lvel = 0, lz = 0;        // the continuous design, same plant
  double worst = 0;
  pid.start(0, 0, 0);
  for (int n = 0; n < rate; ++n) {
    const double duty = pid.update((int32_t)(step * units), (int32_t)std::lround(pos * units)) / 32767.0;
    for (int i = 0; i < 10; ++i) {
      const double h = 0.1 / rate;
      vel += (k * duty - vel) / tau * h;
      pos += vel * h;
      const double u = g.kp * (step - lpos) + g.ki * lz - g.kd * lvel;
      lz += (step - lpos) * h;
      lvel += (k * u - lvel) / tau * h;
      lpos += lvel * h;
    }
    worst = std::max(worst, std::abs(pos - lpos));
  }
  std::printf("fixed-point PID vs continuous design, worst difference %.3f counts\n", worst);
  EXPECT_LT(worst, 0.1 * step);
  EXPECT_NEAR(pos, step, 0.05);
}

TEST(PolePlacement, RefusesShapesTheMethodCannotSolve) {
  const Model m = manutec();
  EXPECT_FALSE(place_pd_rank1(m.a, m.b, m.c, {1, 1}, {1, 2, 3}).ok);  // wrong degree
  const Matrix a3 = Matrix::identity(3);
  EXPECT_FALSE(place_pd_rank1(a3, Matrix(3, 1, {0, 0, 1}), Matrix(1, 3, {1, 0, 0}), {1}, {1, 1, 1, 1}).ok);  // n != 2m
}
