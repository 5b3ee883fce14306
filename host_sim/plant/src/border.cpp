#include "lashid/plant/border.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "lashid/plant/nearby_search.hpp"

namespace lashid::sim {

namespace {

bool between(double level, double y0, double y1) {
  return std::min(y0, y1) <= level && level <= std::max(y0, y1);
}

// For the sampled (callable) border: g = C - level. A point is "inside" relative to a reference value g_out
// (non-zero) when it is on the level or on the other side of it; a bracket [outside, inside] then contains a
// point of C^{-1}(level) by the intermediate value property (or a jump whose vertical segment meets the level).
bool inside_relative_to(double g, double g_out) { return g == 0.0 || ((g < 0.0) != (g_out < 0.0)); }

}  // namespace

struct Border::Data {
  bool table = false;
  double lo = 0.0;
  double hi = 0.0;

  // Table border: points sorted by abscissa, at most two per abscissa.
  std::vector<double> xs;
  std::vector<double> ys;
  // min / max of ys over the points of segment block j (segments [j*kSegmentBlock, (j+1)*kSegmentBlock), i.e. points
  // j*kSegmentBlock .. (j+1)*kSegmentBlock). A segment lying wholly inside [a, b] takes exactly its stored end values
  // (segment_value), so a whole block inside [a, b] whose range excludes the level holds no point of the set: the
  // scans skip it, with the same answer as a segment-by-segment scan. The diagnosis's fine borders have 10 segments
  // per interval between the levels, and a backlash asks at every sample across a move that may span most of them.
  static constexpr std::size_t kSegmentBlock = 8;
  std::vector<double> segment_block_min;
  std::vector<double> segment_block_max;

  // Whether the full segment block starting at point `first` (a multiple of kSegmentBlock) lies inside [a, b] and
  // its points' range excludes `level`: then no segment of it meets the level, and a scan may skip it whole.
  bool block_skippable(std::size_t first, double level, double a, double b) const {
    const std::size_t j = first / kSegmentBlock;
    return xs[first] >= a && xs[first + kSegmentBlock] <= b &&
           !(segment_block_min[j] <= level && level <= segment_block_max[j]);
  }

  // Callable border: function, cached grid nodes and the bisection stopping width.
  Function f;
  std::vector<double> node_x;
  std::vector<double> node_y;
  static constexpr std::size_t kBlock = 64;
  std::vector<double> block_min;  // min / max of node_y over nodes [j*kBlock, (j+1)*kBlock)
  std::vector<double> block_max;
  double tolerance = 0.0;

  // Linear interpolation on table segment k (points k, k+1). Endpoints return the stored values exactly so that
  // a level computed as C(v) at a node is recognised by the searches without rounding.
  double segment_value(std::size_t k, double v) const {
    if (v == xs[k]) return ys[k];
    if (v == xs[k + 1]) return ys[k + 1];
    return ys[k] + (ys[k + 1] - ys[k]) * ((v - xs[k]) / (xs[k + 1] - xs[k]));
  }

  double value(double v) const {
    std::size_t hint = xs.size() / 2;
    return value(v, hint);
  }

  // The same from a hint (nearby_search.hpp).
  double value(double v, std::size_t& hint) const {
    const double clamped = std::clamp(v, lo, hi);
    if (!table) return f(clamped);
    // Last point with abscissa <= v: at a jump this picks the second (right) point.
    const std::size_t j = upper_bound_near(xs, clamped, hint);
    if (j == xs.size()) return ys.back();
    return segment_value(j - 1, clamped);
  }

  // Where C^{-1}(level) meets table segment k restricted to [a, b]: the max (prefer_right) or min abscissa.
  std::optional<double> segment_hit(std::size_t k, double level, double a, double b, bool prefer_right) const {
    const double xl = xs[k];
    const double xr = xs[k + 1];
    if (xl == xr) {  // Vertical segment of a jump: the abscissa belongs to the set if the level is spanned.
      if (xl >= a && xl <= b && between(level, ys[k], ys[k + 1])) return xl;
      return std::nullopt;
    }
    const double l = std::max(xl, a);
    const double r = std::min(xr, b);
    if (l > r) return std::nullopt;
    const double cl = segment_value(k, l);
    const double cr = segment_value(k, r);
    if (prefer_right && cr == level) return r;
    if (!prefer_right && cl == level) return l;
    if (!between(level, cl, cr)) return std::nullopt;
    if (cl == cr) return prefer_right ? r : l;  // Flat piece lying on the level.
    const double v = xl + (level - ys[k]) * ((xr - xl) / (ys[k + 1] - ys[k]));
    return std::clamp(v, l, r);
  }

