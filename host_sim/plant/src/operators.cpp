#include "lashid/plant/operators.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace lashid::sim {

namespace {

void require_number(double v, const char* who) {
  if (std::isnan(v)) throw std::invalid_argument(std::string(who) + "::step: input is NaN");
}

std::unique_ptr<HysteresisOperator> require_inner(std::unique_ptr<HysteresisOperator> inner, const char* who) {
  if (!inner) throw std::invalid_argument(std::string(who) + ": inner operator is null");
  return inner;
}

}  // namespace

// ---------------------------------------------------------------------------------------------- switch (2.3)

SwitchOperator::SwitchOperator(Border ascending, Border descending)
    : ascending_(std::move(ascending)),
      descending_(std::move(descending)),
      v_prev_(descending_.lo()),
      u_prev_(descending_(descending_.lo())) {}

double SwitchOperator::step(double v) {
  require_number(v, "SwitchOperator");
  if (v > v_prev_) {
    u_prev_ = ascending_(v, ascending_hint_);
  } else if (v < v_prev_) {
    u_prev_ = descending_(v, descending_hint_);
  }
  v_prev_ = v;
  return u_prev_;
}

void SwitchOperator::reset(double v_prev, double u_prev) {
  v_prev_ = v_prev;
  u_prev_ = u_prev;
}

std::unique_ptr<HysteresisOperator> SwitchOperator::clone() const { return std::make_unique<SwitchOperator>(*this); }

std::string SwitchOperator::name() const { return "switch"; }

// -------------------------------------------------------------------------------------------- backlash (2.4)

BacklashOperator::BacklashOperator(Border ascending, Border descending)
    : ascending_(std::move(ascending)), descending_(std::move(descending)), v_prev_(0.0), u_prev_(0.0) {
  reset(descending_.lo(), descending_(descending_.lo()));
}

// Shortcut proof. Suppose u_prev == C_d(v_prev) and v < v_prev. Because C_d(v_prev) lies between C_d(v_prev-)
// and C_d(v_prev+) (tables are right-continuous; callables are required to be one-sided continuous at jumps),
// v_prev belongs to C_d^{-1}(u_prev) ∩ [lo, v_prev], so the max s of that set is v_prev itself and v < s:
// the first case of (2.4) applies and u = C_d(v) without any search. Symmetrically u_prev == C_a(v_prev) and
// v > v_prev give min C_a^{-1}(u_prev) ∩ [v_prev, hi] = v_prev < v, hence u = C_a(v).
// Otherwise the search is needed, and only on [v, v_prev] (resp. [v_prev, v]): "max(S ∩ [lo, v_prev]) >= v" is
// equivalent to "S ∩ [v, v_prev] is non-empty" for v >= lo, which keeps each search local to the move. For
// v < lo the borders are extended by the constant C(lo); the extra piece [v, lo) can only join S when
// u_prev == C(lo), in which case lo is in S already, so the test still equals the literal (2.4) condition.
double BacklashOperator::step(double v) {
  require_number(v, "BacklashOperator");
  if (v < v_prev_) {
    if (on_descending_ || descending_.reaches(u_prev_, v, v_prev_)) {
      u_prev_ = descending_(v, descending_hint_);
      on_descending_ = true;
      on_ascending_ = false;  // Unknown: the borders may cross here; a later search decides.
    } else {
      on_descending_ = on_ascending_ = false;  // Horizontal move: u stays, v changed.
    }
  } else if (v > v_prev_) {
    if (on_ascending_ || ascending_.reaches(u_prev_, v_prev_, v, Border::Scan::from_left)) {
      u_prev_ = ascending_(v, ascending_hint_);
      on_ascending_ = true;
      on_descending_ = false;
    } else {
      on_descending_ = on_ascending_ = false;
    }
  }
  // v == v_prev: u holds and so does the on-border knowledge.
  v_prev_ = v;
  return u_prev_;
}

void BacklashOperator::reset(double v_prev, double u_prev) {
  v_prev_ = v_prev;
  u_prev_ = u_prev;
  on_ascending_ = ascending_(v_prev) == u_prev;
  on_descending_ = descending_(v_prev) == u_prev;
}

std::unique_ptr<HysteresisOperator> BacklashOperator::clone() const {
  return std::make_unique<BacklashOperator>(*this);
}

std::string BacklashOperator::name() const { return "backlash"; }

// ----------------------------------------------------------------------------------------------- input lag

InputLagOperator::InputLagOperator(std::unique_ptr<HysteresisOperator> inner, double lambda)
    : inner_(require_inner(std::move(inner), "InputLagOperator")), lambda_(lambda) {
  if (!(lambda >= 0.0 && lambda < 1.0)) {
    throw std::invalid_argument("InputLagOperator: lambda must be in [0, 1), got " + std::to_string(lambda));
  }
}

double InputLagOperator::step(double v) {
  require_number(v, "InputLagOperator");
  w_prev_ = lambda_ * w_prev_ + (1.0 - lambda_) * v;
  return inner_->step(w_prev_);
}

void InputLagOperator::reset(double v_prev, double u_prev) {
  w_prev_ = v_prev;  // At rest: a constant input v_prev has passed through G (unit DC gain) for ever.
  inner_->reset(v_prev, u_prev);
}

std::unique_ptr<HysteresisOperator> InputLagOperator::clone() const {
  auto copy = std::make_unique<InputLagOperator>(inner_->clone(), lambda_);
  copy->w_prev_ = w_prev_;
  return copy;
}

std::string InputLagOperator::name() const { return "input_lag(" + inner_->name() + ")"; }

// ----------------------------------------------------------------------------------------------- dead time

DeadTimeOperator::DeadTimeOperator(std::unique_ptr<HysteresisOperator> inner, int delay)
    : inner_(require_inner(std::move(inner), "DeadTimeOperator")) {
  if (delay < 0) throw std::invalid_argument("DeadTimeOperator: delay must be >= 0, got " + std::to_string(delay));
  queue_.assign(static_cast<std::size_t>(delay), 0.0);
}

double DeadTimeOperator::step(double v) {
  require_number(v, "DeadTimeOperator");
  if (queue_.empty()) return inner_->step(v);
  const double delayed = queue_[head_];
  queue_[head_] = v;
  head_ = head_ + 1 == queue_.size() ? 0 : head_ + 1;
  return inner_->step(delayed);
}

void DeadTimeOperator::reset(double v_prev, double u_prev) {
  std::fill(queue_.begin(), queue_.end(), v_prev);
  head_ = 0;
  inner_->reset(v_prev, u_prev);
}

std::unique_ptr<HysteresisOperator> DeadTimeOperator::clone() const {
  auto copy = std::make_unique<DeadTimeOperator>(inner_->clone(), delay());
  copy->queue_ = queue_;
  copy->head_ = head_;
  return copy;
}

std::string DeadTimeOperator::name() const { return "dead_time(" + inner_->name() + ")"; }

}  // namespace lashid::sim
