// Host-side design helper (double, std): seed 1's pole placement of rank-1 PD and PID output
// feedback for a linearised model (Seraji's method; Miranda's thesis, sections 3.3-3.4), and its use for a
// DC joint. Not for the AVR.
//
// Method. For x' = A x + B u, y = C x, the PD law u = P (v - y) - R y' with the rank-1 gains
// P = p k, R = r k (p, r: m x 1, k: 1 x l chosen) gives the closed-loop polynomial
//     H(s) = F(s) + k W(s) (p + s r),   F = det(sI - A),  W(s) = C adj(sI - A) B,
// linear in (p, r): matching H = (1 + k M1 r) D(s) with the wanted D(s) coefficient by
// coefficient gives n equations in 2m unknowns (square when
// n = 2m). For the PID law u = P e + Q z - R y', z = integral of e, the system is augmented
// with z (A1* = [[A, B Qhat], [-C, 0]], Qhat full rank, pre-applied), K*(s) = (p + q/s + r s) k,
// H(s) = F*(s) + k W*(s) (p + q/s + r s), n + l equations in 3m unknowns; the integral gain is
// Q = Qhat + q k. F and adj(sI - A) come from the Faddeev-LeVerrier recursion.
//
// Errata (Miranda's thesis, section 3.4): the printed PID design of Annex c has sign errors in F*(s), a
// W*(s) that does not match its A1*, a P row that does not solve its own equations, and gains
// that put closed-loop poles at 4.11 +- 4.76j and 0.17 +- 4.15j: unstable. This helper
// reproduces the method; test_pole_placement checks that its gains put the poles where asked
// (eigenvalues of the closed-loop matrix, computed independently with Eigen) and that the
// printed gains are indeed unstable. The printed PD gains of Annex b are close to the correct
// ones (rounding).
#pragma once

#if defined(__AVR__)
#error "pole_placement.h is a host-side design helper (double, std::vector)"
#endif

#include <cmath>
#include <complex>
#include <cstddef>
#include <utility>
#include <vector>

#include "control/pid.h"

namespace wmra {
namespace control {
namespace design {

struct Matrix {
  int rows = 0, cols = 0;
  std::vector<double> a;
  Matrix() = default;
  Matrix(int r, int c) : rows(r), cols(c), a((size_t)r * c, 0.0) {}
  Matrix(int r, int c, std::vector<double> v) : rows(r), cols(c), a(std::move(v)) {}
  double& operator()(int i, int j) { return a[(size_t)i * cols + j]; }
  double operator()(int i, int j) const { return a[(size_t)i * cols + j]; }
  static Matrix identity(int n) {
    Matrix m(n, n);
    for (int i = 0; i < n; ++i) m(i, i) = 1;
    return m;
  }
};

inline Matrix operator*(const Matrix& x, const Matrix& y) {
  Matrix m(x.rows, y.cols);
  for (int i = 0; i < x.rows; ++i)
    for (int k = 0; k < x.cols; ++k)
      for (int j = 0; j < y.cols; ++j) m(i, j) += x(i, k) * y(k, j);
  return m;
}
inline Matrix operator+(Matrix x, const Matrix& y) {
  for (size_t i = 0; i < x.a.size(); ++i) x.a[i] += y.a[i];
  return x;
}
inline Matrix operator-(Matrix x, const Matrix& y) {
  for (size_t i = 0; i < x.a.size(); ++i) x.a[i] -= y.a[i];
  return x;
}
inline Matrix scaled(Matrix x, double s) {
  for (double& v : x.a) v *= s;
  return x;
}

// Solves the square system M x = b by Gaussian elimination with partial pivoting;
// false if M is singular (to working precision).
inline bool solve(Matrix m, std::vector<double> b, std::vector<double>& x) {
  const int n = m.rows;
  double scale = 0;
  for (double v : m.a) scale = std::max(scale, std::abs(v));
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(m(r, c)) > std::abs(m(piv, c))) piv = r;
    if (std::abs(m(piv, c)) <= 1e-13 * scale) return false;
    for (int j = 0; j < n; ++j) std::swap(m(c, j), m(piv, j));
    std::swap(b[c], b[piv]);
    for (int r = c + 1; r < n; ++r) {
      const double f = m(r, c) / m(c, c);
      for (int j = c; j < n; ++j) m(r, j) -= f * m(c, j);
      b[r] -= f * b[c];
    }
  }
  x.assign(n, 0);
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int j = r + 1; j < n; ++j) s -= m(r, j) * x[j];
    x[r] = s / m(r, r);
  }
  return true;
}

