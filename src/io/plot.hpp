// Plots as PNG files, drawn by gnuplot (Debian gnuplot-nox, pngcairo terminal).
// Each plot writes three files side by side: NAME.png, NAME.gp (the script)
// and NAME.dat (the data), so a person can re-run or tweak it
// (`cd DIR && gnuplot NAME.gp`).
//
// Texts (titles, labels, legend entries) are gnuplot "enhanced" text: '_' and
// '^' make sub/superscripts, {/Symbol q} is theta. Pass literal text through
// plot_literal() when it may contain those characters (e.g. "c3_deg").
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace magenc {

struct PlotSeries {
  std::string title;           // legend entry (empty: no entry)
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
  // Extra gnuplot commands issued before this panel's plot command (after the
  // panel's defaults), e.g. "set xtics 1", "set yrange [0:*]",
  // "set boxwidth 0.2". Settings are reset between panels.
  std::vector<std::string> commands;
};

// A panel with its title and axis labels (series and settings added by the caller).
inline PlotPanel plot_panel(std::string title, std::string xlabel, std::string ylabel) {
  PlotPanel p;
  p.title = std::move(title);
  p.xlabel = std::move(xlabel);
  p.ylabel = std::move(ylabel);
  return p;
}

struct PlotSpec {
  std::string title;               // figure title
  std::vector<PlotPanel> panels;   // laid out in a grid (multiplot)
  int columns = 1;                 // panels per row
  int width_px = 1000, height_px = 700;
};

// Escapes enhanced-text control characters (_ ^ @ & ~ { }) so s prints literally.
std::string plot_literal(const std::string& s);

// Writes dir/name.{png,gp,dat}. Series with no points are drawn as empty
// legend entries; non-finite y values are gaps. Throws InputError for a name
// that is not a plain file name or series with x/y of different lengths.
// Runs `gnuplot NAME.gp` in dir; throws ComputeError (with gnuplot's last
// message) if gnuplot is missing, fails, or leaves no PNG.
void write_plot(const std::filesystem::path& dir, const std::string& name, const PlotSpec& spec);

// A heat map: a matrix of values, one coloured cell per (row, column), each
// cell optionally labelled with a text (e.g. its value). First row on top.
struct HeatmapSpec {
  std::string title;
  std::string xlabel, ylabel;                  // axis titles (enhanced text)
  std::vector<std::string> column_labels;      // x tick labels, left to right (enhanced text)
  std::vector<std::string> row_labels;         // y tick labels, top to bottom (enhanced text)
  std::vector<std::vector<double>> values;     // rows x columns; NaN = blank cell
  std::vector<std::vector<std::string>> cell_text;  // rows x columns, or empty (no labels)
  std::string cblabel;                         // colour-bar title
  bool log_colour = true;                      // logarithmic colour scale ...
  double log_floor = 1e-4;                     // ... values below this get the lowest colour
  std::vector<int> row_separators;             // draw a line above these rows (e.g. between groups)
  int cell_font_size = 9;
  int width_px = 1100, height_px = 900;
};
// Writes dir/name.{png,gp,dat} (gnuplot `with image` plus `with labels`).
// InputError for a bad name or inconsistent sizes; ComputeError as write_plot.
void write_heatmap(const std::filesystem::path& dir, const std::string& name, const HeatmapSpec& spec);

}  // namespace magenc
