// diagnose's outputs (docs/interfaces.md, "Measured error curves and diagnose"), written into one directory:
//   fit.json     parameters {json_name: {value, sigma, free, unit, identifiable}}, residual_rms_deg,
//                not_identifiable, confounded (plain words), correlation, singular values, curves (their
//                facts, residual RMS, harmonics measured / fitted / residual), starts, run metadata
//   fit.csv      curve,theta_deg,measured_deg,fitted_deg,residual_deg,row  (one line per sample)
//   summary.md   the same for a person, with the plots
//   fit.png      per curve: measured (points) and fitted (line) error, the residual below
//   harmonics.png per curve: |a0|, c1..c8 of measured, fitted and residual (least squares on the samples)
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/diagnosis_fit.hpp"
#include "probe/spectrum.hpp"
#include "report/study_output.hpp"

namespace magenc {

struct DiagnosisRunInfo {
  std::string program = "diagnose";
  std::string command_line;
  std::string field_spec;      // --field as given
  std::string config_json;     // Config::to_json() of the values used
  std::string config_toml;     // Config::to_toml()
  std::vector<std::string> curve_sets;  // --curve-set texts
  DiagnosisOptions options;
  double wall_s = 0;
};

std::string diagnosis_json(const std::vector<CurveInput>& curves, const DiagnosisResult& res,
                           const DiagnosisRunInfo& info);
std::string diagnosis_csv(const std::vector<CurveInput>& curves, const DiagnosisResult& res);
std::string diagnosis_summary(const std::vector<CurveInput>& curves, const DiagnosisResult& res,
                              const DiagnosisRunInfo& info);
// Writes fit.png and harmonics.png (and their .gp/.dat) into dir.
void write_diagnosis_plots(const std::filesystem::path& dir, const std::vector<CurveInput>& curves,
                           const DiagnosisResult& res);
// Everything above into dir (which must exist; diagnose passes an AtomicDir's temporary path).
void write_diagnosis_outputs(const std::filesystem::path& dir, const std::vector<CurveInput>& curves,
                             const DiagnosisResult& res, const DiagnosisRunInfo& info);

}  // namespace magenc
