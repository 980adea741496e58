// report.html, the page armsim writes next to trajectory.csv and summary.json:
// one self-contained file (inline CSS and JS, no network) with the arm animated in 3D and its
// end-effector trail, plots of joint angles, joint and hand velocities, mode, state and faults
// over time, and the run's measurements.
//
// The page is sim/armsim/report_page.html with the run's data embedded as JSON: plot samples
// at 100 Hz of simulated time (fewer on long runs), animation frames at 30 Hz holding the
// joint-frame origins of the modified DH chain below, so the drawing is the real arm.
// On load the page sets document.body.dataset.status to "rendered", or to "error: ..." when a
// script fails (how a headless browser tells; see scripts/check-report).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "armsim/run.h"
#include "armsim/scenario.h"

namespace wmra {
namespace armsim {

struct Frame {
  std::array<double, 3> p;  // origin, base frame, m
  std::array<double, 9> R;  // rotation base <- frame, row-major
};

// Frames 0..6 of Craig's modified DH chain at the joint angles q (joint 5's DH
// angle is q5 - pi/2); frame 6 is the pose forward kinematics gives.
std::array<Frame, 7> arm_frames(const std::array<double, 6>& q);

// dx/dt at every sample, as the slope between the samples `half_width` before and after
// (fewer at the ends): a central difference that also smooths the quantised stepper angles.
std::vector<double> smoothed_derivative(const std::vector<double>& t, const std::vector<double>& x, int half_width);

// The page as text, and the page written to path (throws std::runtime_error when it cannot be).
std::string report_html(const RunResult& result, const Scenario& scenario, const std::string& title);
void write_report_html(const std::string& path, const RunResult& result, const Scenario& scenario,
                       const std::string& title);

}  // namespace armsim
}  // namespace wmra
