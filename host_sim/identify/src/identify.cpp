#include "lashid/identify/identify.hpp"

#include <fmt/format.h>

#include "identify_dispatch.hpp"

namespace lashid::sim {

static_assert(kMaxOrder == 3, "identify_scheme dispatches orders 1..3: add an identify_order_<N>.cpp per order");

SchemeResult identify_scheme(const ExperimentConfig& config, const Recording& recording, est::Scheme scheme,
                             const IdentifyOptions& options, std::string_view data_name) {
  switch (config.n) {
    case 1: return detail::identify_order<1>(config, recording, scheme, options, data_name);
    case 2: return detail::identify_order<2>(config, recording, scheme, options, data_name);
    case 3: return detail::identify_order<3>(config, recording, scheme, options, data_name);
    default:
      throw DataError(data_name, fmt::format("n = {} is outside the compiled range [1, {}]", config.n, kMaxOrder));
  }
}

}  // namespace lashid::sim
