// gnuplot driver for plot.hpp: NAME.dat holds one data block per series
// (blocks separated by two blank lines, addressed with `index`), NAME.gp the
// script that draws them into NAME.png with the pngcairo terminal.
#include "io/plot.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace fs = std::filesystem;

namespace magenc {

namespace {

// A number in a .dat block: 10 significant digits; NaN for gnuplot's missing points.
std::string data_text(double v) { return std::isfinite(v) ? fmt_sig(v, 10) : std::string("NaN"); }

// A gnuplot single-quoted string literal ('' stands for one quote).
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "''";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out + "'";
}

// A POSIX shell single-quoted word.
std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

bool has_finite_point(const PlotPanel& panel) {
  for (const auto& s : panel.series)
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) return true;
  return false;
}

bool is_line_style(const std::string& style) {
  return style == "lines" || style == "linespoints" || style == "impulses" || style == "steps";
}

std::string last_lines(const std::string& text, int n) {
  std::vector<std::string> lines;
  std::istringstream is(text);
  for (std::string l; std::getline(is, l);)
    if (!l.empty()) lines.push_back(l);
  std::string out;
  for (std::size_t i = lines.size() > std::size_t(n) ? lines.size() - n : 0; i < lines.size(); ++i)
    out += (out.empty() ? "" : " | ") + lines[i];
  return out;
}

// Writes dir/name.dat and dir/name.gp and runs gnuplot, which must write dir/name.png.
void run_gnuplot(const fs::path& dir, const std::string& name, const std::string& dat_text, const std::string& gp_text) {
  const std::string png = name + ".png", datfile = name + ".dat";
  std::error_code ec;
  fs::create_directories(dir, ec);
  {
    std::ofstream f(dir / datfile);
    f << dat_text;
    std::ofstream g(dir / (name + ".gp"));
    g << gp_text;
    if (!f || !g) throw ComputeError("plot " + name + ": cannot write into " + dir.string());
  }
  const fs::path log = dir / (name + ".gnuplot.log");
  fs::remove(dir / png, ec);
  const std::string cmd = "cd " + shell_quoted(dir.string()) + " && gnuplot " + shell_quoted(name + ".gp") +
                          " >" + shell_quoted(log.filename().string()) + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::string log_text;
  {
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    log_text = ss.str();
  }
  fs::remove(log, ec);
  const bool exited_ok = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!exited_ok) {
    fs::remove(dir / png, ec);  // gnuplot may have drawn some panels before failing: no partial PNG
    const bool missing = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 127;
    throw ComputeError("plot " + name + ": " +
                       (missing ? std::string("gnuplot not found (install gnuplot-nox)")
                                : "gnuplot failed: " + last_lines(log_text, 3)));
  }
  if (!fs::exists(dir / png) || fs::file_size(dir / png) == 0) {
    fs::remove(dir / png, ec);
    throw ComputeError("plot " + name + ": gnuplot wrote no " + png + " (" + last_lines(log_text, 3) + ")");
  }
}

void check_plot_name(const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name.find('\'') != std::string::npos)
    throw InputError("plot name '" + name + "' must be a plain file name");
}

}  // namespace

std::string plot_literal(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '^' || c == '@' || c == '&' || c == '~' || c == '{' || c == '}') out += '\\';
    out += c;
  }
  return out;
}

