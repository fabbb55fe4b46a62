// Small PNG charts drawn with Cairo for the benchmark report: line plots
// (recall against size or angle, one line per detector) and a heat map
// (recall over size x angle). Functions return false and set *error when the
// file cannot be written; they never print.
#ifndef CHROMATAG_BENCH_PLOT_H_
#define CHROMATAG_BENCH_PLOT_H_

#include <array>
#include <string>
#include <vector>

namespace chromatag::bench {

struct Series {
  std::string name;
  std::array<double, 3> rgb{0, 0, 0};  // Line colour, channels in [0, 1].
  std::vector<double> x, y;            // A NaN y breaks the line.
};

struct LinePlot {
  std::string title, x_label, y_label;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  double x_tick = 0.1, y_tick = 0.1;  // Grid spacing in data units.
  std::vector<Series> series;
};

bool WriteLinePlot(const LinePlot& plot, const std::string& png_path, std::string* error);

struct HeatMap {
  std::string title, x_label, y_label;
  std::vector<double> x_edges, y_edges;  // Cell boundaries, ascending; n + 1 each.
  // values[row][col], row along y, in [0, 1]; NaN draws an empty (grey) cell.
  std::vector<std::vector<double>> values;
  std::vector<std::vector<int>> counts;  // Printed small in each cell.
};

bool WriteHeatMap(const HeatMap& map, const std::string& png_path, std::string* error);

// Low (dark blue) to high (yellow) colour scale, as the paper's Figure 9c.
std::array<double, 3> ScaleColor(double value);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_PLOT_H_
