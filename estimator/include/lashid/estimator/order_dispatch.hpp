// Calls a kernel compiled for the model order chosen at run time. The estimator's storage has compile-time
// capacity (N), its hot loops run over the actual order n: compiled once per n in 1..N, they stay unrolled. On the
// Cortex-M4F the rolled loops cost about 90 more instructions per sample at n = 2 (docs/on-target-cost.md).
#pragma once

#include <type_traits>
#include <utility>

namespace lashid::est {

namespace detail {
template <class F, int... I>
constexpr void dispatch_order(int n, F&& f, std::integer_sequence<int, I...> /*orders - 1*/) {
  (void)((n == I + 1 ? (f(std::integral_constant<int, I + 1>{}), true) : false) || ...);
}
}  // namespace detail

/// f(std::integral_constant<int, n>{}) for n in [1, N]; nothing for an n outside (callers check the range first).
template <int N, class F>
constexpr void with_order(int n, F&& f) {
  detail::dispatch_order(n, std::forward<F>(f), std::make_integer_sequence<int, N>{});
}

}  // namespace lashid::est
