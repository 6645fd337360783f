// A measured angle-error curve (docs/interfaces.md, "Measured error curves and diagnose"): a reference encoder's
// rotor angle theta and what the sensor under test reported, read from a CSV file with a header row:
//   theta_deg,error_deg      error = sensor - reference (error_sign = +1) or reference - sensor (-1)
//   theta_deg,phi_deg        the sensor's angle phi; error = wrap(phi - theta)
//   theta_deg,u_cos,u_sin    raw channels (any units); error = wrap(atan2(u_sin, u_cos) - theta)
// Read as spreadsheet programs write CSV (core/text_table.hpp): ',' or ';' (with decimal commas), tab or blank
// separated, a UTF-8 byte-order mark, CRLF or CR line ends; blank lines and lines starting with '#' are
// skipped; spaces around cells are allowed.
// Samples need not be uniform; several turns are folded into [0, 360). The reader's file is attack
// surface: every rejection is an InputError of one line naming the file, the row (1-based line number)
// and the problem.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "probe/spectrum.hpp"

namespace magenc {

// Reader limits (stated in --help and in errors).
struct CurveReadOptions {
  int error_sign = +1;          // theta_deg,error_deg only: +1 error = sensor - reference, -1 the opposite
  int min_points = 64;          // fewer rows are refused
  double max_gap_deg = 30.0;    // largest gap between folded samples (circularly) allowed
};

// One gap between neighbouring folded samples larger than the reporting threshold.
struct CurveGap {
  double from_deg, to_deg;  // folded angles on either side (to may be < from across 0/360)
  double width_deg;
};

struct MeasuredCurve {
  std::string path;              // file it came from
  std::string format;            // "error_deg", "phi_deg" or "raw"
  Eigen::VectorXd theta_deg;     // folded into [0, 360), sorted ascending
  Eigen::VectorXd error_deg;     // eps = wrap(sensor - reference), same order
  Eigen::VectorXi row;           // 1-based line of each sample in the file
  Eigen::MatrixXd channels;      // raw format: the channels (u_cos, u_sin) of each sample, same order; else empty
  double raw_span_deg = 0;       // max - min of the unfolded theta
  double turns = 0;              // raw span / 360 (fractional)
  double median_step_deg = 0;    // median spacing of the folded samples
  double largest_gap_deg = 0;    // largest circular gap of the folded samples
  std::vector<CurveGap> gaps;    // gaps wider than max(5 * median step, 2 deg), widest first
  int duplicates = 0;            // rows repeating an earlier theta with the same value (kept)
  std::size_t size() const { return static_cast<std::size_t>(theta_deg.size()); }
};

// Reads and checks a curve file. Throws InputError naming the file and row for: unreadable file, missing
// or unknown header columns, non-numeric cells, wrong cell count, NaN/inf, raw channels both zero, the
// same theta twice with different values, fewer than min_points rows, less than a turn
// (raw span + the largest gap's share < 360, i.e. the wrap-around gap alone exceeds max_gap_deg), or a
// gap wider than max_gap_deg.
MeasuredCurve read_measured_curve(const std::string& path, const CurveReadOptions& opts = {});

// The same checks on in-memory text (tests; origin is used as the file name in messages).
MeasuredCurve parse_measured_curve(const std::string& text, const std::string& origin,
                                   const CurveReadOptions& opts = {});

// harmonics_ls (least-squares harmonics of a measured curve) is declared in probe/spectrum.hpp.

}  // namespace magenc
