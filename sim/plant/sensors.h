// The arm's sensors and the operator's inputs, as voltages and contact states.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "arm_plant_config.h"
#include "noise.h"

namespace wmra {
namespace plant {

// What simavr 1.6 does with an analog input: counts = mV * 1023 / Vref, truncated, clamped to
// 0..1023 (measured with test/sim/plant; the chip itself rounds mV * 1024 / Vref).
inline int adc_counts_simavr(double mv, double vref_mv = kAdcRefMv) {
  if (mv <= 0) return 0;
  const long c = (long)(std::floor(mv) * 1023 / vref_mv);
  return c > 1023 ? 1023 : (int)c;
}

enum class PotFault : uint8_t { ok, open, shorted };

// A joint potentiometer with its conditioning: joint range -> kPotLowMv..kPotHighMv, RC low-pass
// (tau = 1 ms), faults at the rails, seeded noise added when the ADC samples it.
class Potentiometer {
 public:
  Potentiometer(double q_min_rad, double q_max_rad, double noise_mv, double tau_s, NoiseStream noise)
      : q_min_(q_min_rad), q_max_(q_max_rad), noise_mv_(noise_mv), tau_s_(tau_s), noise_(noise) {}

  // the conditioned voltage for a joint angle, without filter and noise
  double ideal_mv(double q_rad) const {
    return kPotLowMv + (q_rad - q_min_) / (q_max_ - q_min_) * (kPotHighMv - kPotLowMv);
  }
  // the joint angle for a voltage (the inverse of ideal_mv; what a calibrated firmware computes)
  double angle_of_mv(double mv) const {
    return q_min_ + (mv - kPotLowMv) / (kPotHighMv - kPotLowMv) * (q_max_ - q_min_);
  }
  void reset(double q_rad) { filtered_mv_ = source_mv(q_rad); }
  void step(double q_rad, double dt) {
    const double target = source_mv(q_rad);
    filtered_mv_ = tau_s_ > 0 ? target + (filtered_mv_ - target) * std::exp(-dt / tau_s_) : target;
  }
  void set_fault(PotFault f) { fault_ = f; }
  PotFault fault() const { return fault_; }
  // one ADC sample: filtered voltage plus noise, within the rails
  double sample_mv() {
    double v = filtered_mv_ + (noise_mv_ > 0 ? noise_mv_ * noise_.normal() : 0.0);
    return v < 0 ? 0 : v > kAdcRefMv ? kAdcRefMv : v;
  }
  double filtered_mv() const { return filtered_mv_; }

 private:
  double source_mv(double q_rad) const {
    switch (fault_) {
      case PotFault::open: return kPotOpenMv;
      case PotFault::shorted: return kPotShortMv;
      default: {
        const double v = ideal_mv(q_rad);
        return v < 0 ? 0 : v > kAdcRefMv ? kAdcRefMv : v;
      }
    }
  }
  double q_min_, q_max_, noise_mv_, tau_s_;
  NoiseStream noise_;
  double filtered_mv_ = 0;
  PotFault fault_ = PotFault::ok;
};

// A limit switch and its RC debounce: the contact is closed past its trip angle (below it for a
// low switch, above for a high one, within +-half_width of every whole turn for a zero cam); the
// line the Mega sees is closed once the RC voltage passes half the swing.
class LimitSwitch {
 public:
  enum class Kind : uint8_t { low, high, zero };
  LimitSwitch(Kind kind, double trip_rad, double tau_s) : kind_(kind), trip_(trip_rad), tau_s_(tau_s) {}

  bool contact_closed(double q_rad) const {
    switch (kind_) {
      case Kind::low: return q_rad <= trip_;
      case Kind::high: return q_rad >= trip_;
      default: {
        const double turn = 2.0 * kPi;
        const double r = q_rad - trip_ - turn * std::floor((q_rad - trip_) / turn + 0.5);
        return std::fabs(r) <= kZeroSwitchHalfWidthRad;
      }
    }
  }
  void reset(double q_rad) {
    v_ = contact_closed(q_rad) ? 1.0 : 0.0;
    closed_ = v_ > 0.5;
  }
  void step(double q_rad, double dt) {
    const double target = contact_closed(q_rad) ? 1.0 : 0.0;
    v_ = tau_s_ > 0 ? target + (v_ - target) * std::exp(-dt / tau_s_) : target;
    closed_ = v_ > 0.5;
  }
  bool closed() const { return closed_; }  // as the Mega sees it (after the debounce RC)

 private:
  Kind kind_;
  double trip_, tau_s_;
  double v_ = 0;
  bool closed_ = false;
};

// A push-button contact that bounces: after each change it flips a few times within bounce_s
// (seeded) before it settles.
class BouncingContact {
 public:
  BouncingContact(double bounce_s, NoiseStream noise) : bounce_s_(bounce_s), noise_(noise) {}

  void set(bool closed, double t_s) {
    if (closed == target_) return;
    settled_ = closed_at(t_s);
    target_ = closed;
    edges_.clear();
    // an odd number of edges, alternating, the last one at the new state
    const int n = bounce_s_ > 0 ? 3 + 2 * (int)(noise_.next() % 3) : 1;
    for (int i = 0; i < n; ++i) {
      const double t = t_s + (i == 0 ? 0.0 : bounce_s_ * (i + 0.8 * noise_.uniform()) / n);
      edges_.push_back({t, (i % 2 == 0) ? closed : !closed});
    }
  }
  bool closed_at(double t_s) const {
    bool level = settled_;
    for (const auto& e : edges_) {
      if (e.t_s > t_s) break;
      level = e.closed;
    }
    return level;
  }
  void settle(double t_s) {  // forget the edges that are over
    if (!edges_.empty() && edges_.back().t_s <= t_s) {
      settled_ = target_;
      edges_.clear();
    }
  }
  bool target() const { return target_; }
  void reset(bool closed) {
    target_ = settled_ = closed;
    edges_.clear();
  }

 private:
  struct Edge {
    double t_s;
    bool closed;
  };
  double bounce_s_;
  NoiseStream noise_;
  bool target_ = false;
  bool settled_ = false;
  std::vector<Edge> edges_;
};

// The KY-023 joystick's two axes through the board's amplifiers.
class JoystickAxes {
 public:
  JoystickAxes(const double centre_offset_mv[2], double noise_mv, NoiseStream nx, NoiseStream ny)
      : noise_mv_(noise_mv), noise_{nx, ny} {
    offset_[0] = centre_offset_mv[0];
    offset_[1] = centre_offset_mv[1];
  }
  void set(double x, double y) {
    d_[0] = x < -1 ? -1 : x > 1 ? 1 : x;
    d_[1] = y < -1 ? -1 : y > 1 ? 1 : y;
  }
  void set_unplugged(bool open) { open_ = open; }
  bool unplugged() const { return open_; }
  double deflection(int axis) const { return d_[axis]; }
  double ideal_mv(int axis) const { return open_ ? kStickOpenMv : kStickCentreMv + offset_[axis] + d_[axis] * kStickFullScaleMv; }
  double sample_mv(int axis) {  // axis 0 = X, 1 = Y
    if (open_) return kStickOpenMv;
    double v = ideal_mv(axis) + (noise_mv_ > 0 ? noise_mv_ * noise_[axis].normal() : 0.0);
    return v < 0 ? 0 : v > kAdcRefMv ? kAdcRefMv : v;
  }

 private:
  double offset_[2];
  double noise_mv_;
  NoiseStream noise_[2];
  double d_[2] = {0, 0};
  bool open_ = false;
};

}  // namespace plant
}  // namespace wmra
