// CSV tables of docs/interfaces.md: spectra table, fits table, mounting cases.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "probe/mounting.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

// One row of the spectra table.
struct SpectrumRow {
  std::string field;   // "linear", "analytic", "grid", "fem"
  std::string array;   // "two", "diff4", "ring:8"
  double r0_mm = 0;
  Mount mount;
  Spectrum spectrum;
  std::vector<std::pair<std::string, std::string>> extra;  // extra columns (name, text), after the standard ones
};

// Header + rows in the docs/interfaces.md column order (extra columns appended;
// every row must carry the same extra column names).
std::string spectra_csv(const std::vector<SpectrumRow>& rows);

struct FitRow {
  std::string study;  // study name
  std::string swept;  // sx_mm, sy_mm, dx_mm, dy_mm, dz_mm, r0_mm
  std::string coef;   // spectra column, e.g. "c3_deg"
  std::array<double, 4> p;  // p3, p2, p1, p0
  std::vector<std::pair<std::string, std::string>> extra;  // e.g. ("array","two")
};
std::string fits_csv(const std::vector<FitRow>& rows);

// Reads a cases file: header with any of sx_mm,sy_mm,dx_mm,dy_mm,dz_mm and
// tilt_x_deg,tilt_y_deg,magnet_tilt_deg,magnet_tilt_azimuth_deg (missing = 0).
// Read as spreadsheet programs write CSV (core/text_table.hpp: ';' with decimal commas, a byte-order
// mark, CRLF). InputError on malformed CSV, unknown column, NaN, a tilt out of range, no rows.
std::vector<Mount> read_cases_csv(const std::filesystem::path& path);

}  // namespace magenc
