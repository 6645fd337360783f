// inspect's outputs (docs/interfaces.md "inspect"): fit.json, fit.csv (measured, fitted and residual components
// per reading), summary.md, components.png (measured vs fitted Bx, By, Bz along the scan).
#pragma once
#include <filesystem>
#include <string>

#include "analysis/inspect_fit.hpp"

namespace magenc {

struct InspectRunInfo {
  std::string command_line;
  std::string scan_file;
  std::string unit;          // "mT" or "T": the scan's field columns
  std::string config_json;   // Config::to_json() of the values used
  std::string config_toml;
};

// fit.json: parameters {name: {value, sigma (null = not identifiable), free, unit, identifiable}},
// residual_rms_mT, not_identifiable, free, correlation {names, matrix}, singular values, condition number,
// n_readings, iterations, config.
std::string inspect_json(const FieldScan& scan, const InspectResult& res, const InspectRunInfo& info);
std::string inspect_csv(const FieldScan& scan, const InspectResult& res);
std::string inspect_summary(const FieldScan& scan, const InspectResult& res, const InspectRunInfo& info);
// Everything above into dir (an AtomicDir's temporary path), plus config.toml.
void write_inspect_outputs(const std::filesystem::path& dir, const FieldScan& scan, const InspectResult& res,
                           const InspectRunInfo& info);

}  // namespace magenc
