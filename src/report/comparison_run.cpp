#include "report/comparison_run.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "io/plot.hpp"
#include "io/tables.hpp"

namespace magenc {

void write_comparison_tables(StudyOutput& out, const ComparisonRun& run) {
  out.write_text("spectra.csv", spectra_csv(comparison_spectra_rows(run)));
  out.write_text("comparison.csv", comparison_csv(run.compared, spectrum_columns()));
  out.write_text("fits.csv", fits_csv(run.fits));
}

std::vector<SweepCase> coefficient_cases(const ComparisonRun& run, std::size_t k) {
  std::vector<SweepCase> sc;
  for (const auto& r : run.arrays) {
    const std::string a = plot_literal(r.setup.array.name);
    if (!r.fem.empty()) sc.push_back({a + " " + r.fem.front().label, &r.fem.front().sweeps.at(k)});
    sc.push_back({a + " exact", &r.exact.sweeps.at(k)});
  }
  return sc;
}

std::vector<DifferenceCase> difference_cases(const ComparisonRun& run, std::size_t k) {
  std::vector<DifferenceCase> dc;
  for (const auto& r : run.arrays) {
    const std::string a = plot_literal(r.setup.array.name);
    for (const auto& f : r.fem) dc.push_back({a + " " + f.label, &f.sweeps.at(k), &r.exact.sweeps.at(k)});
  }
  return dc;
}

std::vector<std::string> write_comparison_plots(const std::filesystem::path& dir, const ComparisonRun& run,
                                                std::size_t k, const SweepPlotText& text,
                                                const std::vector<std::string>& diff_coefs) {
  write_plot(dir, "coefficients_" + text.tag,
             coefficient_figure(text.coefficients_title, text.xlabel, coefficient_cases(run, k), run.fits,
                                run.plan.fit_coefs));
  write_plot(dir, "differences_" + text.tag,
             difference_figure(text.differences_title, text.xlabel, difference_cases(run, k), diff_coefs));
  return {"coefficients_" + text.tag + ".png", "differences_" + text.tag + ".png"};
}

std::string max_difference_table(const ComparisonRun& run, const std::string& first_header,
                                 const std::vector<std::string>& coefs) {
  std::vector<std::vector<std::string>> t;
  for (std::size_t k = 0; k < run.plan.sweeps.size(); ++k)
    for (const auto& r : run.arrays)
      for (const auto& f : r.fem) {
        std::vector<std::string> row{run.plan.sweeps[k].label, "`" + r.setup.array.name + "`", f.label};
        for (const auto& coef : coefs) row.push_back(fmt(max_abs_difference(f.sweeps[k], r.exact.sweeps[k], coef), 5));
        t.push_back(row);
      }
  std::vector<std::string> header{first_header, "array", "source"};
  for (const auto& c : coefs) header.push_back("max abs diff " + c.substr(0, c.find('_')));
  return md_table(header, t);
}

std::string fe_solution_text(const std::string& dir, const std::string& description, const std::vector<FemSource>& sources,
                             const std::string& interp) {
  std::ostringstream s;
  s << "FE solution `" << dir << "` (" << description << "), used through ";
  for (std::size_t i = 0; i < sources.size(); ++i)
    s << (i ? " and " : "") << "`" << sources[i].spec << "`"
      << (sources[i].label == "grid" ? " (" + interp + " interpolation)" : "");
  return s.str();
}

}  // namespace magenc
