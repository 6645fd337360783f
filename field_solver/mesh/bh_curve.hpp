// B-H curve of a soft-magnetic material (a table file, `bh:FILE.csv` of a
// part's material; docs/interfaces.md). CSV with the header H_A_per_m,B_T
// (through core/text_table.hpp: comments, ';' and decimal commas, CRLF),
// rows starting at (0, 0), H and B strictly increasing, at least 4 rows,
// B >= mu0 H (relative permeability >= 1) at every row; plausible for a soft-magnetic material (units as
// the header says): polarization B - mu0 H at most 3 T, relative permeability (secant and of every segment)
// at most 1e6 (any material); a curve whose polarization reaches 1.7 T (iron, steels, Fe-Si, Fe-Co: no
// nickel alloy or amorphous metal gets there) has a secant relative permeability of at most iron_max_mu_r
// (default kBhIronMaxMuR, the key fem.bh_iron_max_mu_r); each refusal names the row and the likely unit.
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

// Unit plausibility of a curve whose polarization B - mu0 H reaches kBhIronPolarization_T: its secant relative
// permeability at most kBhIronMaxMuR by default. Isotropic irons and steels stay below it (hot-rolled low-carbon
// steel 2,900, M400-50A 6,100, annealed pure iron up to about 40,000, Fe-Co about 20,000); the same curves
// with H in Oe or A/cm (80-100 times the permeability), kA/m or mT of mu0 H (800-1000 times) exceed it.
// Grain-oriented Fe-Si along its rolling direction (up to about 1e5) or hydrogen-annealed iron: raise
// fem.bh_iron_max_mu_r (up to the 1e6 every curve is held to).
inline constexpr double kBhIronPolarization_T = 1.7;
inline constexpr double kBhIronMaxMuR = 5e4;

class BhCurve {
 public:
  // Checked rows (InputError "WHERE ...: ... allowed ..." otherwise).
  BhCurve(std::vector<double> H_A_per_m, std::vector<double> B_T, const std::string& where,
          double iron_max_mu_r = kBhIronMaxMuR);

  double B_T(double H_A_per_m) const;
  double dB_dH(double H_A_per_m) const;  // T m / A
  // Relative secant permeability B / (mu0 H) (the initial slope / mu0 at H = 0).
  double mu_r(double H_A_per_m) const;

  const std::vector<double>& H() const { return H_; }
  const std::vector<double>& B() const { return B_; }

 private:
  void check_plausible_row(std::size_t i, const std::string& where) const;
  void check_iron_permeability(const std::string& where, double iron_max_mu_r) const;
  void check_segments(const std::string& where) const;
  std::vector<double> H_, B_, slope_;  // rows and PCHIP slopes dB/dH at them
};

// Parses CSV text (where names it in messages).
BhCurve parse_bh_csv(const std::string& text, const std::string& where, double iron_max_mu_r = kBhIronMaxMuR);
// Reads FILE (messages: "B-H curve FILE ...").
BhCurve read_bh_csv(const std::filesystem::path& file, double iron_max_mu_r = kBhIronMaxMuR);

}  // namespace magenc::fem
