// Plots as PNG files, drawn by gnuplot (Debian gnuplot-nox, pngcairo terminal).
// Each plot writes three files side by side: NAME.png, NAME.gp (the script)
// and NAME.dat (the data), so a person can re-run or tweak it.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace magenc {

struct PlotSeries {
  std::string title;           // legend entry
  std::vector<double> x, y;    // same length
  std::string style = "lines"; // gnuplot style: "lines", "points", "linespoints", "boxes", "impulses"
  std::string extra;           // extra gnuplot "with" options, e.g. "lw 2 dt 2"
};

struct PlotPanel {
  std::string title;
  std::string xlabel;  // with unit, e.g. "theta [deg]"
  std::string ylabel;  // with unit, e.g. "angle error [deg]"
  std::vector<PlotSeries> series;
  bool logx = false, logy = false;
};

struct PlotSpec {
  std::string title;               // figure title
  std::vector<PlotPanel> panels;   // laid out in a grid (multiplot)
  int columns = 1;                 // panels per row
  int width_px = 1000, height_px = 700;
};

// Writes dir/name.{png,gp,dat}. Throws ComputeError if gnuplot fails or is missing.
void write_plot(const std::filesystem::path& dir, const std::string& name, const PlotSpec& spec);

}  // namespace magenc