// Monic polynomial prod (s - root), coefficients indexed by power (c[n] = 1).
inline std::vector<double> poly_from_roots(const std::vector<std::complex<double>>& roots) {
  std::vector<std::complex<double>> c{1.0};
  for (const auto& r : roots) {
    std::vector<std::complex<double>> next(c.size() + 1, 0.0);
    for (size_t i = 0; i < c.size(); ++i) {
      next[i + 1] += c[i];
      next[i] -= r * c[i];
    }
    c = next;
  }
  std::vector<double> out;
  for (const auto& v : c) out.push_back(v.real());
  return out;
}

// prod (s^2 + 2 zeta omega s + omega^2): the thesis's way of choosing poles
inline std::vector<double> poly_from_damping(const std::vector<std::pair<double, double>>& zeta_omega) {
  std::vector<std::complex<double>> roots;
  for (const auto& zo : zeta_omega) {
    const double z = zo.first, w = zo.second;
    const std::complex<double> d = std::sqrt(std::complex<double>(z * z - 1, 0));
    roots.push_back(w * (-z + d));
    roots.push_back(w * (-z - d));
  }
  return poly_from_roots(roots);
}

// det(sI - A) (coefficients by power, monic) and adj(sI - A) = sum_k adj[k] s^(n-1-k)
struct Resolvent {
  std::vector<double> f;
  std::vector<Matrix> adj;
};
inline Resolvent resolvent(const Matrix& a) {
  const int n = a.rows;
  Resolvent r;
  r.f.assign(n + 1, 0);
  r.f[n] = 1;
  Matrix bk = Matrix::identity(n);
  for (int k = 1; k <= n; ++k) {
    r.adj.push_back(bk);
    const Matrix ab = a * bk;
    double tr = 0;
    for (int i = 0; i < n; ++i) tr += ab(i, i);
    const double ck = -tr / k;
    r.f[n - k] = ck;
    bk = ab + scaled(Matrix::identity(n), ck);
  }
  return r;
}

// k W(s) = k C adj(sI - A) B as rows of m coefficients, indexed by power 0..n-1
inline std::vector<std::vector<double>> k_w(const Resolvent& res, const Matrix& b, const Matrix& c,
                                            const std::vector<double>& k) {
  const int n = (int)res.adj.size();
  std::vector<std::vector<double>> w(n, std::vector<double>(b.cols, 0.0));
  for (int i = 0; i < n; ++i) {
    const Matrix m = c * res.adj[i] * b;  // coefficient of s^(n-1-i)
    for (int j = 0; j < b.cols; ++j) {
      double s = 0;
      for (int l = 0; l < c.rows; ++l) s += k[l] * m(l, j);
      w[n - 1 - i][j] = s;
    }
  }
  return w;
}

// rank-1 outer product column * row
inline Matrix outer(const std::vector<double>& col, const std::vector<double>& row) {
  Matrix m((int)col.size(), (int)row.size());
  for (size_t i = 0; i < col.size(); ++i)
    for (size_t j = 0; j < row.size(); ++j) m((int)i, (int)j) = col[i] * row[j];
  return m;
}

struct PdDesign {
  bool ok = false;
  std::vector<double> p, r;  // P = p k, R = r k
  Matrix P, R;
};

