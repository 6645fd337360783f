// Mounting tolerances: a box of allowed offsets, its corners, a seeded Monte
// Carlo sampler and order statistics.
//
// A tolerance box allows |sx| <= tol.sx_mm, |sy| <= tol.sy_mm, |dx| <= tol.dx_mm,
// |dy| <= tol.dy_mm, |dz| <= tol.dz_mm (half-widths, mm, >= 0; the offsets are
// those of mounting.hpp), and the tilts of docs/physics.md "Beyond the five
// offsets": sensor tilts |tilt_x|, |tilt_y| <= tol.tilt_x_deg, tol.tilt_y_deg
// and a magnet lean whose two components (toward +x and toward +y of the
// rotor frame: magnet_tilt_deg * (cos psi, sin psi) with psi the tilt azimuth)
// each lie in +-tol.magnet_tilt_deg (so the magnet tilt itself reaches
// sqrt(2) * tol.magnet_tilt_deg at the corners). Monte Carlo samples are
// uniform in the box (in the lean components for the magnet tilt). The tilt
// half-widths default to 0 here (the five-offset box); the radius study's
// configuration sets them (radius.tol_tilt_*).
//
// Two more groups, off (0) by default here and in the radius study:
//  * the signal chain of docs/physics.md (channel offsets |oc|, |os| <=
//    tol.offset_cos_mT, tol.offset_sin_mT; gain mismatch |g| <=
//    tol.gain_mismatch; phase error |delta| <= tol.phase_error_deg), applied to
//    the array's channels before atan2 (probe/signal_chain.hpp);
//  * the magnetization elevation: |al - al0| <= tol.magnetization_elevation_deg
//    about the magnet's configured elevation al0 (a property of the field, so a
//    ToleranceCase carries the deviation; only fields that can change their
//    magnetization serve it, see radius_scan.hpp).
// A ToleranceCase is one point of the whole box: the Mount plus the chain and
// the elevation deviation; sample()/corners() give the Mount part alone.
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

#include "core/config.hpp"
#include "probe/environment.hpp"
#include "probe/mounting.hpp"
#include "probe/signal_chain.hpp"

namespace magenc {

// One point of a tolerance box: a mount, a signal chain and an elevation deviation.
struct ToleranceCase {
  Mount mount;
  SignalChain chain;          // ideal unless the box has a signal chain
  double elevation_deg = 0;   // magnetization elevation minus the magnet's configured one, deg
  Environment env{};          // temperature and stray field (neutral unless the box draws them)
};

struct ToleranceBox {
  double sx_mm = 0.1;  // half-width of static eccentricity x (sensor off axis), mm
  double sy_mm = 0.1;  // half-width of static eccentricity y, mm
  double dx_mm = 0.1;  // half-width of dynamic eccentricity x (magnet off axis), mm
  double dy_mm = 0.1;  // half-width of dynamic eccentricity y, mm
  double dz_mm = 0.2;  // half-width of the air-gap offset, mm
  double tilt_x_deg = 0;      // half-width of the sensor tilt about x, deg
  double tilt_y_deg = 0;      // half-width of the sensor tilt about y, deg
  double magnet_tilt_deg = 0; // half-width of each magnet lean component (toward x, toward y), deg
  double offset_cos_mT = 0;   // half-width of the cos channel offset oc, mT
  double offset_sin_mT = 0;   // half-width of the sin channel offset os, mT
  double gain_mismatch = 0;   // half-width of the gain mismatch g (1 = 100 %)
  double phase_error_deg = 0; // half-width of the phase error delta, deg
  double magnetization_elevation_deg = 0;  // half-width of the elevation deviation, deg
  // The environment (off by default): a temperature uniform in [temperature_min_C, temperature_max_C]
  // and a homogeneous stray field (fixed frame) of magnitude uniform in [0, stray_mT] and a direction
  // uniform on the sphere. Each case's Environment is env_coefficients (Br coefficient, offset and
  // air-gap drifts) with the drawn temperature and stray field. Corners do not include it.
  double temperature_min_C = kReferenceTemperature_C, temperature_max_C = kReferenceTemperature_C;
  double stray_mT = 0;
  Environment env_coefficients{};

