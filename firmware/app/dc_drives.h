// The DC joints J2, J3, J4 (drives 0, 1, 2): their pots read and checked every tick, their
// servos (feedforward, PID or relay) following the joints' references on the BTS7960 bridges,
// the holding effort against gravity and the speed governor that bounds each way's speed.
#pragma once

#include <stdint.h>

#include "app/settings.h"
#include "core/joint_map.h"
#include "kinematics/fixed_point.h"
#include "kinematics/forward_kinematics.h"
#include "protocol/messages.h"

namespace wmra {
namespace app {
namespace dc_drives {

void configure(const Settings& settings);
// a joint's pot map and its tracking thresholds from its calibration
void configure_pot(const Settings& settings, uint8_t d);

// Every tick: the pots' readings (ADC counts) into pot units, checked at the rails and for a
// jump; in a servo tick (servo_tick) also for a stall or a wrong sign, over the ticks since the
// last servo tick. Raises the faults it finds.
void read_and_check(const uint16_t* pot_counts, uint8_t ticks, bool servo_tick);

// the servos of a servo tick: each drive towards its joint's reference
void run_servos();
// the drives braked (PWM 0 both sides), each servo at rest and its reference where its joint is
void hold();
// the servos restart at rest where the joints are, their references there too
void start();
// after a re-arm: the servos' plausibility checks start afresh
void reset_checks();

// How much the DC joints' lag allows the hand's speed: 1 up to the slow-down lag, 0 at the stop
// lag (kTrackingSlowFrom_mrad, kTrackingStopAt_mrad).
fx::Unit tracking_factor();
// The holding effort (each joint's duty against gravity at the pose of `trig`), and the speed
// governor from its last duties: each way the servo's effort bounds and the drive's speed
// (g_arm.drives) that the load leaves.
void update_holding(const kin::JacobianTrig<kin::Fixed>& trig);
void update_governor();

// While the arm stands: where the joints came to rest, and whether one moved from there by more
// than kStandstillMove_mdeg.
void mark_rest();
bool moved_from_rest();

int16_t units(uint8_t d);  // the last reading, ADC counts x 16
fx::Angle angle(uint8_t d);

}  // namespace dc_drives
}  // namespace app
}  // namespace wmra
