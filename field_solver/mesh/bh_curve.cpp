#include "field_solver/mesh/bh_curve.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/text_table.hpp"

namespace magenc::fem {
namespace {

constexpr std::size_t kMinRows = 4;
// Plausibility of a soft-magnetic material (a curve in other units than its header claims fails these):
// the polarization B - mu0 H stays below 3 T (the highest of any soft-magnetic material, Fe-Co, is
// 2.45 T; B in mT under B_T gives hundreds of tesla), and the relative permeability, secant B / (mu0 H)
// and of every segment, stays below 1e6 (Supermalloy's maximum is about 1e6; H in kA/m or Oe under
// H_A_per_m gives 80 to 1000 times the true permeability; a near-duplicate H an unbounded slope).
constexpr double kMaxPolarization_T = 3.0;
constexpr double kMaxRelativePermeability = 1e6;

// Fritsch-Carlson slopes at the rows of a strictly increasing table (monotone cubic Hermite).
std::vector<double> pchip_slopes(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  std::vector<double> h(n - 1), d(n - 1), m(n, 0.0);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = x[i + 1] - x[i];
    d[i] = (y[i + 1] - y[i]) / h[i];
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    // Weighted harmonic mean of the neighbouring secants (all > 0 here).
    const double w1 = 2 * h[i] + h[i - 1], w2 = h[i] + 2 * h[i - 1];
    m[i] = (w1 + w2) / (w1 / d[i - 1] + w2 / d[i]);
  }
  // End slopes: the three-point formula, kept within [0, 3 d] (monotone).
  auto end = [](double h0, double h1, double d0, double d1) {
    double s = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
    if (s < 0) s = 0;
    if (s > 3 * d0) s = 3 * d0;
    return s;
  };
  // At the origin (the first row is (0, 0)) at least mu0: a measured curve whose first rows are still in the
  // convex (Rayleigh) start gives a three-point slope <= 0, and B would fall below mu0 H near H = 0.
  // There the first segment's secant B_1 / H_1 (>= mu0, the curve's own average initial permeability) stands in:
  // end slope d0 and interior slopes <= 3 min(d) keep the cubic monotone (de Boor-Swartz box [0, 3]^2), and a
  // steep start (0,0 / 100,0.1 / 110,0.2 ...) does not turn the material into air near H = 0.
  const double m0 = end(h[0], h[1], d[0], d[1]);
  m[0] = m0 >= kMu0_T_m_per_A ? m0 : d[0];
  m[n - 1] = end(h[n - 2], h[n - 3], d[n - 2], d[n - 3]);
  return m;
}


// The likely unit of B when the polarization exceeds 3 T: the curve's largest B read as kG, mT or G would be
// 0.3-5 T, 0.05-5 T, 0.5-... T.
std::string likely_b_unit(double b_max) {
  if (b_max <= 50) return "B in kG (1 kG = 0.1 T) under a B_T header?";
  if (b_max <= 5000) return "B in mT under a B_T header?";
  return "B in G (1 G = 1e-4 T) under a B_T header?";
}

// The H at which the polarization B - mu0 H first reaches J_T (linear between rows), or -1.
double h_at_polarization(const std::vector<double>& H, const std::vector<double>& B, double J_T) {
  for (std::size_t i = 1; i < H.size(); ++i) {
    const double j0 = B[i - 1] - kMu0_T_m_per_A * H[i - 1], j1 = B[i] - kMu0_T_m_per_A * H[i];
    if (j1 >= J_T) return j1 > j0 ? H[i - 1] + (J_T - j0) / (j1 - j0) * (H[i] - H[i - 1]) : H[i];
  }
  return -1;
}

// The likely unit of H of a curve whose permeability is too large (mu_r the largest secant). Steels reach
// 1.7 T at 1.5-20 kA/m (the curves of materials/: 4.4-6.8 kA/m), so read as Oe at 19-250, as kA/m or mT of
// mu0 H at 1.5-25: a curve reaching 1.7 T below 20 of its units is likely kA/m, above it Oe.
std::string likely_h_unit(const std::vector<double>& H, const std::vector<double>& B, double mu_r) {
  constexpr double kOe_A_per_m = 1e3 / (4 * 3.14159265358979323846);  // 79.577 A/m
  const double h17 = h_at_polarization(H, B, kBhIronPolarization_T);
  auto as = [&](const std::string& unit, double factor) {
    return "H likely in " + unit + ": x " + num(factor) + " gives a relative permeability of " + num(mu_r / factor) +
           (h17 > 0 ? " and 1.7 T at " + num(h17 * factor) + " A/m" : "");
  };
  if (h17 > 0) return h17 < 20 ? as("kA/m (or mT of mu0 H, x 795.8)", 1000) : as("Oe (or A/cm, x 100)", kOe_A_per_m);
  return "H in Oe (relative permeability then " + num(mu_r / kOe_A_per_m) + ") or kA/m (" + num(mu_r / 1000) +
         ") under an H_A_per_m header?";
}

}  // namespace

