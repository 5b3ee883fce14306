// The estimator instantiations for model order n = 2 (see identify_dispatch.hpp).
#include "identify_dispatch.hpp"

namespace lashid::sim::detail {
template SchemeResult identify_order<2>(const ExperimentConfig&, const Recording&, est::Scheme,
                                         const IdentifyOptions&, std::string_view);
}  // namespace lashid::sim::detail
