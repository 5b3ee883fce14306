// What the firmware-on-the-host-board tests share: a sensor that gives a bad reading at chosen samples, and the
// comparison of the firmware's reports with `lashid identify` on the same recording.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "firmware_reports.hpp"
#include "lashid/hal/status.hpp"
#include "lashid/hil/hil.hpp"  // sim::ScenarioBoard, make_scenario_board
#include "lashid/identify/identify.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::test {

// A sensor that returns a bad reading (and says ok) at the chosen samples: the estimator must refuse them, and the
// firmware must count them instead of dropping the status.
class NanSensorBoard : public sim::ScenarioBoard {
 public:
  /// `bad` is the reading given at those samples: NaN by default, or a finite value too large for the estimator.
  NanSensorBoard(sim::ScenarioBoard board, std::vector<std::size_t> nan_at, float bad = std::nanf(""))
      : sim::ScenarioBoard(std::move(board)), nan_at_(std::move(nan_at)), bad_(bad) {}
  hal::Status measure(float& y) {
    const hal::Status s = sim::ScenarioBoard::measure(y);
    if (std::find(nan_at_.begin(), nan_at_.end(), exchanges().size() - 1) != nan_at_.end()) y = bad_;
    return s;
  }

 private:
  std::vector<std::size_t> nan_at_;
  float bad_;
};

// Both schemes' reported estimates equal `identify --float` (with `options`) on `rec`: a, b, F and ybar0, n = 2, m = 6.
inline void expect_cli_estimates(const Reports& r, const sim::ExperimentConfig& config, const sim::Recording& rec,
                                 const sim::IdentifyOptions& options) {
  ASSERT_EQ(r.estimates.size(), 2u);
  for (const auto& e : r.estimates) {
    const sim::SchemeResult cli = sim::identify_scheme(config, rec, e.scheme, options, "rec");
    EXPECT_EQ(e.status, static_cast<int>(est::Status::kOk));
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_FLOAT_EQ(e.a[i], static_cast<float>(cli.a[i]));
      EXPECT_FLOAT_EQ(e.b[i], static_cast<float>(cli.b[i]));
    }
    for (std::size_t j = 0; j < 6; ++j) EXPECT_FLOAT_EQ(e.F[j], static_cast<float>(cli.F[j]));
    EXPECT_FLOAT_EQ(e.ybar0, static_cast<float>(cli.ybar0));
  }
}


}  // namespace lashid::test
