#include "app/velocity_request.h"

#include "config/motion_config.h"
#include "core/joint_map.h"

namespace wmra {
namespace app {

namespace {

fx::Real clamp_real(fx::Real r, int32_t limit) { return fx::Real{r.raw > limit ? limit : r.raw < -limit ? -limit : r.raw}; }

}  // namespace

kin::TwistWrist<kin::Fixed> velocity_twist(const Requests& rq, const kin::JacobianTrig<kin::Fixed>& trig) {
  using core::kRealPerMilli;
  constexpr int32_t kHand = fx::real(config::kMaxHandSpeed_m_s).raw, kWrist = fx::real(config::kMaxWristSpeed_rad_s).raw;
  kin::Twist<kin::Fixed> t;
  t.v_m_s = {clamp_real(fx::Real{rq.v_mm_s[0] * kRealPerMilli}, kHand), clamp_real(fx::Real{rq.v_mm_s[1] * kRealPerMilli}, kHand),
             clamp_real(fx::Real{rq.v_mm_s[2] * kRealPerMilli}, kHand)};
  t.w_rad_s = {clamp_real(fx::Real{rq.w_mrad_s[0] * kRealPerMilli}, kWrist),
               clamp_real(fx::Real{rq.w_mrad_s[1] * kRealPerMilli}, kWrist),
               clamp_real(fx::Real{rq.w_mrad_s[2] * kRealPerMilli}, kWrist)};
  return kin::twist_wrist<kin::Fixed>(trig, t);
}

}  // namespace app
}  // namespace wmra
