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

/// std::upper_bound(xs, v) as an index (the first element > v), searched from `hint`, which it becomes.
inline std::size_t upper_bound_near(const std::vector<double>& xs, double v, std::size_t& hint) {
  constexpr int kSteps = 2;  // neighbours tried on either side before the binary search
  const std::size_t n = xs.size();
  std::size_t i = std::min(hint, n);
  const auto at = [&xs](std::size_t k) { return xs.begin() + static_cast<std::ptrdiff_t>(k); };
  const auto answer = [&](std::size_t k) { return hint = k; };
  if (i < n && xs[i] <= v) {  // the answer lies above i
    for (int k = 0; k < kSteps; ++k) {
      ++i;
      if (i == n || xs[i] > v) return answer(i);
    }
    return answer(static_cast<std::size_t>(std::upper_bound(at(i), xs.end(), v) - xs.begin()));
  }
  // Here i == n or xs[i] > v: the answer is i or below.
  for (int k = 0; k <= kSteps; ++k, --i) {
    if (i == 0 || xs[i - 1] <= v) return answer(i);
  }
  return answer(static_cast<std::size_t>(std::upper_bound(xs.begin(), at(i), v) - xs.begin()));
}

}  // namespace lashid::sim