  // Throws InputError naming `prefix`+"sx_mm" etc. for a negative or
  // non-finite half-width (allowed [0, 10] mm; tilts [0, 10] deg; channel
  // offsets [0, 100] mT; gain mismatch [0, 0.5]; phase error [0, 45] deg;
  // elevation [0, 45] deg; temperatures finite in [-273.15, 1000] C with min <= max; stray [0, 1e4] mT).
  void validate(const std::string& prefix = "tolerance.") const;
  // The box corners (every component at +-half-width), up to 2^14 of them,
  // fewer when half-widths are 0 (duplicates dropped; with no tilts, chain or
  // elevation the 32 five-offset corners as before). Order: bit b of the
  // corner index selects the sign of b (sx, sy, dx, dy, dz, tilt_x, tilt_y,
  // lean x, lean y, oc, os, g, delta, elevation), + first; so the corners of a
  // box without chain and elevation are those of the nine mounting axes.
  std::vector<ToleranceCase> case_corners() const;
  // The Mount part of the corners of the nine mounting axes (chain and elevation ignored).
  std::vector<Mount> corners() const;
  // Monte Carlo sample `index` (uniform in the box) for `seed`. The stream's
  // draws have fixed places: the five offsets first, then the four tilt
  // components, then the four chain components, then the elevation; the
  // stream stops after the last group the box has (then four environment draws: temperature, stray
  // magnitude, cos of its polar angle, its azimuth; so a box without tilts,
  // chain and elevation gives exactly the five-offset samples, and a box
  // without chain and elevation exactly the samples it gave before those
  // axes existed). A group's values do not depend on which other groups are
  // in the box (common random numbers for the budget).
  ToleranceCase case_sample(std::uint64_t seed, std::uint64_t index) const;
  // The Mount part of case_sample().
  Mount sample(std::uint64_t seed, std::uint64_t index) const { return case_sample(seed, index).mount; }
  bool has_tilts() const { return tilt_x_deg > 0 || tilt_y_deg > 0 || magnet_tilt_deg > 0; }
  bool has_chain() const { return offset_cos_mT > 0 || offset_sin_mT > 0 || gain_mismatch > 0 || phase_error_deg > 0; }
  bool has_elevation() const { return magnetization_elevation_deg > 0; }
  bool has_environment() const {
    return temperature_min_C != kReferenceTemperature_C || temperature_max_C != kReferenceTemperature_C || stray_mT > 0;
  }
  // Every half-width is 0.
  bool empty() const {
    return max_inplane_mm() == 0 && dz_mm == 0 && !has_tilts() && !has_chain() && !has_elevation() && !has_environment();
  }
  // The same box with only the named group's half-widths kept (the others 0):
  // "static" (sx, sy), "dynamic" (dx, dy), "air gap" (dz), "sensor tilt"
  // (tilt_x, tilt_y), "magnet tilt", "signal chain" (oc, os, g, delta),
  // "magnetization elevation". InputError for another name.
  ToleranceBox only(const std::string& group) const;
  static const std::vector<std::string>& groups();
  // Largest in-plane displacement of a probe from its nominal path over the
  // box: |s| + |d| at a corner (mm).
  double max_inplane_mm() const;
};

// A study's mounting box in `tol.` keys: tol.sx_mm, sy_mm, dx_mm, dy_mm, dz_mm, tilt_x_deg, tilt_y_deg and, with
// magnet_tilt, tol.magnet_tilt_deg; defaults from `d`, each help text "<what> half-width of ...".
std::vector<KeySpec> mount_box_keys(const ToleranceBox& d, bool magnet_tilt, const std::string& what);
// The box those keys give (every other half-width 0), validated with the prefix "tol.".
ToleranceBox mount_box_from_config(const Config& cfg, bool magnet_tilt);

// SplitMix64 step (public for tests): a bijective 64-bit mixer.
std::uint64_t splitmix64(std::uint64_t x);

// Evaluates f(i, cases[i], out) for every case in parallel (OpenMP); f writes
// n_out values to out and must be thread-safe. Returns cases.size() x n_out.
// The first exception thrown by f is rethrown.
using CaseFunction = std::function<void(std::size_t i, const Mount& m, double* out)>;
Eigen::MatrixXd evaluate_cases(const std::vector<Mount>& cases, int n_out, const CaseFunction& f);
using ToleranceCaseFunction = std::function<void(std::size_t i, const ToleranceCase& c, double* out)>;
Eigen::MatrixXd evaluate_cases(const std::vector<ToleranceCase>& cases, int n_out, const ToleranceCaseFunction& f);

// Samples 0..n-1 of the box for `seed` (n >= 1, else InputError).
std::vector<Mount> monte_carlo_samples(const ToleranceBox& box, long n, std::uint64_t seed);
std::vector<ToleranceCase> monte_carlo_cases(const ToleranceBox& box, long n, std::uint64_t seed);

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
// Values within kWorstCaseTieRelative (relative) of each other are ties and the
// first row wins: mirror-image corners differ only by round-off, and the corner
// reported must not depend on it.
constexpr double kWorstCaseTieRelative = 1e-9;
struct WorstCase {
  double value = 0;    // the largest value (of the first row among ties)
  std::size_t row = 0; // row (case index) where it occurs (first one on ties)
};
// True when `candidate` exceeds `current` by more than the tie tolerance.
bool clearly_larger(double candidate, double current);
WorstCase worst_case(const Eigen::MatrixXd& values, int col);

// Compact sign text of a corner, e.g. "sx+ sy- dx+ dy+ dz-" (0 half-widths show "0");
// tilted corners append "tx+ ty-" and the magnet lean "gx+ gy-".
std::string corner_text(const Mount& m);
// The same for a whole case: a non-ideal chain appends "oc+ os- g+ ph-", an
// elevation deviation "el+" / "el-".
std::string corner_text(const ToleranceCase& c);

}  // namespace magenc
