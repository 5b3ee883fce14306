// Where a model's fast error comes from: does the measured displacement drive it, echo it, or ignore it?
//
// On the friction damper (docs/friction-damper.md) the final operator's error on the fastest test files is mostly an
// oscillation of 10-20 Hz that no model of the displacement v predicts. Its origin is told by the cross-spectrum of v
// and the error e = u - u_sim at the oscillation's frequency: a displacement that drives the force gives a coherent
// e in phase with a stiffness-like gain; a displacement that yields to the force (the compliance of the actuator and
// the rig) carries the oscillation too, but in antiphase and with the rig's much larger stiffness; an oscillation
// with its own phase (chatter) is not coherent with v at all.
#pragma once

#include <span>
#include <string>

namespace lashid::sim {

/// The cross-spectrum of the displacement v and the error measured - simulated near one frequency, averaged over
/// Hann windows of window_s seconds with half overlap (Welch), each window's mean removed.
struct DisplacementEcho {
  double hz = 0;          ///< the frequency the gain and phase are given at
  double coherence = 0;   ///< magnitude-squared coherence over hz +- band_hz (1 Hz steps), weighted by the error's power
  double gain = 0;        ///< |S_ve / S_vv| at hz: error per unit of displacement (kip/in on the damper)
  double phase_deg = 0;   ///< arg(S_ve / S_vv) at hz, degrees in (-180, 180]: near +-180 is antiphase
  int windows = 0;        ///< windows averaged (0: the record is too short; one window would give coherence 1)
};

/// A record shorter than two windows gives windows = 0 and zeros (a coherence needs at least two). Throws
/// std::invalid_argument for unequal sizes, a rate, hz or window that is not positive and finite, or a band that is
/// negative or not finite.
DisplacementEcho displacement_echo(std::span<const double> v, std::span<const double> measured,
                                   std::span<const double> simulated, double sample_rate, double hz,
                                   double band_hz = 2, double window_s = 1);

/// How the echo reads, in words, for a slider whose engaged stiffness is `stiffness` (error units per unit of v):
/// "not coherent with the displacement" (coherence below 0.5), "driven by the displacement" (within 90 degrees of
/// in phase), "echoed by the displacement" (antiphase and a gain over 3 times the stiffness: the displacement yields
/// to the force), or, antiphase at a lower gain, "coherent with the displacement in antiphase" (not named further).
std::string displacement_echo_words(const DisplacementEcho& echo, double stiffness);

}  // namespace lashid::sim
