#include "drv8825.h"

namespace wmra {
namespace plant {

void Drv8825::reset(bool en_high, bool dir_high, bool step_high, double t_s) {
  en_high_ = en_high;
  dir_high_ = dir_high;
  step_high_ = step_high;
  last_rise_s_ = last_fall_s_ = last_dir_s_ = t_s - 1.0;
}

int Drv8825::update(bool en_high, bool dir_high, bool step_high, double t_s) {
  en_high_ = en_high;
  if (dir_high != dir_high_) {
    dir_high_ = dir_high;
    last_dir_s_ = t_s;
  }
  if (step_high == step_high_) return 0;
  step_high_ = step_high;
  // small tolerance: the simulator's edge times carry a few cycles of jitter
  constexpr double kTolS = 0.5 / 16e6;
  if (!step_high) {
    if (t_s - last_rise_s_ < kDrvStepMinHighS - kTolS) ++violations_;
    last_fall_s_ = t_s;
    return 0;
  }
  if (t_s - last_fall_s_ < kDrvStepMinLowS - kTolS) ++violations_;
  if (t_s - last_dir_s_ < kDrvDirSetupS - kTolS) ++violations_;
  last_rise_s_ = t_s;
  if (en_high_) {
    ++ignored_;
    return 0;
  }
  ++taken_;
  return dir_high_ ? 1 : -1;
}

}  // namespace plant
}  // namespace wmra
