// The DRV8825's logic inputs: EN (active low), DIR, STEP. A rising STEP edge while enabled moves
// the indexer one microstep in the direction DIR gives (high = positive joint direction); while
// disabled the outputs are off and STEP is ignored. Edges that break the datasheet's timing
// (STEP high or low < 1.9 us, DIR changed < 650 ns before a rising STEP) are counted.
#pragma once

#include <cstdint>

#include "arm_plant_config.h"

namespace wmra {
namespace plant {

class Drv8825 {
 public:
  // the pin levels at time t_s; returns +1 or -1 when a microstep is taken, else 0
  int update(bool en_high, bool dir_high, bool step_high, double t_s);
  void reset(bool en_high, bool dir_high, bool step_high, double t_s);

  bool enabled() const { return !en_high_; }
  int64_t steps_taken() const { return taken_; }
  int64_t steps_ignored() const { return ignored_; }  // STEP edges while disabled
  int64_t timing_violations() const { return violations_; }
  double last_step_s() const { return last_rise_s_; }

 private:
  bool en_high_ = true, dir_high_ = false, step_high_ = false;
  double last_rise_s_ = -1, last_fall_s_ = -1, last_dir_s_ = -1;
  int64_t taken_ = 0, ignored_ = 0, violations_ = 0;
};

}  // namespace plant
}  // namespace wmra