  std::optional<double> table_search(double level, double a, double b, bool from_right) const {
    const std::size_t segments = xs.size() - 1;
    if (from_right) {
      // Segments are scanned right to left, starting from the last one that begins at or before b.
      auto k = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), b) - xs.begin());
      k = std::min(k == 0 ? 0 : k - 1, segments - 1);
      for (std::size_t i = k + 1; i-- > 0;) {
        if (xs[i + 1] < a) break;
        // At the top segment of a full block: skipped whole where it cannot meet the level.
        if ((i + 1) % kSegmentBlock == 0 && block_skippable(i + 1 - kSegmentBlock, level, a, b)) {
          i = i + 1 - kSegmentBlock;  // the loop goes on at the block's first segment - 1
          continue;
        }
        if (auto hit = segment_hit(i, level, a, b, true)) return hit;
      }
    } else {
      // Left to right, starting from the first segment that ends at or after a.
      const auto k = static_cast<std::size_t>(std::lower_bound(xs.begin(), xs.end(), a) - xs.begin());
      for (std::size_t i = k == 0 ? 0 : k - 1; i < segments; ++i) {
        if (xs[i] > b) break;
        // At the first segment of a full block: skipped whole where it cannot meet the level.
        if (i % kSegmentBlock == 0 && i + kSegmentBlock <= segments && block_skippable(i, level, a, b)) {
          i += kSegmentBlock - 1;  // the loop goes on at the next block's first segment
          continue;
        }
        if (auto hit = segment_hit(i, level, a, b, false)) return hit;
      }
    }
    return std::nullopt;
  }

  // Whether C([a, b]) meets `level` on a table, a <= b inside [lo, hi]: the answer of table_search(level, a, b, .)
  // in either direction, without its scan (a backlash asks this at every sample of a horizontal move, and the scans
  // were a tenth of a diagnosis). The segments over [a, b] form a chain whose neighbours share their end values
  // (both points of a jump join through its vertical segment), so the union of their ranges is [min, max] of the
  // chain's values: C(a) and C(b) on their segments, and every point with a <= x <= b. The scan's tests on those
  // values are comparisons only, so the answers agree exactly (tests/test_border.cpp checks it against the scan).
  bool table_meets(double level, double a, double b) const {
    const auto first = static_cast<std::size_t>(std::lower_bound(xs.begin(), xs.end(), a) - xs.begin());
    const auto end = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), b) - xs.begin());
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    const auto take = [&](double u) {
      low = std::min(low, u);
      high = std::max(high, u);
    };
    if (first > 0 && xs[first] > a) take(segment_value(first - 1, a));  // a inside segment first - 1
    if (end < xs.size() && xs[end - 1] < b) take(segment_value(end - 1, b));  // b inside segment end - 1
    for (std::size_t i = first; i < end;) {
      // A whole block of points i .. i + kSegmentBlock inside the range: its stored min and max.
      if (i % kSegmentBlock == 0 && i + kSegmentBlock < end) {
        take(segment_block_min[i / kSegmentBlock]);
        take(segment_block_max[i / kSegmentBlock]);
        i += kSegmentBlock;
        continue;
      }
      take(ys[i]);
      ++i;
    }
    return low <= level && level <= high;
  }

  // Bisection on a bracket [p, q] of the callable border. `outside_at_q` chooses which end is outside
  // (last_reach: q; first_reach: p). Returns the midpoint of the final bracket, a point of the set up to the
  // tolerance; across a jump both ends converge to the jump abscissa. The midpoint (rather than either end)
  // makes last_reach == first_reach exactly when the level is crossed once.
  double refine(double level, double p, double q, bool outside_at_q) const {
    const double g_out = (outside_at_q ? f(q) : f(p)) - level;
    while (q - p > tolerance) {
      const double m = p + 0.5 * (q - p);
      if (m <= p || m >= q) break;
      const double gm = f(m) - level;
      const bool m_outside = !inside_relative_to(gm, g_out);
      if (m_outside == outside_at_q) {
        q = m;
      } else {
        p = m;
      }
    }
    return p + 0.5 * (q - p);
  }

  // Index of the first (scan_down: last) node in [first, last) whose value is NOT strictly on the starting side
  // of the level -- the first node where a crossing shows; `last` if there is none. Blocks of nodes whose cached
  // min/max lie strictly on the starting side are skipped whole, which gives the same answer as a node-by-node
  // scan in a fraction of the time (a long horizontal move of the backlash crosses most of the grid).
  std::size_t crossing_node(double level, bool above, std::size_t first, std::size_t last, bool scan_down) const {
    auto block_on_side = [&](std::size_t block) { return above ? block_min[block] > level : block_max[block] < level; };
    auto node_crosses = [&](std::size_t k) { return above ? !(node_y[k] > level) : !(node_y[k] < level); };
    if (!scan_down) {
      for (std::size_t k = first; k < last;) {
        if (k % kBlock == 0 && k + kBlock <= last && block_on_side(k / kBlock)) {
          k += kBlock;
          continue;
        }
        if (node_crosses(k)) return k;
        ++k;
      }
      return last;
    }
    for (std::size_t end = last; end > first;) {  // visits nodes end-1, end-2, ..., first
      if (end % kBlock == 0 && end >= first + kBlock && block_on_side(end / kBlock - 1)) {
        end -= kBlock;
        continue;
      }
      if (node_crosses(end - 1)) return end - 1;
      --end;
    }
    return last;
  }

  std::optional<double> function_search(double level, double a, double b, bool from_right, bool refine_hit) const {
    // The starting end fixes the reference side; the first point found on the level or across it closes a
    // bracket [inside, outside] with the previously visited point (or the starting end).
    const double start = from_right ? b : a;
    const double g_start = f(start) - level;
    if (g_start == 0.0) return start;
    const bool above = g_start > 0.0;
    // Grid nodes strictly inside (a, b): indices [first, last).
    const auto first = static_cast<std::size_t>(std::upper_bound(node_x.begin(), node_x.end(), a) - node_x.begin());
    const auto last = std::max(
        first, static_cast<std::size_t>(std::lower_bound(node_x.begin(), node_x.end(), b) - node_x.begin()));
    const std::size_t k = crossing_node(level, above, first, last, from_right);
    double inside = 0.0;
    double outside = 0.0;
    if (k != last) {
      inside = node_x[k];
      if (from_right) {
        outside = k + 1 < last ? node_x[k + 1] : b;
      } else {
        outside = k > first ? node_x[k - 1] : a;
      }
    } else {
      // No node crosses: only the far end of [a, b] is left to look at.
      if (!(a < b)) return std::nullopt;
      const double far_end = from_right ? a : b;
      if (!inside_relative_to(f(far_end) - level, g_start)) return std::nullopt;
      inside = far_end;
      if (from_right) {
        outside = first < last ? node_x[first] : b;
      } else {
        outside = first < last ? node_x[last - 1] : a;
      }
    }
    if (!refine_hit) return inside;
    return from_right ? refine(level, inside, outside, true) : refine(level, outside, inside, false);
  }

  // Search inside the domain: [a, b] must already be clamped to [lo, hi] with a <= b.
  std::optional<double> search(double level, double a, double b, bool from_right, bool refine_hit) const {
    if (table) return table_search(level, a, b, from_right);
    return function_search(level, a, b, from_right, refine_hit);
  }

  // Whether the border's constant extension beyond hi (below lo) lies inside [a, b] at the level.
  bool right_extension(double level, double b) const { return b > hi && level == value(hi); }
  bool left_extension(double level, double a) const { return a < lo && level == value(lo); }

  // Whether reach(level, a, b, from_right, false) has a value; on a table by table_meets, without the scan.
  bool meets(double level, double a, double b, bool from_right) const {
    if (!table) return reach(level, a, b, from_right, false).has_value();
    if (!(a <= b)) return false;
    // reach answers from an extension at the level in either direction.
    if (right_extension(level, b) || left_extension(level, a)) return true;
    const double ia = std::max(a, lo);
    const double ib = std::min(b, hi);
    return ia <= ib && table_meets(level, ia, ib);
  }

  // C^{-1}(level) ∩ [a, b] including the constant extensions outside [lo, hi]: the max or the min element
  // (any element when !refine_hit).
  std::optional<double> reach(double level, double a, double b, bool from_right, bool refine_hit) const {
    if (!(a <= b)) return std::nullopt;
    const bool at_right = right_extension(level, b);
    const bool at_left = left_extension(level, a);
    if (from_right && at_right) return b;
    if (!from_right && at_left) return a;
    const double ia = std::max(a, lo);
    const double ib = std::min(b, hi);
    if (ia <= ib) {
      if (auto hit = search(level, ia, ib, from_right, refine_hit)) return hit;
    }
    if (from_right && at_left) return std::min(b, lo);
    if (!from_right && at_right) return std::max(a, hi);
    return std::nullopt;
  }
};