void write_plot(const fs::path& dir, const std::string& name, const PlotSpec& spec) {
  check_plot_name(name);
  if (spec.panels.empty()) throw InputError("plot " + name + ": no panels");
  const int columns = std::max(1, spec.columns);
  const int rows = (static_cast<int>(spec.panels.size()) + columns - 1) / columns;

  // 1. Data: one block per series, in panel order.
  std::ostringstream dat;
  dat << "# " << name << ".dat: data of " << name << ".png; one block per series (gnuplot index)\n";
  int block = 0;
  std::vector<std::vector<int>> block_of(spec.panels.size());
  for (std::size_t p = 0; p < spec.panels.size(); ++p) {
    for (const auto& s : spec.panels[p].series) {
      if (s.x.size() != s.y.size())
        throw InputError("plot " + name + ", series '" + s.title + "': x and y differ in length");
      if (block > 0) dat << "\n\n";
      dat << "# index " << block << ": panel " << p << " '" << spec.panels[p].title << "', series '"
          << s.title << "'\n";
      if (s.x.empty()) dat << "NaN NaN\n";
      for (std::size_t i = 0; i < s.x.size(); ++i) dat << data_text(s.x[i]) << ' ' << data_text(s.y[i]) << '\n';
      block_of[p].push_back(block++);
    }
  }

  // 2. Script.
  const std::string png = name + ".png", datfile = name + ".dat";
  std::ostringstream gp;
  gp << "# " << name << ".gp: draws " << png << " from " << datfile << " (run: gnuplot " << name << ".gp)\n";
  gp << "set terminal pngcairo size " << spec.width_px << "," << spec.height_px
     << " enhanced font 'sans,11'\n";
  gp << "set output " << quoted(png) << "\n";
  gp << "set datafile missing 'NaN'\n";
  gp << "set style fill solid 0.75 border -1\n";
  gp << "set multiplot layout " << rows << "," << columns;
  if (!spec.title.empty()) gp << " title " << quoted(spec.title) << " font 'sans,13'";
  gp << "\n";
  for (std::size_t p = 0; p < spec.panels.size(); ++p) {
    const PlotPanel& panel = spec.panels[p];
    gp << "\n# panel " << p << "\n";
    gp << "unset logscale; unset label; unset arrow; set autoscale xy\n";
    gp << "set xtics autofreq; set ytics autofreq; set format x '% h'; set format y '% h'\n";
    gp << "set boxwidth; set grid xtics ytics lc rgb '#b0b0b0' lw 1 dt 1\n";
    gp << "set key default; set key top right box opaque samplen 2 spacing 1.1\n";
    gp << "set title " << quoted(panel.title) << "\n";
    gp << "set xlabel " << quoted(panel.xlabel) << "\n";
    gp << "set ylabel " << quoted(panel.ylabel) << "\n";
    if (panel.logx) gp << "set logscale x\n";
    if (panel.logy) gp << "set logscale y\n";
    if (!has_finite_point(panel)) {
      gp << "set xrange [0:1]; set yrange [-1:1]\n";
      gp << "set label 'no data' at graph 0.5, 0.5 center\n";
    }
    for (const auto& c : panel.commands) gp << c << "\n";
    if (panel.series.empty()) {
      gp << "plot NaN notitle\n";
      continue;
    }
    gp << "plot ";
    for (std::size_t k = 0; k < panel.series.size(); ++k) {
      const PlotSeries& s = panel.series[k];
      std::string opts = s.extra;
      if (is_line_style(s.style) && opts.find("lw") == std::string::npos &&
          opts.find("linewidth") == std::string::npos)
        opts = "lw 2 " + opts;
      if (s.style == "points" && opts.find("pt") == std::string::npos &&
          opts.find("pointtype") == std::string::npos)
        opts = "pt 7 ps 0.8 " + opts;
      gp << (k ? ", \\\n     " : "") << quoted(datfile) << " index " << block_of[p][k]
         << " using 1:2 with " << s.style << " " << opts
         << (s.title.empty() ? std::string(" notitle") : " title " + quoted(s.title));
    }
    gp << "\n";
  }
  gp << "\nunset multiplot\nset output\n";

  // 3. Files and gnuplot.
  run_gnuplot(dir, name, dat.str(), gp.str());
}

