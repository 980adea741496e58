// Cycle benchmark of the kinematics on the ATmega2560, run by scripts/bench in simavr.
// Every measured call goes through a noinline wrapper, so the region markers bracket
// exactly the call (its call overhead included) and nothing the compiler moved.
#include "kinematics/inverse_jacobian.h"
#include "kinematics/inverse_kinematics.h"
#include "kinematics_vectors.h"
#include "probe.h"

using namespace wmra;
using kin::Fixed;
using Float = kin::Floating<float>;

namespace {

constexpr int kPoses = 64;

enum Region : uint8_t {
  kEmpty = 1,  // calibration: start immediately followed by stop
  kTrigFixed,
  kFkFixed,
  kJinvFixed,
  kJinvCoreFixed,
  kTrigFloat,
  kFkFloat,
  kJinvFloat,
  kJinvCoreFloat,
  kMulUnitUnit,
  kMulUnitReal,
  kMulRealRecip,
  kReciprocal,
  kSinCos,
  kIkFixed,
};

kin::JointAngles<Fixed> q_fixed[kPoses];
kin::Twist<Fixed> twist_fixed[kPoses];
kin::JointAngles<Float> q_float[kPoses];
kin::Twist<Float> twist_float[kPoses];

volatile int32_t sink_fixed;
volatile int16_t unit_in = 12345;
volatile int32_t real_in = 987654321;

__attribute__((noinline)) fx::Unit op_mul_unit_unit(fx::Unit a, fx::Unit b) { return a * b; }
__attribute__((noinline)) fx::Real op_mul_unit_real(fx::Unit a, fx::Real b) { return a * b; }
__attribute__((noinline)) fx::Real op_mul_real_recip(fx::Real a, fx::Recip b) { return a * b; }
__attribute__((noinline)) fx::Recip op_reciprocal(fx::Unit a) { return fx::reciprocal(a); }
__attribute__((noinline)) fx::SinCos op_sincos(fx::Angle a) { return fx::sincos(a); }
volatile float sink_float;

__attribute__((noinline)) kin::ArmTrig<Fixed> trig_fixed(const kin::JointAngles<Fixed>& q) {
  return kin::arm_trig<Fixed>(q);
}
__attribute__((noinline)) kin::Pose<Fixed> fk_fixed(const kin::JointAngles<Fixed>& q) {
  return kin::forward_kinematics<Fixed>(q);
}
__attribute__((noinline)) kin::JacobianInverse<Fixed> jinv_fixed(const kin::JointAngles<Fixed>& q,
                                                                 const kin::Twist<Fixed>& t) {
  return kin::inverse_jacobian<Fixed>(q, t);
}
__attribute__((noinline)) kin::JacobianInverse<Fixed> jinv_core_fixed(const kin::ArmTrig<Fixed>& trig,
                                                                      const kin::Twist<Fixed>& t) {
  return kin::inverse_jacobian<Fixed>(trig, t);
}
__attribute__((noinline)) kin::IkSolutions<Fixed> ik_fixed(const kin::Pose<Fixed>& pose) {
  return kin::inverse_kinematics<Fixed>(pose);
}
__attribute__((noinline)) kin::ArmTrig<Float> trig_float(const kin::JointAngles<Float>& q) {
  return kin::arm_trig<Float>(q);
}
__attribute__((noinline)) kin::Pose<Float> fk_float(const kin::JointAngles<Float>& q) {
  return kin::forward_kinematics<Float>(q);
}
__attribute__((noinline)) kin::JacobianInverse<Float> jinv_float(const kin::JointAngles<Float>& q,
                                                                 const kin::Twist<Float>& t) {
  return kin::inverse_jacobian<Float>(q, t);
}
__attribute__((noinline)) kin::JacobianInverse<Float> jinv_core_float(const kin::ArmTrig<Float>& trig,
                                                                      const kin::Twist<Float>& t) {
  return kin::inverse_jacobian<Float>(trig, t);
}

void make_inputs() {
  vectors::Lcg rng{vectors::kSeed};
  for (int i = 0; i < kPoses; ++i) {
    q_fixed[i] = vectors::random_joint_angles(rng);
    twist_fixed[i] = vectors::random_twist(rng);
    for (int j = 0; j < arm::kJoints; ++j) q_float[i].q[j] = (float)fx::to_radians(q_fixed[i].q[j]);
    const fx::Real* v = &twist_fixed[i].v_m_s.x;
    float* vf = &twist_float[i].v_m_s.x;
    for (int j = 0; j < 3; ++j) vf[j] = (float)fx::to_double(v[j]);
    const fx::Real* w = &twist_fixed[i].w_rad_s.x;
    float* wf = &twist_float[i].w_rad_s.x;
    for (int j = 0; j < 3; ++j) wf[j] = (float)fx::to_double(w[j]);
  }
}

}  // namespace