BhCurve::BhCurve(std::vector<double> H, std::vector<double> B, const std::string& where, double iron_max_mu_r)
    : H_(std::move(H)), B_(std::move(B)) {
  const std::string allowed = "allowed rows H_A_per_m,B_T starting at 0,0, both strictly increasing, at least " +
                              std::to_string(kMinRows) + " rows, B >= mu0 H";
  if (H_.size() != B_.size()) throw InputError(where + ": H and B columns differ in length: " + allowed);
  if (H_.size() < kMinRows)
    throw InputError(where + ": " + std::to_string(H_.size()) + " rows are too few: " + allowed);
  for (std::size_t i = 0; i < H_.size(); ++i)
    if (!std::isfinite(H_[i]) || !std::isfinite(B_[i]))
      throw InputError(where + ": row " + std::to_string(i + 1) + " is not finite: " + allowed);
  if (H_[0] != 0.0 || B_[0] != 0.0)
    throw InputError(where + ": the first row is (" + num(H_[0]) + ", " + num(B_[0]) + "), not (0, 0): " + allowed);
  for (std::size_t i = 1; i < H_.size(); ++i) {
    if (!(H_[i] > H_[i - 1]) || !(B_[i] > B_[i - 1]))
      throw InputError(where + ": row " + std::to_string(i + 1) + " (H " + num(H_[i]) + " A/m, B " + num(B_[i]) +
                       " T) does not increase over the row before: " + allowed);
    if (B_[i] < kMu0_T_m_per_A * H_[i] * (1 - 1e-12))
      throw InputError(where + ": row " + std::to_string(i + 1) + " has B " + num(B_[i]) + " T < mu0 H = " +
                       num(kMu0_T_m_per_A * H_[i]) + " T (relative permeability below 1): " + allowed);
    check_plausible_row(i, where);
  }
  check_iron_permeability(where, iron_max_mu_r);
  check_segments(where);
  slope_ = pchip_slopes(H_, B_);
}

void BhCurve::check_plausible_row(std::size_t i, const std::string& where) const {
  const std::string row = where + ": row " + std::to_string(i + 1) + " (H " + num(H_[i]) + " A/m, B " + num(B_[i]) + " T)";
  const double J = B_[i] - kMu0_T_m_per_A * H_[i];
  if (J > kMaxPolarization_T)
    throw InputError(row + " has a polarization B - mu0 H of " + num(J) + " T: allowed at most " +
                     num(kMaxPolarization_T) + " T (soft iron saturates below 2.5 T; " +
                     likely_b_unit(*std::max_element(B_.begin(), B_.end())) + ")");
  const double secant = B_[i] / (kMu0_T_m_per_A * H_[i]);
  if (secant > kMaxRelativePermeability)
    throw InputError(row + " gives a relative permeability of " + num(secant) + ": allowed at most " +
                     num(kMaxRelativePermeability) + " (" + likely_h_unit(H_, B_, secant) + ")");
}

