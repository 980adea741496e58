#include "drive.h"

#include <cmath>

namespace wmra {
namespace plant {

namespace {
double sign(double x) { return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0; }
}  // namespace

bool drive_step(DriveState& s, double inertia_kgm2, const DriveFriction& f, double motor_nm, double load_nm,
                bool self_locking, double stop_low_rad, double stop_high_rad, double dt,
                double overrun_inertia_kgm2) {
  const double w = s.speed_rad_s;
  // the way the drive moves, or at rest the way it is pushed
  const double way = w != 0 ? sign(w) : sign(self_locking ? motor_nm : motor_nm + load_nm);
  double load = load_nm;
  if (self_locking && load * way >= 0) load = 0;  // a self-locking gear takes an aiding load itself

  double w_new;
  if (w == 0) {
    const double net = motor_nm + load;
    // at rest, a self-locking gear never lets the load turn it against the motor
    if (std::fabs(net) <= f.static_nm || (self_locking && net * way < 0)) {
      w_new = 0;
    } else {
      w_new = (net - sign(net) * f.coulomb_nm) / inertia_kgm2 * dt;
    }
  } else {
    const double net = motor_nm + load - sign(w) * f.coulomb_nm - f.viscous_nm_per_rad_s * w;
    const double inertia = (self_locking && net * w < 0) ? inertia_kgm2 - overrun_inertia_kgm2 : inertia_kgm2;
    w_new = w + net / inertia * dt;
    if (w_new * w < 0) w_new = 0;  // friction stops it; it may break away again next step
  }
  s.speed_rad_s = w_new;
  s.angle_rad += w_new * dt;
  if (s.angle_rad <= stop_low_rad && w_new <= 0) {
    s.angle_rad = stop_low_rad;
    s.speed_rad_s = 0;
    return true;
  }
  if (s.angle_rad >= stop_high_rad && w_new >= 0) {
    s.angle_rad = stop_high_rad;
    s.speed_rad_s = 0;
    return true;
  }
  return false;
}

}  // namespace plant
}  // namespace wmra
