// Discrete-time hysteresis operators u = F[v] of the paper (Section 2.1) and the input-side perturbations used
// in its robustness study (Section 3.5.3). One sample at a time: step(v(t)) returns u(t).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "lashid/plant/border.hpp"

namespace lashid::sim {

class HysteresisOperator {
 public:
  virtual ~HysteresisOperator() = default;
  // Applies v(t) and returns u(t). Throws std::invalid_argument for a NaN input.
  virtual double step(double v) = 0;
  // Sets the state (v(t-1), u(t-1)) seen by the next step.
  virtual void reset(double v_prev, double u_prev) = 0;
  // Deep copy including the current state.
  virtual std::unique_ptr<HysteresisOperator> clone() const = 0;
  virtual std::string name() const = 0;

 protected:
  HysteresisOperator() = default;
  HysteresisOperator(const HysteresisOperator&) = default;
  HysteresisOperator& operator=(const HysteresisOperator&) = default;
};

// Switch (2.3): the working point jumps to the ascending border when v rises, to the descending one when it
// falls, and holds when v repeats. Initial state: (lo, C_d(lo)) of the descending border.
class SwitchOperator final : public HysteresisOperator {
 public:
  SwitchOperator(Border ascending, Border descending);
  double step(double v) override;
  void reset(double v_prev, double u_prev) override;
  std::unique_ptr<HysteresisOperator> clone() const override;
  std::string name() const override;

  const Border& ascending() const { return ascending_; }
  const Border& descending() const { return descending_; }

 private:
  Border ascending_;
  Border descending_;
  double v_prev_;
  double u_prev_;
  Border::Hint ascending_hint_, descending_hint_;  // where the last lookups ended (Border::Hint)
};

// Backlash (2.4), read literally with the borders' domain as working interval:
//   v < v_prev and C_d^{-1}(u_prev) ∩ [lo, v_prev] has a max s >= v  ->  u = C_d(v)
//   v > v_prev and C_a^{-1}(u_prev) ∩ [v_prev, hi] has a min s <= v  ->  u = C_a(v)
//   otherwise (including v == v_prev)                                ->  u = u_prev
// Borders may cross, jump and be non-monotone. Initial state: (lo, C_d(lo)) of the descending border.
class BacklashOperator final : public HysteresisOperator {
 public:
  BacklashOperator(Border ascending, Border descending);
  double step(double v) override;
  void reset(double v_prev, double u_prev) override;
  std::unique_ptr<HysteresisOperator> clone() const override;
  std::string name() const override;

  const Border& ascending() const { return ascending_; }
  const Border& descending() const { return descending_; }

 private:
  Border ascending_;
  Border descending_;
  double v_prev_;
  double u_prev_;
  // u_prev == C_a(v_prev) / u_prev == C_d(v_prev) is known to hold: the next step in that border's direction
  // follows it without a search (see step()). False means "unknown", never "false for sure".
  bool on_ascending_ = false;
  bool on_descending_ = false;
  // Where the last lookups on each border ended (Border::Hint): the input moves a segment or less per sample.
  Border::Hint ascending_hint_, descending_hint_;
};

// First-order input dynamics before an operator (Section 3.5.3, G(q^-1) = (1-lambda)/(1-lambda q^-1)):
// w(t) = lambda w(t-1) + (1-lambda) v(t), u = inner(w). reset() puts the filter at rest on v_prev and resets
// the inner operator to (v_prev, u_prev); before the first reset() the filter state is w = 0.
class InputLagOperator final : public HysteresisOperator {
 public:
  // Throws std::invalid_argument for a null inner or lambda outside [0, 1).
  InputLagOperator(std::unique_ptr<HysteresisOperator> inner, double lambda);
  double step(double v) override;
  void reset(double v_prev, double u_prev) override;
  std::unique_ptr<HysteresisOperator> clone() const override;
  std::string name() const override;

  double lambda() const { return lambda_; }

 private:
  std::unique_ptr<HysteresisOperator> inner_;
  double lambda_;
  double w_prev_ = 0.0;
};

// Pure extra delay of d samples before an operator: u(t) = inner(v(t-d)). reset() fills the queue with v_prev
// and resets the inner operator to (v_prev, u_prev); before the first reset() the queue holds zeros.
class DeadTimeOperator final : public HysteresisOperator {
 public:
  // Throws std::invalid_argument for a null inner or a negative delay.
  DeadTimeOperator(std::unique_ptr<HysteresisOperator> inner, int delay);
  double step(double v) override;
  void reset(double v_prev, double u_prev) override;
  std::unique_ptr<HysteresisOperator> clone() const override;
  std::string name() const override;

  int delay() const { return static_cast<int>(queue_.size()); }

 private:
  std::unique_ptr<HysteresisOperator> inner_;
  std::vector<double> queue_;  // Ring buffer of the last d inputs; queue_[head_] is v(t-d).
  std::size_t head_ = 0;
};

}  // namespace lashid::sim