void write_heatmap(const fs::path& dir, const std::string& name, const HeatmapSpec& spec) {
  check_plot_name(name);
  const std::size_t nr = spec.row_labels.size(), nc = spec.column_labels.size();
  if (nr == 0 || nc == 0) throw InputError("heat map " + name + ": no rows or no columns");
  if (spec.values.size() != nr) throw InputError("heat map " + name + ": values and row labels differ in count");
  for (const auto& r : spec.values)
    if (r.size() != nc) throw InputError("heat map " + name + ": a row of values has the wrong length");
  if (!spec.cell_text.empty() && spec.cell_text.size() != nr)
    throw InputError("heat map " + name + ": cell texts and row labels differ in count");
  if (spec.log_colour && !(spec.log_floor > 0)) throw InputError("heat map " + name + ": log_floor must be > 0");

  // 1. Data: x (column), y (row, first row on top), colour value, cell text.
  double vmax = spec.log_colour ? spec.log_floor : 0, vmin = 0;
  bool first = true;
  for (const auto& r : spec.values)
    for (double v : r)
      if (std::isfinite(v)) {
        vmax = first ? v : std::max(vmax, v);
        vmin = first ? v : std::min(vmin, v);
        first = false;
      }
  std::ostringstream dat;
  dat << std::setprecision(10);
  dat << "# " << name << ".dat: data of " << name << ".png; columns: column index, row index (0 = bottom), colour value"
      << (spec.log_colour ? " (clipped below at " + (std::ostringstream() << spec.log_floor).str() + ")" : std::string())
      << ", cell text, text colour (white on the dark end of the palette)\n";
  const double cb_lo = spec.log_colour ? spec.log_floor : std::min(vmin, 0.0);
  const double cb_hi = spec.log_colour ? std::max(vmax, 10 * spec.log_floor) : (vmax > cb_lo ? vmax : 1.0);
  // Position of a value along the colour bar, 0..1; above 0.6 the palette is dark red.
  auto dark = [&](double v) {
    const double f = spec.log_colour ? std::log(v / cb_lo) / std::log(cb_hi / cb_lo) : (v - cb_lo) / (cb_hi - cb_lo);
    return std::isfinite(v) && f > 0.6;
  };
  for (std::size_t r = 0; r < nr; ++r) {
    for (std::size_t c = 0; c < nc; ++c) {
      double v = spec.values[r][c];
      if (std::isfinite(v) && spec.log_colour) v = std::max(v, spec.log_floor);
      std::string text = spec.cell_text.empty() || spec.cell_text[r].size() != nc ? "" : spec.cell_text[r][c];
      for (char& ch : text)
        if (ch == '"') ch = '\'';
      dat << c << ' ' << (nr - 1 - r) << ' ' << (std::isfinite(v) ? (std::ostringstream() << std::setprecision(10) << v).str() : "NaN")
          << " \"" << text << "\" " << (dark(v) ? "16777215" : "0") << "\n";
    }
    dat << "\n";
  }

  // 2. Script.
  const std::string png = name + ".png", datfile = name + ".dat";
  std::ostringstream gp;
  gp << "# " << name << ".gp: draws " << png << " from " << datfile << " (run: gnuplot " << name << ".gp)\n";
  gp << "set terminal pngcairo size " << spec.width_px << "," << spec.height_px << " enhanced font 'sans,11'\n";
  gp << "set output " << quoted(png) << "\n";
  // No "set datafile missing": a missing cell would drop out of the image's grid and shift the cells
  // after it; a NaN value is drawn blank in place.
  gp << "set title " << quoted(spec.title) << " font 'sans,13'\n";
  gp << "set xlabel " << quoted(spec.xlabel) << "\nset ylabel " << quoted(spec.ylabel) << "\n";
  gp << "set xrange [-0.5:" << nc - 0.5 << "]\nset yrange [-0.5:" << nr - 0.5 << "]\n";
  gp << "set xtics (";
  for (std::size_t c = 0; c < nc; ++c) gp << (c ? ", " : "") << quoted(spec.column_labels[c]) << " " << c;
  gp << ") scale 0\nset ytics (";
  for (std::size_t r = 0; r < nr; ++r) gp << (r ? ", " : "") << quoted(spec.row_labels[r]) << " " << nr - 1 - r;
  gp << ") scale 0\n";
  gp << "set cblabel " << quoted(spec.cblabel) << "\n";
  if (spec.log_colour) gp << "set logscale cb\nset format cb '10^{%L}'\n";
  gp << "set cbrange [" << cb_lo << ":" << cb_hi << "]\n";
  gp << "set palette defined (0 '#fffff0', 1 '#fdd49e', 2 '#fc8d59', 3 '#d7301f', 4 '#7f0000')\n";
  gp << "unset key\n";
  for (int sep : spec.row_separators)
    if (sep > 0 && std::size_t(sep) < nr)
      gp << "set arrow from -0.5," << nr - sep - 0.5 << " to " << nc - 0.5 << "," << nr - sep - 0.5
         << " nohead front lw 2 lc rgb '#000000'\n";
  gp << "plot " << quoted(datfile) << " using 1:2:3 with image, \\\n     " << quoted(datfile)
     << " using 1:2:4:5 with labels font 'sans," << spec.cell_font_size << "' tc rgb variable\n";
  gp << "set output\n";
  run_gnuplot(dir, name, dat.str(), gp.str());
}

}  // namespace magenc
