#include "lashid/report/plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include <fmt/format.h>

#include "lashid/io/files.hpp"
#include "lashid/io/recording.hpp"

namespace lashid::report::plot {

namespace fs = std::filesystem;

namespace {

// gnuplot single-quoted string: only ' is special, written ''.
std::string gp_string(std::string_view text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\n') continue;
    out += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return out + "'";
}

// Shell single-quoted word.
std::string shell_word(std::string_view text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "lashid_plot_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create a temporary directory");
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string script_for(const Figure& figure, const fs::path& dir, const fs::path& png) {
  const int columns = figure.columns;
  const int n = static_cast<int>(figure.panels.size());
  const int rows = (n + columns - 1) / columns;
  const int used_columns = n < columns ? n : columns;
  std::string s;
  s += fmt::format("set terminal pngcairo size {},{} noenhanced font 'sans,10'\n", used_columns * figure.panel_width,
                   rows * figure.panel_height);
  s += fmt::format("set output {}\n", gp_string(png.string()));
  s += "set grid\nset key top left box opaque\n";
  s += fmt::format("set multiplot layout {},{}{}\n", rows, columns,
                   figure.title.empty() ? "" : " title " + gp_string(figure.title));
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const Panel& panel = figure.panels[p];
    s += fmt::format("set title {}\nset xlabel {}\nset ylabel {}\n", gp_string(panel.title), gp_string(panel.x_label),
                     gp_string(panel.y_label));
    std::string plot;
    for (std::size_t k = 0; k < panel.series.size(); ++k) {
      const Series& series = panel.series[k];
      if (series.x.empty()) continue;
      const fs::path data = dir / fmt::format("panel{}_series{}.dat", p, k);
      std::ofstream out(data);
      for (std::size_t i = 0; i < series.x.size(); ++i) {
        if (std::isfinite(series.x[i]) && std::isfinite(series.y[i])) {
          out << fmt::format("{} {}\n", series.x[i], series.y[i]);
        } else {
          out << "\n";
        }
      }
      if (!out) throw std::runtime_error("cannot write plot data to " + data.string());
      plot += fmt::format("{}{} using 1:2 with lines lw 1.2 title {}", plot.empty() ? "plot " : ", ",
                          gp_string(data.string()), gp_string(series.name));
    }
    s += (plot.empty() ? "plot NaN notitle" : plot) + "\n";
  }
  s += "unset multiplot\nset output\n";
  return s;
}

int exit_code(const std::string& command) {
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

sim::DataError gnuplot_not_found(const std::string& out, const std::string& gnuplot_exe) {
  return sim::DataError(out, fmt::format("cannot plot: '{}' not found (install gnuplot-nox)", gnuplot_exe));
}

}  // namespace

void check_can_plot(const fs::path& out, const std::string& gnuplot_exe) {
  sim::check_can_write(out);
  // The shell answers 127 when it cannot find or run the command.
  if (exit_code(fmt::format("{} --version >/dev/null 2>&1 </dev/null", shell_word(gnuplot_exe))) == 127) {
    throw gnuplot_not_found(out.string(), gnuplot_exe);
  }
}

void write_png(const Figure& figure, const fs::path& out, const std::string& gnuplot_exe) {
  if (figure.panels.empty()) throw std::invalid_argument("plot: a figure needs at least one panel");
  if (figure.columns < 1) throw std::invalid_argument("plot: columns must be >= 1");
  for (const auto& panel : figure.panels) {
    for (const auto& series : panel.series) {
      if (series.x.size() != series.y.size()) {
        throw std::invalid_argument(fmt::format("plot: series '{}' has {} x and {} y values", series.name,
                                                series.x.size(), series.y.size()));
      }
    }
  }
  const std::string name = out.string();
  sim::check_can_write(out);
  const TemporaryDirectory dir;
  const fs::path png = dir.path() / "figure.png";
  const fs::path script = dir.path() / "figure.gp";
  const fs::path log = dir.path() / "gnuplot.log";
  {
    std::ofstream s(script);
    s << script_for(figure, dir.path(), png);
    if (!s) throw sim::DataError(name, "cannot write the gnuplot script to a temporary directory");
  }
  const std::string command = fmt::format("{} {} >{} 2>&1 </dev/null", shell_word(gnuplot_exe),
                                          shell_word(script.string()), shell_word(log.string()));
  const int code = exit_code(command);
  if (code == 127) throw gnuplot_not_found(name, gnuplot_exe);
  if (code != 0 || !fs::is_regular_file(png)) {
    std::string message = sim::read_file_text(log);
    if (message.size() > 2000) message.resize(2000);
    throw sim::DataError(name, fmt::format("gnuplot failed (exit code {}): {}", code, message));
  }
  sim::write_file_atomically(out, sim::read_file_text(png));
}

}  // namespace lashid::report::plot