int main() {
  probe::name_region(kEmpty, "empty");
  probe::name_region(kTrigFixed, "trig_fixed");
  probe::name_region(kFkFixed, "fk_fixed");
  probe::name_region(kJinvFixed, "jinv_fixed");
  probe::name_region(kJinvCoreFixed, "jinv_core_fixed");
  probe::name_region(kTrigFloat, "trig_float");
  probe::name_region(kFkFloat, "fk_float");
  probe::name_region(kJinvFloat, "jinv_float");
  probe::name_region(kJinvCoreFloat, "jinv_core_float");
  probe::name_region(kMulUnitUnit, "op_unit_x_unit");
  probe::name_region(kMulUnitReal, "op_unit_x_real");
  probe::name_region(kMulRealRecip, "op_real_x_recip");
  probe::name_region(kReciprocal, "op_reciprocal");
  probe::name_region(kSinCos, "op_sincos");
  probe::name_region(kIkFixed, "ik_fixed");
  make_inputs();

  for (int i = 0; i < kPoses; ++i) {
    probe::start(kEmpty);
    probe::stop(kEmpty);

    probe::start(kTrigFixed);
    const auto tf = trig_fixed(q_fixed[i]);
    probe::stop(kTrigFixed);
    probe::start(kFkFixed);
    const auto pf = fk_fixed(q_fixed[i]);
    probe::stop(kFkFixed);
    probe::start(kJinvFixed);
    const auto jf = jinv_fixed(q_fixed[i], twist_fixed[i]);
    probe::stop(kJinvFixed);
    probe::start(kJinvCoreFixed);
    const auto jcf = jinv_core_fixed(tf, twist_fixed[i]);
    probe::stop(kJinvCoreFixed);
    probe::start(kIkFixed);
    const auto ikf = ik_fixed(pf);
    probe::stop(kIkFixed);
    sink_fixed = pf.p_m.x.raw + jf.qd_rad_s[2].raw + jcf.qd_rad_s[3].raw + ikf.count;

    probe::start(kTrigFloat);
    const auto tl = trig_float(q_float[i]);
    probe::stop(kTrigFloat);
    probe::start(kFkFloat);
    const auto pl = fk_float(q_float[i]);
    probe::stop(kFkFloat);
    probe::start(kJinvFloat);
    const auto jl = jinv_float(q_float[i], twist_float[i]);
    probe::stop(kJinvFloat);
    probe::start(kJinvCoreFloat);
    const auto jcl = jinv_core_float(tl, twist_float[i]);
    probe::stop(kJinvCoreFloat);
    sink_float = pl.p_m.x + jl.qd_rad_s[2] + jcl.qd_rad_s[3];
  }
  for (int i = 0; i < kPoses; ++i) {
    const fx::Unit u{(int16_t)(unit_in + 97 * i)};
    const fx::Real r{real_in + 7919l * i};
    probe::start(kMulUnitUnit);
    const fx::Unit uu = op_mul_unit_unit(u, u);
    probe::stop(kMulUnitUnit);
    probe::start(kMulUnitReal);
    const fx::Real ur = op_mul_unit_real(u, r);
    probe::stop(kMulUnitReal);
    probe::start(kReciprocal);
    const fx::Recip k = op_reciprocal(u);
    probe::stop(kReciprocal);
    probe::start(kMulRealRecip);
    const fx::Real rk = op_mul_real_recip(fx::Real{r.raw >> 4}, k);
    probe::stop(kMulRealRecip);
    probe::start(kSinCos);
    const fx::SinCos sc = op_sincos(q_fixed[i].q[1]);
    probe::stop(kSinCos);
    sink_fixed = uu.raw + ur.raw + rk.raw + sc.s.raw;
  }
  probe::print("END\n");
  probe::finish();
}
