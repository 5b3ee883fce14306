// A binary search of a sorted table that starts from where the previous one ended.
//
// An operator run over a recording looks up its input in a border table at every sample, and the input moves by a
// segment or less per sample most of the time: the answer is the previous one or a neighbour. The search looks
// there first and falls back to a binary search over the part of the table that is left. It returns exactly the
// index std::upper_bound would (the index that splits the table is unique), whatever the hint: only the time
// differs.
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

namespace lashid::sim {

namespace nearby_detail {

/// The first index i of `xs` whose element is not `before` (before must hold on a prefix of xs), from `hint`.
template <class Before>
std::size_t partition_from(const std::vector<double>& xs, std::size_t hint, Before before) {
  constexpr int kSteps = 2;  // neighbours tried on either side before the binary search
  const std::size_t n = xs.size();
  std::size_t i = std::min(hint, n);
  if (i < n && before(xs[i])) {  // the answer lies above i
    for (int k = 0; k < kSteps; ++k) {
      ++i;
      if (i == n || !before(xs[i])) return i;
    }
    const auto from = xs.begin() + static_cast<std::ptrdiff_t>(i);
    return static_cast<std::size_t>(std::partition_point(from, xs.end(), before) - xs.begin());
  }
  // Here i == n or xs[i] is not before: the answer is i or below.
  for (int k = 0; k < kSteps; ++k) {
    if (i == 0 || before(xs[i - 1])) return i;
    --i;
  }
  if (i == 0 || before(xs[i - 1])) return i;
  const auto to = xs.begin() + static_cast<std::ptrdiff_t>(i);
  return static_cast<std::size_t>(std::partition_point(xs.begin(), to, before) - xs.begin());
}

}  // namespace nearby_detail

/// std::upper_bound(xs, v) as an index (the first element > v), searched from `hint`, which it becomes.
inline std::size_t upper_bound_near(const std::vector<double>& xs, double v, std::size_t& hint) {
  hint = nearby_detail::partition_from(xs, hint, [v](double x) { return x <= v; });
  return hint;
}

}  // namespace lashid::sim
