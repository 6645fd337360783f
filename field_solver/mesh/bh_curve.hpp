// B-H curve of a soft-magnetic material (a table file, `bh:FILE.csv` of a
// part's material; docs/interfaces.md). CSV with the header H_A_per_m,B_T
// (through core/text_table.hpp: comments, ';' and decimal commas, CRLF),
// rows starting at (0, 0), H and B strictly increasing, at least 4 rows,
// B >= mu0 H (relative permeability >= 1) at every row; plausible for a soft-magnetic material (units as
// the header says): polarization B - mu0 H at most 3 T, relative permeability (secant and of every segment)
// at most 1e6; each refusal names the row.
//
// Interpolation: monotone piecewise cubic Hermite (Fritsch-Carlson / PCHIP
// slopes), so B(H) is monotone and C1 between the rows and never overshoots;
// the slope at the origin is the three-point end formula, or, where that falls
// below mu0 (a table starting convex, as measured curves below their permeability
// maximum do, or a steep start), the first segment's secant B_1 / H_1;
// beyond the last row B = B_n + mu0 (H - H_n) (saturated iron: dB/dH = mu0).
// H < 0: B(-H) = -B(H) (no hysteresis). Units: H in A/m, B in T.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace magenc::fem {

inline constexpr double kMu0_T_m_per_A = 1.25663706212e-6;  // vacuum permeability (T m / A)

class BhCurve {
 public:
  // Checked rows (InputError "WHERE ...: ... allowed ..." otherwise).
  BhCurve(std::vector<double> H_A_per_m, std::vector<double> B_T, const std::string& where);

  double B_T(double H_A_per_m) const;
  double dB_dH(double H_A_per_m) const;  // T m / A
  // Relative secant permeability B / (mu0 H) (the initial slope / mu0 at H = 0).
  double mu_r(double H_A_per_m) const;

  const std::vector<double>& H() const { return H_; }
  const std::vector<double>& B() const { return B_; }

 private:
  void check_plausible_row(std::size_t i, const std::string& where) const;
  std::vector<double> H_, B_, slope_;  // rows and PCHIP slopes dB/dH at them
};

// Parses CSV text (where names it in messages).
BhCurve parse_bh_csv(const std::string& text, const std::string& where);
// Reads FILE (messages: "B-H curve FILE ...").
BhCurve read_bh_csv(const std::filesystem::path& file);

}  // namespace magenc::fem
