#include "sim.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "control/relay.h"
#include "control/step_ramp.h"
#include "kinematics/arm_model.h"
#include "models/dc_joint_rl.h"
#include "models/seed1_motor.h"
#include "models/stepper_rotor.h"
#include "plant/arm_statics.h"
#include "plant/motors.h"
#include "plant/sensors.h"

namespace wmra {
namespace jointsim {

namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

const char* seed0_status_text(control::Seed0Status s) {
  switch (s) {
    case control::Seed0Status::gain_invalid:
      return "K_P or K_D out of the controller's range (K_P < 128, K_D / dt < 128)";
    case control::Seed0Status::accel_not_positive:
      return "alpha x dt rounds to less than 1 step/s per period";
    case control::Seed0Status::speed_invalid:
      return "V_S out of the controller's range";
    case control::Seed0Status::band_invalid:
      return "deadband / near band invalid";
    default:
      return "ok";
  }
}

std::string ramp_status_text(control::RampStatus s, uint32_t tick_hz) {
  switch (s) {
    case control::RampStatus::accel_not_positive:
      return "alpha must be positive";
    case control::RampStatus::accel_too_low: {
      // the first interval sqrt(2 / (31/32 a)) must fit the 16-bit compare register
      const double least = 2.0 * 32 / 31 * std::pow(tick_hz / 65534.0, 2);
      return "alpha is too low for the step timer at " + std::to_string(tick_hz) +
             " Hz (its first interval must fit 16 bits): at least " + fmt("%.0f", std::ceil(least)) + " steps/s^2";
    }
    case control::RampStatus::accel_too_high:
      return "alpha is too high for the step timer";
    case control::RampStatus::min_interval_invalid:
      return "minimum step interval invalid";
    case control::RampStatus::speed_range_too_wide:
      return "alpha too low for V_S (more than 2^22 ramp levels)";
    default:
      return "ok";
  }
}

// The encoder's count edges sit 1/8 count off the power-up position, so that the rotor's rest
// positions (0.75 count apart) never fall on an edge.
int32_t seed0_encoder(const StepperRotor& r) {
  return (int32_t)std::floor(r.angle_steps() * kSeed0CountsPerHalfStep + 0.125);
}

}  // namespace

// ------------------------------------------------------------------------------------ seed 0

StepperRotorParams seed0_rotor_params() {
  return StepperRotorParams{
      kSeed0HoldingTorqueNm,  kSeed0DetentTorqueNm, kSeed0CornerSpeedRadS, kSeed0InertiaKgm2,
      kSeed0ViscousNmPerRadS, kSeed0DampingRatio,   kSeed0RotorTeeth,      kSeed0HalfStepsPerElectricalPeriod};
}

namespace {

template <uint32_t kTickHz>
Seed0Result run_seed0_at(const Seed0Options& o) {
  using namespace control;
  const int32_t dt_ms = (int32_t)std::lround(o.dt_s * 1000);
  if (dt_ms < 1 || std::fabs(dt_ms - o.dt_s * 1000) > 1e-6)
    throw BadOption("dt must be a whole number of milliseconds");
  const int32_t alpha = (int32_t)std::lround(o.alpha_steps_s2);
  const int32_t v_s = (int32_t)std::lround(o.v_s_steps_s);
  // joint 1 of Appendix A for the firmware variant's bands (seed0 3.5)
  const Seed0Config cfg{o.variant,
                        (int32_t)std::lround(o.kp * 256),
                        seed0_kd_q8(Ratio{(int64_t)std::llround(o.kd_s * 1e6), 1000000}, dt_ms),
                        seed0_accel_per_period(alpha, dt_ms),
                        v_s,
                        1,
                        10,
                        2 * 256,
                        25};
  Seed0StepperController ctl;
  const Seed0Status cs = ctl.configure(cfg);
  if (cs != Seed0Status::ok) throw BadOption(std::string("seed-0 controller: ") + seed0_status_text(cs));
  StepRamp<kTickHz> ramp;
  const int32_t ramp_alpha = o.ramp_alpha_steps_s2 > 0 ? (int32_t)std::lround(o.ramp_alpha_steps_s2) : alpha;
  // the ramp's top speed 2 V_S: never the limit (V_C <= V_S)
  const uint16_t min_interval = (uint16_t)std::max<int64_t>(1, std::min<int64_t>(65534, kTickHz / (2 * (int64_t)v_s)));
  const RampStatus rs = ramp.configure({ramp_alpha, min_interval});
  if (rs != RampStatus::ok) throw BadOption("step ramp: " + ramp_status_text(rs, kTickHz));

  StepperRotor rotor(seed0_rotor_params());
  const int64_t kSubstepTicks = kTickHz / 40000;  // 25 us
  const int64_t period_ticks = (int64_t)dt_ms * (kTickHz / 1000);
  const double tick_s = 1.0 / kTickHz;

  Seed0Result res;
  int64_t now = 0;
  bool pending = false;  // a step edge is scheduled
  int64_t edge = 0;
  int8_t edge_dir = 0;
  uint32_t last_interval = 0;  // Q16 ticks, of the previous step in this run of steps (0: none)
  int8_t last_dir = 0;
  auto fetch = [&](int64_t from) {  // the ramp's next step, timed from the edge at `from`
    const auto s = ramp.next();
    if (s.interval_ticks == 0) {
      pending = false;
      last_interval = 0;
      return;
    }
    // the profile's own intervals (Q16.16 ticks), before the timer rounds them to whole ticks
    const uint32_t interval_q16 = ramp.last_interval_q16();
    if (last_interval != 0 && s.dir == last_dir) {
      const double t1 = last_interval * tick_s / 65536, t2 = interval_q16 * tick_s / 65536;
      res.max_train_accel_steps_s2 =
          std::max(res.max_train_accel_steps_s2, std::fabs(1 / t2 - 1 / t1) / ((t1 + t2) / 2));
    }
    last_interval = interval_q16;
    last_dir = s.dir;
    pending = true;
    edge = from + s.interval_ticks;
    edge_dir = s.dir;
  };

  const int periods = (int)std::lround(o.duration_s / o.dt_s);
  for (int k = 0; k < periods; ++k) {
    const int32_t v = ctl.update(o.target_counts, seed0_encoder(rotor));
    ramp.set_speed(v);
    if (!pending && ramp.wants_step()) fetch(now);  // from rest: the first interval counts from now
    const int64_t end = now + period_ticks;
    const double angle0 = rotor.angle_rad();
    while (now < end) {
      int64_t next = std::min(now + kSubstepTicks, end);
      if (pending && edge < next) next = edge;
      rotor.advance((next - now) * tick_s);
      now = next;
      while (pending && edge <= now) {
        rotor.step(edge_dir);
        ++res.steps_emitted;
        fetch(edge);
      }
    }
    res.rows.push_back(Seed0Row{now * tick_s, o.target_counts, seed0_encoder(rotor),
                                (rotor.angle_rad() - angle0) / o.dt_s / rotor.step_rad(), rotor.steps_lost(), v,
                                pending ? last_dir * 65536.0 * kTickHz / last_interval : 0.0});
  }
  return res;
}

}  // namespace

Seed0Result run_seed0(const Seed0Options& o) {
  if (o.timer_hz == 250000) return run_seed0_at<250000>(o);
  if (o.timer_hz == 2000000) return run_seed0_at<2000000>(o);
  throw BadOption("the step timer runs at 250000 or 2000000 Hz");
}

// ------------------------------------------------------------------------------------ seed 1

Seed1Result run_seed1_relay(const Seed1Options& o) {
  using namespace control;
  const double counts_per_rad = kSeed1CountsPerRev / (2 * kPi);
  Seed1Result res;
  res.dead_zone_counts = (int32_t)std::lround(o.deadzone_deg * kPi / 180 * counts_per_rad);
  Relay relay;
  if (relay.configure({res.dead_zone_counts, 0, 32767}) != RelayStatus::ok) throw BadOption("relay: dead zone invalid");
  FirstOrderMotor motor(kSeed1GainRadPerVS, kSeed1TimeConstantS);
  const int32_t target = (int32_t)std::floor(o.target_rad * counts_per_rad);
  const double period = 1.0 / o.fs_hz;
  const long samples = std::lround(o.duration_s * o.fs_hz);
  for (long n = 0; n <= samples; ++n) {
    const int32_t counts = (int32_t)std::floor(motor.angle_rad() * counts_per_rad);
    const int h = relay.level(target, counts);
    res.rows.push_back(Seed1Row{n * period, o.target_rad, motor.angle_rad(), motor.speed_rad_s(), h});
    motor.advance(h * o.drive_v, period);  // the ZOH over one sample (exact)
  }
  return res;
}

// ---------------------------------------------------------------------------------- DC joints

std::vector<double> default_dc_poles(int joint) {
  switch (joint) {
    case 2:
      return {-5, -7.5, -10};
    case 3:
      return {-6, -9, -12};
    default:
      return {-8, -12, -16};
  }
}

namespace {

// the pot chain's ADC counts for a joint angle, without noise, as a real number
double pot_counts(const plant::Potentiometer& pot, double q_rad) {
  return pot.ideal_mv(q_rad) * kAdcFullScaleCounts / plant::kAdcRefMv;
}

plant::JointLoads loads_at(int plant_joint, double q_rad, bool payload) {
  std::array<double, plant::kJoints> q{};
  q[plant_joint] = q_rad;
  return plant::joint_loads(q, true, payload);
}

void check_dc(const DcOptions& o) {
  if (o.joint < 2 || o.joint > 4) throw BadOption("joint must be 2, 3 or 4 (the DC joints)");
  const int j = o.joint - 1;
  const double lo = arm::q_min_rad(j), hi = arm::q_max_rad(j);
  if (o.start_rad < lo || o.start_rad > hi || o.start_rad + o.step_rad < lo || o.start_rad + o.step_rad > hi) {
    throw BadOption("start and start + step must be within joint " + std::to_string(o.joint) + "'s limits [" +
                    fmt("%.4f", lo) + ", " + fmt("%.4f", hi) + "] rad");
  }
}

}  // namespace

DcDesign design_dc_pid(const DcOptions& o) {
  check_dc(o);
  const int j = o.joint - 1;
  const double gear = plant::kGearRatio[j];
  const plant::Potentiometer pot(arm::q_min_rad(j), arm::q_max_rad(j), 0, 0, plant::NoiseStream());
  DcDesign d;
  d.counts_per_rad = pot_counts(pot, 1.0) - pot_counts(pot, 0.0);
  d.inertia_kgm2 = plant::kDcAssemblyInertiaKgm2 + loads_at(j, o.start_rad, o.payload).inertia_kgm2[j] / (gear * gear);
  const double slope = plant::kDcStallTorqueNm / plant::kDcNoLoadSpeedRadS + plant::kDcViscousNmPerRadS;
  d.tau_s = d.inertia_kgm2 / slope;
  d.k_counts_s = plant::kDcStallTorqueNm / slope / gear * d.counts_per_rad;
  for (double p : o.poles.empty() ? default_dc_poles(o.joint) : o.poles) d.poles.emplace_back(p, 0.0);
  d.continuous = control::design::design_dc_joint_pid(d.k_counts_s, d.tau_s, d.poles);
  const double rate = o.rate_hz > 0 ? o.rate_hz : kDcDefaultRateHz;
  d.fixed = control::design::to_pid_gains(d.continuous, (int32_t)std::lround(rate), kPositionUnitsPerCount);
  if (!d.continuous.ok || !d.fixed.ok) {
    throw BadOption("the poles give gains outside the PID's formats (Kp " + fmt("%.4g", d.continuous.kp) + ", Ki " +
                    fmt("%.4g", d.continuous.ki) + ", Kd " + fmt("%.4g", d.continuous.kd) +
                    "): choose poles nearer the origin, or another rate");
  }
  // The limits: full duty either way; the effort ramps from 0 to full in 50 ms; the dead-zone
  // inverse starts at the breakaway duty of the worm's stiction (1.0 of 9.12 N m: 11 %); below
  // 1 % effort the duty is 0 (no hum at rest: the worm holds the joint).
  const int16_t rate_q15 = (int16_t)std::max(1L, std::lround(32767 / (0.05 * rate)));
  const int16_t min_duty = (int16_t)std::lround(32767 * plant::kDcStaticFrictionNm / plant::kDcStallTorqueNm);
  d.config = control::PidConfig{d.fixed.gains, 32767, rate_q15, min_duty, 328};
  return d;
}

DcResult run_dc(const DcOptions& o) {
  using namespace control;
  check_dc(o);
  const int j = o.joint - 1;
  const double rate = o.rate_hz > 0 ? o.rate_hz : kDcDefaultRateHz;
  DcResult res;
  Pid pid;
  Relay relay;
  plant::Potentiometer pot(arm::q_min_rad(j), arm::q_max_rad(j), o.noise_mv, plant::kPotFilterTauS,
                           plant::NoiseStream(o.seed, (uint64_t)o.joint));
  const double target = o.start_rad + o.step_rad;
  // the setpoint in position units: the ADC truncates, so its mean reading sits half a count below
  const int32_t setpoint = (int32_t)std::lround((pot_counts(pot, target) - 0.5) * kPositionUnitsPerCount);
  if (o.controller == DcController::pid) {
    res.design = design_dc_pid(o);
    if (pid.configure(res.design.config) != PidStatus::ok) throw BadOption("PID configuration refused");
  } else {
    const double counts_per_rad = pot_counts(pot, 1.0) - pot_counts(pot, 0.0);
    const double units_per_deg = kPi / 180 * counts_per_rad * kPositionUnitsPerCount;
    const int32_t dz = (int32_t)std::lround(o.deadzone_deg * units_per_deg);
    const int32_t hyst = (int32_t)std::lround(o.hysteresis_deg * units_per_deg);
    if (relay.configure({dz, hyst, (int16_t)std::lround(o.relay_duty * 32767)}) != RelayStatus::ok) {
      throw BadOption("relay configuration refused (the hysteresis must not exceed the dead zone)");
    }
  }

  DcJointRl joint(j, o.inductance_h);
  joint.set_angle(o.start_rad);
  pot.reset(o.start_rad);
  plant::JointLoads loads = loads_at(j, o.start_rad, o.payload);
  double loads_age_s = 0;
  constexpr double kLoadsEveryS = 1e-3;

  const double period = 1.0 / rate;
  const int sub = std::max(1, (int)std::ceil(period / plant::kPlantStepS - 1e-9));
  const double h = period / sub;
  const long samples = std::lround(o.duration_s * rate);
  const int32_t park_units = o.park_counts * kPositionUnitsPerCount;
  const int park_samples = (int)std::ceil(0.05 * rate);
  int in_band = 0;
  bool parked = false;
  for (long n = 0; n <= samples; ++n) {
    const int adc = plant::adc_counts_simavr(pot.sample_mv());
    const int32_t measured = adc * kPositionUnitsPerCount;
    int16_t duty_q15 = 0;
    if (o.controller == DcController::relay) {
      duty_q15 = relay.update(setpoint, measured);
    } else {
      const int32_t e = std::abs(setpoint - measured);
      if (park_units > 0) {
        in_band = e <= park_units ? in_band + 1 : 0;
        if (parked && e > 2 * park_units) parked = false;
        if (!parked && in_band >= park_samples) parked = true;
      }
      if (n == 0 || parked) pid.start(setpoint, measured, 0);  // from rest, bumpless
      if (!parked) duty_q15 = pid.update(setpoint, measured);
    }
    const double duty = duty_q15 / 32767.0;
    joint.set_voltage(plant::bts7960_voltage(duty > 0 ? duty : 0, duty < 0 ? -duty : 0));
    res.rows.push_back(DcRow{n * period, target, joint.q(), joint.qd(), adc, duty, joint.current_a()});
    for (int i = 0; i < sub; ++i) {
      joint.step(h, loads.inertia_kgm2[j], loads.gravity_nm[j]);
      pot.step(joint.q(), h);
      loads_age_s += h;
      if (loads_age_s >= kLoadsEveryS) {
        loads = loads_at(j, joint.q(), o.payload);
        loads_age_s = 0;
      }
    }
  }
  return res;
}

StepMetrics step_metrics(const std::vector<DcRow>& rows, double start_rad, double target_rad, double band_rad,
                         double tail_s) {
  StepMetrics m;
  if (rows.empty()) return m;
  const double step = target_rad - start_rad;
  const double sign = step >= 0 ? 1.0 : -1.0;
  double t10 = -1, t90 = -1, err_sum = 0;
  int err_n = 0;
  const double t_end = rows.back().t_s;
  m.settling_s = 0;
  for (const DcRow& r : rows) {
    const double progress = (r.position_rad - start_rad) * sign;
    m.overshoot_rad = std::max(m.overshoot_rad, progress - std::fabs(step));
    if (t10 < 0 && progress >= 0.1 * std::fabs(step)) t10 = r.t_s;
    if (t90 < 0 && progress >= 0.9 * std::fabs(step)) t90 = r.t_s;
    if (std::fabs(target_rad - r.position_rad) > band_rad)
      m.settling_s = -1;
    else if (m.settling_s < 0)
      m.settling_s = r.t_s;
    if (r.t_s >= t_end - tail_s) {
      err_sum += target_rad - r.position_rad;
      ++err_n;
    }
  }
  m.overshoot_percent = step != 0 ? 100 * m.overshoot_rad / std::fabs(step) : 0;
  m.steady_error_rad = err_n ? err_sum / err_n : 0;
  m.rise_s = (t10 >= 0 && t90 >= 0) ? t90 - t10 : -1;
  return m;
}

// ------------------------------------------------------------------------------------ CSV

void write_csv(std::ostream& out, const Seed0Result& r) {
  out << "t,target,position,speed,lost\n";
  char buf[160];
  for (const Seed0Row& w : r.rows) {
    std::snprintf(buf, sizeof buf, "%.3f,%d,%d,%.1f,%lld\n", w.t_s, (int)w.target_counts, (int)w.position_counts,
                  w.speed_steps_s, (long long)w.lost_steps);
    out << buf;
  }
}

void write_csv(std::ostream& out, const Seed1Result& r) {
  out << "t,target,position,velocity,h\n";
  char buf[160];
  for (const Seed1Row& w : r.rows) {
    std::snprintf(buf, sizeof buf, "%.6f,%.6f,%.6f,%.5f,%d\n", w.t_s, w.target_rad, w.position_rad, w.velocity_rad_s,
                  w.h);
    out << buf;
  }
}

void write_csv(std::ostream& out, const DcResult& r) {
  out << "t,target,position,velocity,adc,duty,current\n";
  char buf[200];
  for (const DcRow& w : r.rows) {
    std::snprintf(buf, sizeof buf, "%.4f,%.6f,%.6f,%.5f,%d,%.4f,%.3f\n", w.t_s, w.target_rad, w.position_rad,
                  w.velocity_rad_s, w.adc_counts, w.duty, w.current_a);
    out << buf;
  }
}

}  // namespace jointsim
}  // namespace wmra