void BhCurve::check_segments(const std::string& where) const {
  for (std::size_t i = 1; i < H_.size(); ++i) {
    const double segment = (B_[i] - B_[i - 1]) / (kMu0_T_m_per_A * (H_[i] - H_[i - 1]));
    if (segment > kMaxRelativePermeability)
      throw InputError(where + ": row " + std::to_string(i + 1) + " (H " + num(H_[i]) + " A/m, B " + num(B_[i]) +
                       " T) gives a relative permeability of " + num(segment) +
                       " over the segment from the row before: allowed at most " + num(kMaxRelativePermeability) +
                       " (two rows of nearly the same H?)");
  }
}

void BhCurve::check_iron_permeability(const std::string& where, double iron_max_mu_r) const {
  if (h_at_polarization(H_, B_, kBhIronPolarization_T) < 0) return;  // not iron or steel (or not saturated)
  std::size_t worst = 1;
  for (std::size_t i = 1; i < H_.size(); ++i)
    if (B_[i] / H_[i] > B_[worst] / H_[worst]) worst = i;
  const double mu = B_[worst] / (kMu0_T_m_per_A * H_[worst]);
  if (mu > iron_max_mu_r)
    throw InputError(where + ": row " + std::to_string(worst + 1) + " (H " + num(H_[worst]) + " A/m, B " +
                     num(B_[worst]) + " T) gives a relative permeability of " + num(mu) +
                     " on a curve reaching a polarization of 1.7 T (iron or steel): allowed at most " +
                     num(iron_max_mu_r) + " (fem.bh_iron_max_mu_r; " + likely_h_unit(H_, B_, mu) + ")");
}

double BhCurve::B_T(double H) const {
  if (H < 0) return -B_T(-H);
  const std::size_t n = H_.size();
  if (H >= H_[n - 1]) return B_[n - 1] + kMu0_T_m_per_A * (H - H_[n - 1]);
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(H_.begin(), H_.end(), H) - H_.begin()) - 1;
  const double h = H_[i + 1] - H_[i], t = (H - H_[i]) / h;
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * B_[i] + (t3 - 2 * t2 + t) * h * slope_[i] + (-2 * t3 + 3 * t2) * B_[i + 1] +
         (t3 - t2) * h * slope_[i + 1];
}

double BhCurve::dB_dH(double H) const {
  if (H < 0) return dB_dH(-H);
  const std::size_t n = H_.size();
  if (H >= H_[n - 1]) return kMu0_T_m_per_A;
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(H_.begin(), H_.end(), H) - H_.begin()) - 1;
  const double h = H_[i + 1] - H_[i], t = (H - H_[i]) / h;
  const double t2 = t * t;
  return ((6 * t2 - 6 * t) * B_[i] + (3 * t2 - 4 * t + 1) * h * slope_[i] + (-6 * t2 + 6 * t) * B_[i + 1] +
          (3 * t2 - 2 * t) * h * slope_[i + 1]) /
         h;
}

double BhCurve::mu_r(double H) const {
  if (H == 0.0) return slope_[0] / kMu0_T_m_per_A;
  return B_T(H) / (kMu0_T_m_per_A * H);
}

BhCurve parse_bh_csv(const std::string& text, const std::string& where, double iron_max_mu_r) {
  const NumericTable t = parse_numeric_table(text, where, {"H_A_per_m", "B_T"});
  const int ch = t.column("H_A_per_m"), cb = t.column("B_T");
  if (ch < 0 || cb < 0)
    throw InputError(where + ": missing column '" + std::string(ch < 0 ? "H_A_per_m" : "B_T") +
                     "': allowed columns H_A_per_m, B_T");
  std::vector<double> H, B;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    H.push_back(t.at(r, static_cast<std::size_t>(ch)));
    B.push_back(t.at(r, static_cast<std::size_t>(cb)));
  }
  return BhCurve(std::move(H), std::move(B), where, iron_max_mu_r);
}

BhCurve read_bh_csv(const std::filesystem::path& file, double iron_max_mu_r) {
  const std::string where = "B-H curve " + file.string();
  return parse_bh_csv(read_text_file(file, where, std::uintmax_t(1) << 24), where, iron_max_mu_r);
}

}  // namespace magenc::fem