// Rank-1 PD: closed-loop polynomial = desired (monic, by power, degree n). Needs n = 2m.
inline PdDesign place_pd_rank1(const Matrix& a, const Matrix& b, const Matrix& c, const std::vector<double>& k,
                               const std::vector<double>& desired) {
  PdDesign d;
  const int n = a.rows, m = b.cols;
  if (n != 2 * m || (int)desired.size() != n + 1 || (int)k.size() != c.rows) return d;
  const Resolvent res = resolvent(a);
  const auto w = k_w(res, b, c, k);
  Matrix e(n, 2 * m);
  std::vector<double> rhs(n);
  for (int t = 0; t < n; ++t) {
    for (int j = 0; j < m; ++j) {
      e(t, j) = w[t][j];                                                      // p
      e(t, m + j) = (t > 0 ? w[t - 1][j] : 0.0) - desired[t] * w[n - 1][j];  // r
    }
    rhs[t] = desired[t] - res.f[t];
  }
  std::vector<double> x;
  if (!solve(e, rhs, x)) return d;
  d.p.assign(x.begin(), x.begin() + m);
  d.r.assign(x.begin() + m, x.end());
  d.P = outer(d.p, k);
  d.R = outer(d.r, k);
  d.ok = true;
  return d;
}

struct PidDesign {
  bool ok = false;
  std::vector<double> p, q, r;  // P = p k, Q = Qhat + q k, R = r k
  Matrix P, Q, R;
};

// Rank-1 PID with a pre-applied integral gain qhat (m x l, full rank): closed-loop polynomial
// = desired (monic, by power, degree n + l). Needs n + l = 3m.
inline PidDesign place_pid_rank1(const Matrix& a, const Matrix& b, const Matrix& c, const std::vector<double>& k,
                                 const Matrix& qhat, const std::vector<double>& desired) {
  PidDesign d;
  const int n = a.rows, m = b.cols, l = c.rows, nn = n + l;
  if (nn != 3 * m || (int)desired.size() != nn + 1 || (int)k.size() != l) return d;
  Matrix a1(nn, nn), b1(nn, m), c1(l, nn);
  const Matrix bq = b * qhat;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) a1(i, j) = a(i, j);
    for (int j = 0; j < l; ++j) a1(i, n + j) = bq(i, j);
    for (int j = 0; j < m; ++j) b1(i, j) = b(i, j);
  }
  for (int i = 0; i < l; ++i)
    for (int j = 0; j < n; ++j) {
      a1(n + i, j) = -c(i, j);
      c1(i, j) = c(i, j);
    }
  const Resolvent res = resolvent(a1);
  const auto w = k_w(res, b1, c1, k);
  double wscale = 0, w0 = 0;
  for (const auto& row : w)
    for (double v : row) wscale = std::max(wscale, std::abs(v));
  for (double v : w[0]) w0 = std::max(w0, std::abs(v));
  if (w0 > 1e-9 * wscale) return d;  // q/s k W*(s) would not be a polynomial
  Matrix e(nn, 3 * m);
  std::vector<double> rhs(nn);
  for (int t = 0; t < nn; ++t) {
    for (int j = 0; j < m; ++j) {
      e(t, j) = w[t][j];                                                       // p
      e(t, m + j) = t + 1 < nn ? w[t + 1][j] : 0.0;                            // q
      e(t, 2 * m + j) = (t > 0 ? w[t - 1][j] : 0.0) - desired[t] * w[nn - 1][j];  // r
    }
    rhs[t] = desired[t] - res.f[t];
  }
  std::vector<double> x;
  if (!solve(e, rhs, x)) return d;
  d.p.assign(x.begin(), x.begin() + m);
  d.q.assign(x.begin() + m, x.begin() + 2 * m);
  d.r.assign(x.begin() + 2 * m, x.end());
  d.P = outer(d.p, k);
  d.Q = qhat + outer(d.q, k);
  d.R = outer(d.r, k);
  d.ok = true;
  return d;
}