Border::Border(std::shared_ptr<const Data> data) : data_(std::move(data)) {}

Border Border::from_function(Function f, double lo, double hi, int grid) {
  if (!f) throw std::invalid_argument("Border::from_function: empty function");
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) {
    throw std::invalid_argument("Border::from_function: domain must be finite with lo < hi, got [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  if (grid < 1) {
    throw std::invalid_argument("Border::from_function: grid must be >= 1, got " + std::to_string(grid));
  }
  auto data = std::make_shared<Data>();
  data->table = false;
  data->lo = lo;
  data->hi = hi;
  data->f = std::move(f);
  const auto nodes = static_cast<std::size_t>(grid) + 1;
  data->node_x.resize(nodes);
  data->node_y.resize(nodes);
  for (std::size_t i = 0; i < nodes; ++i) {
    const double x = i + 1 == nodes ? hi : lo + (hi - lo) * (static_cast<double>(i) / static_cast<double>(grid));
    const double y = data->f(x);
    if (!std::isfinite(y)) {
      throw std::invalid_argument("Border::from_function: non-finite value at grid node " + std::to_string(i) +
                                  " (v = " + std::to_string(x) + ")");
    }
    data->node_x[i] = x;
    data->node_y[i] = y;
  }
  const std::size_t blocks = (nodes + Data::kBlock - 1) / Data::kBlock;
  data->block_min.assign(blocks, data->node_y.front());
  data->block_max.assign(blocks, data->node_y.front());
  for (std::size_t i = 0; i < nodes; ++i) {
    const std::size_t j = i / Data::kBlock;
    data->block_min[j] = i % Data::kBlock == 0 ? data->node_y[i] : std::min(data->block_min[j], data->node_y[i]);
    data->block_max[j] = i % Data::kBlock == 0 ? data->node_y[i] : std::max(data->block_max[j], data->node_y[i]);
  }
  data->tolerance = 1e-13 * std::max({std::abs(lo), std::abs(hi), hi - lo});
  return Border(std::move(data));
}

