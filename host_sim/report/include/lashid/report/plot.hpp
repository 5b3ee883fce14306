// Figures as PNG through gnuplot (pngcairo terminal): a grid of panels, each with a title, axis labels and named
// (x, y) line series. Used by `lashid operator-fit --plot`; generic on purpose (any command can draw with it).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lashid::report::plot {

struct Series {
  std::string name;  ///< legend entry (printed literally, no gnuplot markup)
  std::vector<double> x;
  std::vector<double> y;  ///< same length as x; non-finite points break the line
};

struct Panel {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<Series> series;
};

struct Figure {
  std::string title;  ///< over all panels; may be empty
  std::vector<Panel> panels;
  int columns = 2;           ///< panels per row
  int panel_width = 640;     ///< pixels
  int panel_height = 440;
};

/// Renders `figure` to the PNG file `out`: data and script go to a fresh temporary directory (removed afterwards),
/// `gnuplot_exe` runs the script, and the image replaces `out` atomically. Throws lashid::sim::DataError naming
/// `out` if it cannot be written, if gnuplot is not found ("install gnuplot-nox"), or if gnuplot fails (with its
/// error output); `out` is then left untouched. Throws std::invalid_argument for a figure without panels, columns
/// < 1 or a series whose x and y differ in length.
void write_png(const Figure& figure, const std::filesystem::path& out, const std::string& gnuplot_exe = "gnuplot");

/// Before any work whose result is to be plotted: throws the DataError write_png would (naming `out`) if `out`
/// cannot be written or `gnuplot_exe` cannot be run.
void check_can_plot(const std::filesystem::path& out, const std::string& gnuplot_exe = "gnuplot");

}  // namespace lashid::report::plot
