// Correction files (docs/interfaces.md "calibrate"): the correction a firmware applies, as CSV and JSON.
// CSV, one row per constant under the header `quantity,index,value`:
//   method,0,lut:32            the method (none | harmonics:N | lut:K | ogp)
//   turns,0,1                  channel-angle turns per mechanical turn (2 for amr: the tables are in 2 phi)
//   lut_deg,k,v                lut:K: e at psi_k = 360 k/K, k = 0..K-1 (all K rows)
//   a_deg,n,v  b_deg,n,v       harmonics:N: e(psi) = a_0 + sum a_n cos n psi + b_n sin n psi (a_0..a_N, b_1..b_N)
//   offset_cos,0,v  offset_sin,0,v  gain_ratio,0,v  phase_deg,0,v     ogp: the channel ellipse
// The corrected angle is psi' = psi - e(psi) (harmonics, lut) or the ellipse's inverse before atan2 (ogp).
// Numbers are written with 17 significant digits, so a file read back gives the same correction.
#pragma once
#include <string>

#include "analysis/calibration.hpp"

namespace magenc {

std::string correction_csv(const Correction& c);
std::string correction_json(const Correction& c);

// Reads a correction CSV (core/text_table rules: separators, BOM, CRLF, '#' comments). InputError of one
// line naming `origin`, the row and the problem: header other than quantity,index,value, an unknown
// quantity, a bad or repeated index, a non-finite value, a constant missing for the method or of another
// method, turns other than 1 or 2, an angle (lut_deg, a_deg, b_deg, phase_deg) beyond +-360 deg, an
// ellipse constant beyond +-1e6, a gain ratio <= 0, |phase| >= 90 deg.
Correction parse_correction_csv(const std::string& text, const std::string& origin);
Correction read_correction_csv(const std::string& path);

}  // namespace magenc