// Closed-loop state matrices (for checks and simulation), reference v = 0:
//   PD:  u = -P y - R y'            -> x' = A_cl x
//   PID: u = -P y + Q z - R y', z' = -y  -> (x, z)' = A_cl (x, z)
// with y' = C (A x + B u), solved for u.
inline Matrix closed_loop_pd(const Matrix& a, const Matrix& b, const Matrix& c, const Matrix& p, const Matrix& r) {
  const int m = b.cols;
  const Matrix mm = Matrix::identity(m) + r * c * b;
  const Matrix g = p * c + r * c * a;  // m x n
  // solve mm X = g column by column
  Matrix x(m, a.cols);
  for (int j = 0; j < a.cols; ++j) {
    std::vector<double> col(m), sol;
    for (int i = 0; i < m; ++i) col[i] = g(i, j);
    solve(mm, col, sol);
    for (int i = 0; i < m; ++i) x(i, j) = sol[i];
  }
  return a - b * x;
}
inline Matrix closed_loop_pid(const Matrix& a, const Matrix& b, const Matrix& c, const Matrix& p, const Matrix& q,
                              const Matrix& r) {
  const int n = a.rows, m = b.cols, l = c.rows;
  const Matrix mm = Matrix::identity(m) + r * c * b;
  const Matrix g = p * c + r * c * a;
  Matrix gx(m, n), gz(m, l);
  for (int j = 0; j < n + l; ++j) {
    std::vector<double> col(m), sol;
    for (int i = 0; i < m; ++i) col[i] = j < n ? g(i, j) : q(i, j - n);
    solve(mm, col, sol);
    for (int i = 0; i < m; ++i) (j < n ? gx(i, j) : gz(i, j - n)) = sol[i];
  }
  Matrix acl(n + l, n + l);
  const Matrix top = a - b * gx, bz = b * gz;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) acl(i, j) = top(i, j);
    for (int j = 0; j < l; ++j) acl(i, n + j) = bz(i, j);
  }
  for (int i = 0; i < l; ++i)
    for (int j = 0; j < n; ++j) acl(n + i, j) = -c(i, j);
  return acl;
}

// --- DC joint: duty (fraction of full PWM) -> position (counts), G(s) = K / (s (tau s + 1)),
// K in counts/s per unit duty (the steady speed at full duty), tau the mechanical time constant.
struct DcJointModel {
  Matrix a, b, c;
};
inline DcJointModel dc_joint_model(double k_counts_s, double tau_s) {
  return DcJointModel{Matrix(2, 2, {0, 1, 0, -1 / tau_s}), Matrix(2, 1, {0, k_counts_s / tau_s}), Matrix(1, 2, {1, 0})};
}

// Continuous PID gains (duty fraction per count, per count-second, seconds per count) that put
// the three closed-loop poles at the given roots, by the rank-1 method with k = 1 and the
// integral gain qhat pre-applied as in Annex c (any non-zero value; it is added back into Ki).
struct DcPidGains {
  bool ok = false;
  double kp = 0, ki = 0, kd = 0;
};
inline DcPidGains design_dc_joint_pid(double k_counts_s, double tau_s, const std::vector<std::complex<double>>& poles,
                                      double qhat = 1.0) {
  const DcJointModel g = dc_joint_model(k_counts_s, tau_s);
  const PidDesign d = place_pid_rank1(g.a, g.b, g.c, {1.0}, Matrix(1, 1, {qhat}), poly_from_roots(poles));
  DcPidGains out;
  if (!d.ok) return out;
  out.ok = true;
  out.kp = d.P(0, 0);
  out.ki = d.Q(0, 0);
  out.kd = d.R(0, 0);
  return out;
}

// The firmware's fixed-point per-sample gains (pid.h) from continuous ones
inline PidGainsResult to_pid_gains(const DcPidGains& g, int32_t rate_hz, int32_t units_per_count) {
  auto q = [&](double v, int frac) { return v * 32768.0 * (double)(1 << frac) / units_per_count; };
  const double kp = q(g.kp, 4), ki = q(g.ki / rate_hz, 8), kd = q(g.kd * rate_hz, 0);
  auto fits = [](double v) { return v >= 0 && v <= 32767.49; };
  return PidGainsResult{PidGains{(int16_t)std::lround(kp), (int16_t)std::lround(ki), (int16_t)std::lround(kd)},
                        g.ok && fits(kp) && fits(ki) && fits(kd)};
}

}  // namespace design
}  // namespace control
}  // namespace wmra
