// Standard figures shared by the studies, built on plot.hpp:
//   eps_panel          angle error eps(theta) of several mounting cases
//   harmonics_panel    grouped bars |a0|, c1..c8 per case
//   coefficient_figure one panel per spectrum coefficient: value vs swept
//                      offset (points) with its cubic fit (line), one colour
//                      per sweep
//   difference_figure  one panel per coefficient: FEM - exact vs the swept
//                      offset, one series per FEM source and array
#pragma once
#include <string>
#include <vector>

#include "probe/angle_error.hpp"
#include "io/plot.hpp"
#include "report/study_output.hpp"
#include "analysis/sweep.hpp"

namespace magenc {

// Axis label of a spectra column: "c3_deg" -> "c_{3} [deg]", "pp_deg" -> "peak-to-peak [deg]".
std::string coef_axis_label(const std::string& coef);

// A labelled angle-error result (one mounting case).
struct EpsCase {
  std::string label;             // legend entry (enhanced text)
  const AngleErrorResult* result;
};
PlotPanel eps_panel(const std::string& title, const std::vector<EpsCase>& cases);

// A labelled spectrum (one mounting case).
struct SpectrumCase {
  std::string label;
  Spectrum spectrum;
};
// Bars of |a0| (at x = 0, when include_dc) and c1..c8 per case, side by side.
// logy: logarithmic amplitude axis (bars below min_deg are clipped).
PlotPanel harmonics_panel(const std::string& title, const std::vector<SpectrumCase>& cases,
                          bool include_dc = true, bool logy = false, double min_deg = 1e-4);

// A labelled sweep for coefficient plots.
struct SweepCase {
  std::string label;
  const SweepResult* sweep;
};
// One panel per coefficient; each sweep drawn as points (computed) and a line
// (its cubic fit from fits, if present). xlabel names the swept offset. A
// panel whose values are all below kRoundingZeroDeg (study_output.hpp) in
// magnitude is drawn on a fixed [-1, 1] axis and labelled as zero up to rounding.
PlotSpec coefficient_figure(const std::string& title, const std::string& xlabel,
                            const std::vector<SweepCase>& sweeps, const std::vector<FitRow>& fits,
                            const std::vector<std::string>& coefs, int columns = 3);

// A labelled pair of sweeps (FEM source and exact field, same spec).
struct DifferenceCase {
  std::string label;          // legend entry (enhanced text)
  const SweepResult* value;   // on the FEM source
  const SweepResult* exact;   // on the exact field
};
// One panel per coefficient: value - exact (deg) vs the swept offset.
PlotSpec difference_figure(const std::string& title, const std::string& xlabel,
                           const std::vector<DifferenceCase>& cases, const std::vector<std::string>& coefs,
                           int columns = 2);

}  // namespace magenc
