// Mounting tolerances: a box of allowed offsets, its corners, a seeded Monte
// Carlo sampler and order statistics.
//
// A tolerance box allows |sx| <= tol.sx_mm, |sy| <= tol.sy_mm, |dx| <= tol.dx_mm,
// |dy| <= tol.dy_mm, |dz| <= tol.dz_mm (half-widths, mm, >= 0; the offsets are
// those of mounting.hpp), and the tilts of physics.md "Beyond the five
// offsets": sensor tilts |tilt_x|, |tilt_y| <= tol.tilt_x_deg, tol.tilt_y_deg
// and a magnet lean whose two components (toward +x and toward +y of the
// rotor frame: magnet_tilt_deg * (cos psi, sin psi) with psi the tilt azimuth)
// each lie in +-tol.magnet_tilt_deg (so the magnet tilt itself reaches
// sqrt(2) * tol.magnet_tilt_deg at the corners). Monte Carlo samples are
// uniform in the box (in the lean components for the magnet tilt). The tilt
// half-widths default to 0 here (the five-offset box); the radius study's
// configuration sets them (radius.tol_tilt_*).
//
// Reproducibility: sample i is a pure function of (seed, i) (a counter-based
// generator: SplitMix64 of seed and index), so a run gives bit-identical
// samples and results for any OpenMP thread count and scheduling, and the
// same sample i is used at every probe radius and array (common random
// numbers: differences between radii are not blurred by sampling noise).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "probe/mounting.hpp"

namespace magenc {

struct ToleranceBox {
  double sx_mm = 0.1;  // half-width of static eccentricity x (sensor off axis), mm
  double sy_mm = 0.1;  // half-width of static eccentricity y, mm
  double dx_mm = 0.1;  // half-width of dynamic eccentricity x (magnet off axis), mm
  double dy_mm = 0.1;  // half-width of dynamic eccentricity y, mm
  double dz_mm = 0.2;  // half-width of the air-gap offset, mm
  double tilt_x_deg = 0;      // half-width of the sensor tilt about x, deg
  double tilt_y_deg = 0;      // half-width of the sensor tilt about y, deg
  double magnet_tilt_deg = 0; // half-width of each magnet lean component (toward x, toward y), deg

  // Throws InputError naming `prefix`+"sx_mm" etc. for a negative or
  // non-finite half-width (allowed [0, 10] mm; tilts [0, 10] deg).
  void validate(const std::string& prefix = "tolerance.") const;
  // The box corners (every offset and tilt component at +-half-width), up to
  // 2^9 = 512 of them, fewer when half-widths are 0 (duplicates dropped; with
  // no tilts the 32 five-offset corners as before). Order: bit b of the
  // corner index selects the sign of b (sx, sy, dx, dy, dz, tilt_x, tilt_y,
  // lean x, lean y), + first.
  std::vector<Mount> corners() const;
  // Monte Carlo sample `index` (uniform in the box) for `seed`. The five
  // offsets are the first five draws of the sample's stream, the tilts the
  // next four, so a box without tilts gives exactly the five-offset samples.
  Mount sample(std::uint64_t seed, std::uint64_t index) const;
  bool has_tilts() const { return tilt_x_deg > 0 || tilt_y_deg > 0 || magnet_tilt_deg > 0; }
  // The same box with only the named group's half-widths kept (the others 0):
  // "static" (sx, sy), "dynamic" (dx, dy), "air gap" (dz), "sensor tilt"
  // (tilt_x, tilt_y), "magnet tilt". InputError for another name.
  ToleranceBox only(const std::string& group) const;
  static const std::vector<std::string>& groups();
  // Largest in-plane displacement of a probe from its nominal path over the
  // box: |s| + |d| at a corner (mm).
  double max_inplane_mm() const;
};

// SplitMix64 step (public for tests): a bijective 64-bit mixer.
std::uint64_t splitmix64(std::uint64_t x);

// Evaluates f(i, cases[i], out) for every case in parallel (OpenMP); f writes
// n_out values to out and must be thread-safe. Returns cases.size() x n_out.
// The first exception thrown by f is rethrown.
using CaseFunction = std::function<void(std::size_t i, const Mount& m, double* out)>;
Eigen::MatrixXd evaluate_cases(const std::vector<Mount>& cases, int n_out, const CaseFunction& f);

// Samples 0..n-1 of the box for `seed` (n >= 1, else InputError).
std::vector<Mount> monte_carlo_samples(const ToleranceBox& box, long n, std::uint64_t seed);

// Percentile p in [0, 100] of values by linear interpolation between order
// statistics (the "type 7" definition: position p/100*(n-1) in sorted order).
// InputError for no values or p outside [0, 100].
double percentile(std::vector<double> values, double p);

struct SampleStats {
  long n = 0;          // number of values
  double mean = 0;     // arithmetic mean
  double p95 = 0;      // 95th percentile (type 7)
  double p99 = 0;      // 99th percentile (type 7)
  double max = 0;      // largest value
};
SampleStats sample_stats(const Eigen::Ref<const Eigen::VectorXd>& values);

// Largest value of column `col` of `values` (rows = cases) and its row.
struct WorstCase {
  double value = 0;    // the largest value
  std::size_t row = 0; // row (case index) where it occurs (first one on ties)
};
WorstCase worst_case(const Eigen::MatrixXd& values, int col);

// Compact sign text of a corner, e.g. "sx+ sy- dx+ dy+ dz-" (0 half-widths show "0");
// tilted corners append "tx+ ty-" and the magnet lean "gx+ gy-".
std::string corner_text(const Mount& m);

}  // namespace magenc
