// `lashid identify`: DIS and/or AIS on a recording, printed next to the truth, optionally as JSON.
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/files.hpp"
#include "lashid/io/recording.hpp"
#include "lashid/report/json.hpp"
#include "lashid/report/report.hpp"

namespace lashid::app {

using namespace lashid::sim;

int run_identify(const IdentifyArgs& args) {
  if (!args.json_out.empty()) check_can_write(args.json_out);  // before the work, not after it
  const ExperimentConfig config = read_config_json(args.config);
  // A float32 device's recording (lashid hil --record) holds float(V_j): the estimator is given the levels.
  const Recording rec = read_recording_for(config, args.data);
  for (const std::string& note : phase_length_notes(config, rec, args.data)) fmt::print(stderr, "lashid: note: {}\n", note);
  IdentifyOptions options;
  options.precision = args.use_float ? Precision::kFloat : Precision::kDouble;

  // auto: the schemes whose phases the data holds; dis, ais or both: those, and their phases must be there
  // (identify_scheme names a missing one).
  const bool want_dis = args.scheme == "dis" || args.scheme == "both" || (args.scheme == "auto" && rec.has(Phase::kDis));
  const bool want_ais = args.scheme == "ais" || args.scheme == "both" || (args.scheme == "auto" && rec.has(Phase::kAis));
  if (!want_dis && !want_ais) {
    throw DataError(args.data, "no 'dis' or 'ais' phase: nothing to identify");
  }
  // Both schemes first, then the output: a scheme that fails on its data (a missing phase) prints nothing at all.
  std::vector<SchemeResult> results;
  for (const auto scheme : {est::Scheme::kDescending, est::Scheme::kAscending}) {
    const bool dis = scheme == est::Scheme::kDescending;
    if (dis ? !want_dis : !want_ais) continue;
    results.push_back(identify_scheme(config, rec, scheme, options, args.data));
  }
  nlohmann::json out = nlohmann::json::object();
  int exit_code = 0;
  for (const SchemeResult& r : results) {
    const bool dis = r.scheme == est::Scheme::kDescending;
    if (r.out_of_sensor_range > 0) {
      fmt::print(stderr, "lashid: note: {}: {} sample{} outside the config's sensor_range [{:g}, {:g}] left out, with the rows "
                         "that lag them, as the device leaves them out\n",
                 dis ? "DIS" : "AIS", r.out_of_sensor_range, r.out_of_sensor_range > 1 ? "s" : "",
                 (*config.sensor_range)[0], (*config.sensor_range)[1]);
    }
    report::print_scheme_result(config, r);
    if (r.status != est::Status::kOk) exit_code = 2;
    out[dis ? "dis" : "ais"] = to_json(r, config);
  }
  if (!args.json_out.empty()) write_json_file(args.json_out, out);
  return exit_code;
}

}  // namespace lashid::app
