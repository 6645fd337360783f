// Angle error and its Fourier spectrum (docs/physics.md, the study's convention):
//   eps(theta) = wrap(phi - theta) into (-180, 180] deg, M uniform samples,
//   eps = a0 + sum_{n=1..8} a_n cos(n theta) + b_n sin(n theta),
//   a0 = mean, a_n = (2/M) sum eps cos, b_n = (2/M) sum eps sin,
//   c_n = hypot(a_n, b_n), c_0 = a0; pp = max - min.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace magenc {

inline constexpr int kHarmonics = 8;

struct Spectrum {
  double a0_deg = 0;
  std::array<double, kHarmonics + 1> a_deg{};  // a_deg[n], n = 1..8 (a_deg[0] unused = a0)
  std::array<double, kHarmonics + 1> b_deg{};  // b_deg[n], n = 1..8
  std::array<double, kHarmonics + 1> c_deg{};  // c_deg[n] = hypot(a_n, b_n); c_deg[0] = a0
  double pp_deg = 0;                           // peak-to-peak of eps
  // A multipole read (pole_pairs p > 0, spectrum_of(eps, p)): ce_deg[k - 1] is the amplitude of order k p,
  // k = 1..4 (electrical_harmonics_deg); spectra tables then add ce1_deg..ce4_deg. 0: not a multipole read.
  int pole_pairs = 0;
  std::array<double, 4> ce_deg{};

  // Value of a spectra-table column by name: "a0_deg", "a3_deg", "b2_deg",
  // "c1_deg", "pp_deg"; "ce1_deg".."ce4_deg" of a multipole read. Throws std::invalid_argument for an
  // unknown name.
  double column(const std::string& name) const;
};

// Wrap an angle difference into (-180, 180] degrees.
double wrap_deg(double a_deg);

// Spectrum of eps sampled at theta_m = 2*pi*m/M, m = 0..M-1 (eps in degrees).
Spectrum spectrum_of(const Eigen::VectorXd& eps_deg);
// The same with ce1..ce4 of a multipole read of pole_pairs p (p = 0: as above).
Spectrum spectrum_of(const Eigen::VectorXd& eps_deg, int pole_pairs);

// The columns a multipole read adds to a spectra table: ce1_deg..ce4_deg.
const std::vector<std::string>& electrical_columns();

// The spectra-table coefficient columns in order: a0..a8, b1..b8, c1..c8, pp.
const std::vector<std::string>& spectrum_columns();

// Least-squares harmonics of values sampled at arbitrary angles theta_deg (not necessarily uniform):
// fits v = a0 + sum_{n=1..max_n} a_n cos(n theta) + b_n sin(n theta). Returns (a0, a1, b1, a2, b2, ...)
// as a vector of 1 + 2*max_n values. Throws InputError when there are fewer samples than coefficients.
Eigen::VectorXd harmonics_ls(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& values,
                             int max_n = kHarmonics);

// Amplitude c_n = hypot(a_n, b_n) of harmonic n >= 1 of a harmonics_ls vector h = (a0, a1, b1, ...).
double harmonic_amplitude(const Eigen::VectorXd& h, int n);

// Amplitudes (deg) of the orders p, 2p, 3p, 4p of eps over one turn (uniform samples; orders above M/2
// give 0): ce1..ce4, the interpolation error of a multipole track's pole period (docs/physics.md).
std::array<double, 4> electrical_harmonics_deg(const Eigen::VectorXd& eps_deg, int pole_pairs);

// A Spectrum (a0, a_n, b_n, c_n for n <= kHarmonics; pp = 0) from harmonics_ls coefficients.
Spectrum spectrum_from_ls(const Eigen::VectorXd& h);

}  // namespace magenc
