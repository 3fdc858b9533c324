#pragma once

#include "core/perception/tilt_sweep.h"

namespace mobot::sim {

// The tilt unit's true pitch during one up-sweep (R1): the speed loop aims at span / period but
// holds it only within +/- ripple_fraction, modelled as a sinusoidal speed error. The pitch a scan
// is assigned (perception::assigned_pitch_rad) assumes the nominal speed, so it is off by the
// integral of that error: a few hundredths of a degree, as on the real unit.
class TiltMotion {
 public:
  TiltMotion(perception::TiltRange range, double period_s, double ripple_fraction,
             double ripple_period_s, double ripple_phase_rad);

  // Pitch after elapsed_s since the limit switch; held at the top once the sweep is over.
  double pitch_rad(double elapsed_s) const;

 private:
  perception::TiltRange range_;
  double period_s_;
  double ripple_fraction_;
  double ripple_period_s_;
  double ripple_phase_rad_;
};

}  // namespace mobot::sim
