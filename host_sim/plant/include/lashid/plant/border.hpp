// Lateral border C(v) of a switch/backlash operator (paper, Section 2.1).
//
// A border is a real function on a closed domain [lo, hi]; outside the domain it is extended by the constant
// end values (C(v) = C(lo) for v < lo, C(v) = C(hi) for v > hi). Borders may be discontinuous, non-monotone and
// non-invertible (Remark 1(c)), so the inverse is the paper's set-valued one:
//     C^{-1}(u) = { v : min(C(v-), C(v+)) <= u <= max(C(v-), C(v+)) },
// i.e. the abscissas where the graph, completed by vertical segments at jumps, meets the level u.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace lashid::sim {

class Border {
 public:
  using Function = std::function<double(double)>;

  // Callable border on [lo, hi]. Crossings of a level are bracketed on `grid` uniform cells over [lo, hi]
  // (node values are cached at construction), then refined by bisection to ~1e-13 relative to the domain scale;
  // a sign change across a jump discontinuity converges to the jump abscissa. Limitations of sampling: a level
  // touched without a sign change (tangency) or crossed an even number of times inside one cell is missed.
  // At a jump, f(x0) must lie between the one-sided limits (true for left- or right-continuous f).
  // Throws std::invalid_argument for an empty f, lo >= hi, non-finite bounds, grid < 1 or non-finite node values.
  static Border from_function(Function f, double lo, double hi, int grid = 4096);

  // Piecewise-linear table (v_k, u_k), v non-decreasing; a repeated abscissa encodes a jump (vertical segment).
  // At a jump abscissa the value is the LAST point's (right-continuous). Crossings are exact (linear algebra).
  // Throws std::invalid_argument naming the offending index for: fewer than 2 points, decreasing v, non-finite
  // values, more than 2 points at one abscissa, or a zero-width domain.
  static Border from_table(std::vector<std::pair<double, double>> points);

  // Value; v outside [lo, hi] is clamped to the domain.
  double operator()(double v) const;
  double lo() const;
  double hi() const;

  // max / min of C^{-1}(level) ∩ [a, b]; nullopt if that set is empty (or a > b).
  std::optional<double> last_reach(double level, double a, double b) const;
  std::optional<double> first_reach(double level, double a, double b) const;
  // Whether C^{-1}(level) ∩ [a, b] is non-empty. Same answer as last_reach(...).has_value(), but without the
  // crossing itself: this is the only question the backlash law asks. A table answers from the range of its values
  // over [a, b]; a callable border stops at the first bracketing cell, and there `scan` affects speed only:
  // starting from the end where the motion starts stops soonest in the usual case.
  enum class Scan { from_left, from_right };
  bool reaches(double level, double a, double b, Scan scan = Scan::from_right) const;

  // A remembered position in a table border, for a caller that looks up nearby abscissas one after another (an
  // operator run over a slowly moving input): the value's search starts from it (lashid/plant/nearby_search.hpp)
  // and moves it. The value is exactly operator()(v); only the time differs. A callable border ignores it.
  // (reaches() takes none: measured with one, its two searches over [a, b] cost more instructions than it saved.)
  struct Hint {
    std::size_t index = 0;
  };
  double operator()(double v, Hint& hint) const;

  bool is_table() const;

 private:
  struct Data;
  explicit Border(std::shared_ptr<const Data> data);
  // Immutable and shared: operators clone their borders freely (Monte Carlo copies), so copying is a refcount.
  std::shared_ptr<const Data> data_;
};

}  // namespace lashid::sim
