// --plot of `lashid diagnose`: val simulations and the residual correlations with their 99 % bands.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/report/diagnose_plot.hpp"
#include "lashid/report/plot.hpp"

namespace lashid::report {

namespace {

std::vector<double> iota(std::size_t count, double first) {
  std::vector<double> x(count);
  for (std::size_t i = 0; i < count; ++i) x[i] = first + static_cast<double>(i);
  return x;
}

plot::Panel correlation_panel(std::string title, const std::vector<double>& r, double first_lag, double band) {
  const std::vector<double> lags = iota(r.size(), first_lag);
  const double last_lag = lags.back();
  return {std::move(title),
          "lag (samples)",
          "correlation",
          {{"r", lags, r},
           {"99 % band", {first_lag, last_lag}, {band, band}},
           {"-99 % band", {first_lag, last_lag}, {-band, -band}}}};
}

}  // namespace

void plot_diagnosis(const sim::Diagnosis& d, const std::string& png_path) {
  const std::vector<double> t = iota(d.val_measured.size(), 0.0);
  plot::Figure figure;
  std::vector<std::string_view> names;
  for (const sim::Cause c : d.causes) names.push_back(sim::to_string(c));
  const std::string causes = fmt::format("{}", fmt::join(names, "+"));
  figure.title = fmt::format("lashid diagnose: cause{} {} {}", d.causes.size() > 1 ? "s" : "", causes,
                             to_string(d.parameters));
  figure.panels.push_back(
      {fmt::format("val: fit {} (nominal), {} (extended)", sim::describe_fit(d.fit_nominal),
                   sim::describe_fit(d.fit_extended)),
       "sample of val",
       "y",
       {{"measured", t, d.val_measured}, {"nominal simulation", t, d.val_nominal},
        {"extended simulation", t, d.val_extended}}});
  figure.panels.push_back({"val input", "sample of val", "v", {{"v", t, d.val_v}}});
  figure.panels.push_back(correlation_panel("autocorrelation of the nominal residuals (identification phases)",
                                            d.identification.autocorrelation, 0.0, d.identification.band));
  figure.panels.push_back(correlation_panel("cross-correlation residuals / input v (identification phases)",
                                            d.identification.cross_correlation, -sim::kResidualLags,
                                            d.identification.band));
  figure.panels.push_back(correlation_panel("autocorrelation of the nominal residuals (val, one step ahead)",
                                            d.validation.autocorrelation, 0.0, d.validation.band));
  figure.panels.push_back(correlation_panel("cross-correlation residuals / input v (val)",
                                            d.validation.cross_correlation, -sim::kResidualLags, d.validation.band));
  plot::write_png(figure, png_path);
}

}  // namespace lashid::report
