// Friction element with a backlash gap: the operator fitted to the measured friction damper
// (docs/friction-damper.md). Same sample-by-sample interface as the paper's switch and backlash, so it can be the
// actuator of any Scenario.
//
// State: the slider position z. The input v drags the slider only when the relative displacement e = v - z leaves
// the play [e_lo, e_hi] (a play operator: z = v - e_hi when sliding up, z = v - e_lo when sliding down). The force
// is a nonparametric curve of the relative displacement plus a parallel stiffness:
//     u = G(v - z) + k v.
// Sliding up, u = G(e_hi) + k v (the upper friction plateau); after a reversal e crosses the play and u follows
// G: finite unloading stiffness, a zero-force gap where the band is slack, finite reloading stiffness, and the
// lower plateau G(e_lo) once the slider moves again. With G a two-level step at e = 0 and a vanishing play this is
// the paper's switch (2.3) with constant borders; with G linear it is a Prandtl (elastic-perfectly-plastic) stop.
#pragma once

#include <memory>
#include <string>

#include "lashid/plant/border.hpp"
#include "lashid/plant/operators.hpp"

namespace lashid::sim {

class FrictionGapOperator final : public HysteresisOperator {
 public:
  // `curve` is G on its domain [e_lo, e_hi] = [curve.lo(), curve.hi()]; `stiffness` is k. Throws
  // std::invalid_argument unless e_lo < 0 < e_hi and k is finite. Initial state: z = 0 (v = 0 mid-play).
  FrictionGapOperator(Border curve, double stiffness);
  double step(double v) override;
  // Places the slider so that G(v_prev - z) + k v_prev = u_prev: among the relative displacements giving u_prev,
  // the one nearest to the middle of the play (the gap is a set of them); if u_prev is out of G's range, the end of
  // the play whose force is nearest.
  void reset(double v_prev, double u_prev) override;
  // Places the slider at relative displacement `offset` from v_prev (clamped to the play): z = v_prev - offset. For
  // a state that the force cannot tell (inside the zero-force gap every offset gives the same force). Throws
  // std::invalid_argument for a non-finite argument.
  void place(double v_prev, double offset);
  std::unique_ptr<HysteresisOperator> clone() const override;
  std::string name() const override;

  const Border& curve() const { return curve_; }
  double stiffness() const { return stiffness_; }
  double slider() const { return z_; }

 private:
  Border curve_;
  double stiffness_;
  double z_ = 0.0;
};

}  // namespace lashid::sim