Border Border::from_table(std::vector<std::pair<double, double>> points) {
  if (points.size() < 2) {
    throw std::invalid_argument("Border::from_table: need at least 2 points, got " + std::to_string(points.size()));
  }
  auto data = std::make_shared<Data>();
  data->table = true;
  data->xs.reserve(points.size());
  data->ys.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [v, u] = points[i];
    const std::string where = "Border::from_table: point " + std::to_string(i);
    if (!std::isfinite(v) || !std::isfinite(u)) throw std::invalid_argument(where + " is not finite");
    if (i > 0 && v < points[i - 1].first) {
      throw std::invalid_argument(where + " has decreasing abscissa (" + std::to_string(v) + " < " +
                                  std::to_string(points[i - 1].first) + ")");
    }
    if (i > 1 && v == points[i - 1].first && v == points[i - 2].first) {
      throw std::invalid_argument(where + " is the third point at abscissa " + std::to_string(v) +
                                  " (at most 2: a jump)");
    }
    data->xs.push_back(v);
    data->ys.push_back(u);
  }
  data->lo = data->xs.front();
  data->hi = data->xs.back();
  if (!(data->lo < data->hi)) {
    throw std::invalid_argument("Border::from_table: point " + std::to_string(points.size() - 1) +
                                " leaves a zero-width domain (all abscissas equal)");
  }
  const std::size_t segments = data->xs.size() - 1;
  for (std::size_t first = 0; first + Data::kSegmentBlock <= segments; first += Data::kSegmentBlock) {
    const auto begin = data->ys.begin() + static_cast<std::ptrdiff_t>(first);
    const auto [low, high] = std::minmax_element(begin, begin + static_cast<std::ptrdiff_t>(Data::kSegmentBlock + 1));
    data->segment_block_min.push_back(*low);
    data->segment_block_max.push_back(*high);
  }
  return Border(std::move(data));
}

double Border::operator()(double v) const { return data_->value(v); }
double Border::lo() const { return data_->lo; }
double Border::hi() const { return data_->hi; }
bool Border::is_table() const { return data_->table; }

std::optional<double> Border::last_reach(double level, double a, double b) const {
  return data_->reach(level, a, b, true, true);
}

std::optional<double> Border::first_reach(double level, double a, double b) const {
  return data_->reach(level, a, b, false, true);
}

bool Border::reaches(double level, double a, double b, Scan scan) const {
  return data_->meets(level, a, b, scan == Scan::from_right);
}

double Border::operator()(double v, Hint& hint) const { return data_->value(v, hint.index); }

}  // namespace lashid::sim
