// The estimator run on a recording in float (see identify_dispatch.hpp).
#include "identify_dispatch.hpp"

namespace lashid::sim::detail {
template SchemeResult run<float>(const ExperimentConfig&, const Recording&, est::Scheme, std::string_view, bool);
}  // namespace lashid::sim::detail
