// Choosing the probe radius r0: error spectra, tolerance analysis (box
// corners and Monte Carlo) and sensor noise across a range of radii, for
// several probe arrays and field sources.
//
// Why a surrogate, and why it is honest
// -------------------------------------
// The direct pipeline (angle_error.hpp) costs M*K field evaluations per
// mounting case. The scan needs (radii) x (10^4 MC samples + 32 corners +
// 6 spectra cases) cases with M ~ 3600 and up to 8 probes: ~1e10 field
// evaluations, hours for the exact field. Instead, per radius r0:
//  1. CircleFieldModel samples the field on a small 3-D stencil around each
//     of N nodes on the nominal probe circle (node j at angle 2*pi*j/N,
//     radius r0, height z_s) and fits a local polynomial (default cubic) in
//     the displacement (ex, ey, ez) by least squares. The stencil spans the
//     whole displacement range the scan asks for (|Rot(-theta)s - d| <=
//     |s|+|d| in plane, |dz| in z), so the fit interpolates and never
//     extrapolates. Any FieldSource works (exact, grid, FEM).
//  2. With N theta samples per turn, probe k at rotor angle theta_m sits at
//     nominal node (i_k - m) mod N (b_k = 360*i_k/N) displaced by
//     Rot(-theta_m) s - d and dz, the same for all probes. So the probe
//     readings of a mounting case cost one polynomial dot product per
//     (theta, distinct probe angle); the arrays share their probe angles.
//  3. atan2, wrap, spectrum and peak-to-peak are then computed exactly as in
//     the direct pipeline, on the N-point theta grid (default N = 360).
// The surrogate's two approximations (local polynomial field, N-point theta
// grid) are measured, not assumed: validate() runs the direct pipeline at
// sensor.steps (default 3600) and at N steps on the spectra cases, the worst
// corner and some MC samples at a few radii, and reports the discrepancies
// (tests bound them).
// CircleFieldModel lives in analysis/circle_field_model.hpp, FastPipeline in
// analysis/fast_pipeline.hpp; this header includes both.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "analysis/circle_field_model.hpp"
#include "analysis/fast_pipeline.hpp"
#include "core/config.hpp"
#include "core/defaults.hpp"
#include "fields/field_source.hpp"
#include "probe/mounting.hpp"
#include "probe/probe_array.hpp"
#include "probe/sensor.hpp"
#include "analysis/sensor_noise.hpp"
#include "probe/spectrum.hpp"
#include "io/tables.hpp"
#include "analysis/tolerance.hpp"

namespace magenc {

// Settings of the scan ([radius] keys; [noise] for the noise model).
struct RadiusScanOptions {
  std::vector<ProbeArray> arrays;       // probe arrays to compare
  std::vector<double> r0_mm;            // scanned probe radii (mm, increasing)
  double plane_z_mm = defaults::kPlaneZ_mm;  // sensing plane height z_s (magnet frame, mm)
  int direct_steps = 3600;              // theta samples of the direct pipeline (validation)
  int fast_steps = 360;                 // theta samples N of the surrogate pipeline
  int surrogate_order = 4;              // polynomial degree of the local field models (4: ~10x more accurate than 3 at ~1.3x the cost)
  // How the local field models are built (radius.surrogate_build): automatic (the default: symmetry for
  // the exact field, symmetrized for the others where their asymmetry at the nodes is small, as an FE
  // solution's, else direct fits), axis_aligned (direct fits), symmetry (the exact field's rotational
  // symmetry, the exact field only) or symmetrized (any field's symmetric part plus its asymmetry at the
  // nodes); with symmetry and symmetrized the pipeline interpolates the readings in theta
  // (FastPipeline::coarse_steps). CircleFieldModel::Construction says how each is built.
  CircleFieldModel::Construction surrogate_build = CircleFieldModel::Construction::automatic;
  ToleranceBox box;                     // mounting tolerance box (half-widths, mm; tilts deg; chain, elevation)
  double magnet_height_mm = defaults::kMagnetHeight_mm;  // L (magnet-tilt pivot and reach)
  double elevation_deg = 0;             // the magnet's configured elevation (centre of the box's elevation axis)
  double case_offset_mm = 0.1;          // spectra cases: this much of each of sx, sy, dx, dy
  double case_dz_mm = 0.2;              // spectra cases: dz = +-this ...
  double case_residual_dx_mm = 0.05;    // ... with this residual dx
  long samples = 10000;                 // Monte Carlo samples per radius
  std::uint64_t seed = 1;               // Monte Carlo base seed
  SensorNoise noise;                    // sensor noise model
  int validate_radii = 4;               // radii (spread over the scan) checked against the direct pipeline
  int validate_samples = 4;             // MC samples checked per validation radius
  double band_rel = 0.05;               // near-optimal band: total_p99 <= (1 + band_rel) * min
  // The chip's field window (sensor.field_min_mT, sensor.field_max_mT; off by default). When it is
  // set, corners and Monte Carlo samples whose peak |Bz| (per probe, min and max over the probes)
  // leaves it are counted apart and left out of the pp statistics (a design whose field leaves the
  // window fails whatever its angle error); off, the outputs are those without a window.
  FieldWindow window;

  static std::vector<KeySpec> keys();   // [radius] keys (noise keys: SensorNoise::keys())
  static RadiusScanOptions from_config(const Config& cfg);
  void validate() const;                // InputError naming the key
};

// The six spectra cases of the radius study: sx, sy, dx, dy = case_offset; dz = +-case_dz with dx = residual.
std::vector<std::pair<std::string, Mount>> spectra_cases(const RadiusScanOptions& opt);

// One row of radius.csv: one (field, array, r0).
struct RadiusRow {
  std::string field, array;
  double r0_mm = 0;
  double bz_amplitude_T = 0;       // amplitude of Bz on the probe circle (ideal mount)
  double ideal_pp_deg = 0;         // pp with an ideal mount (0 for an exact field: any value is a field artefact)
  double worst_pp_deg = 0;         // largest pp over the tolerance box corners
  std::string worst_corner;        // which corner, e.g. "sx+ sy- dx+ dy+ dz-" (corner_text of the case)
  SampleStats mc;                  // pp over the Monte Carlo samples (deg)
  AngleNoise noise;                // sensor noise contribution
  double total_p99_pp_deg = 0;     // mc.p99 + noise.pp_deg (linear sum, conservative)
  double total_worst_pp_deg = 0;   // worst_pp + noise.pp_deg
  // Field window (only with RadiusScanOptions::window set): samples and corners whose field left it
  // (counted apart: mc and worst_pp are over the in-window ones), and the field extremes over all
  // MC samples (the peak |Bz| of a probe, mT).
  long mc_out_of_window = 0;
  long corners_out_of_window = 0;
  double field_min_mT = 0, field_max_mT = 0;
};

// Surrogate vs direct pipeline on one case.
struct ValidationRow {
  std::string field, array, label;
  double r0_mm = 0;
  Mount mount;
  double pp_direct_deg = 0;        // direct pipeline, direct_steps samples
  double pp_direct_coarse_deg = 0; // direct pipeline, fast_steps samples (theta-grid effect alone)
  double pp_surrogate_deg = 0;     // surrogate pipeline, fast_steps samples
  double max_coef_diff_deg = 0;    // max |surrogate - direct| over a0, a1..a8, b1..b8
};

struct Recommendation {
  std::string field, array;
  double r0_best_mm = 0;           // argmin of total_p99 over the scan
  double total_p99_best_deg = 0;
  double mc_p99_best_deg = 0, noise_pp_best_deg = 0;  // its two parts
  double total_p99_left_deg = 0;   // at the neighbouring radii (NaN at the scan's ends)
  double total_p99_right_deg = 0;
  double band_lo_mm = 0, band_hi_mm = 0;  // contiguous r0 range with total_p99 <= (1+band_rel)*best
  double r0_best_mount_only_mm = 0;       // argmin of mc_p99 alone (no noise)
  bool at_scan_edge = false;              // best r0 is the first or last scanned radius
};

struct FieldScanInfo {
  std::string field;               // FieldSource::name()
  std::string spec;                // how it was given (e.g. "fem:output/field")
  double r_bz_peak_mm = 0;         // radius where the Bz amplitude peaks (parabolic refinement)
  double bz_peak_T = 0;
  bool peak_at_edge = false;       // the maximum is at the first/last scanned radius
  double max_fit_residual_T = 0;   // largest surrogate fit residual over the radii
  // How the surrogate's node models were built at each radius (CircleFieldModel::Construction: radii
  // per construction, in the order automatic chose them), and for symmetrized models the largest
  // asymmetry at the nodes relative to the Bz amplitude over the radii.
  std::vector<std::pair<std::string, int>> builds;
  double max_node_residual_rel = 0;
  double t_models_s = 0, t_cases_s = 0, t_validate_s = 0;  // wall time per stage
};

// Error budget at a recommended radius: the Monte Carlo p99 of pp with only
// one group of the tolerance box active (the same samples, the other
// half-widths 0) against the p99 with the whole box. share = p99_only / p99_all
// (the shares need not add up to 1: the sources combine neither linearly nor
// in quadrature).
struct BudgetRow {
  std::string field, array;
  double r0_mm = 0;                // the recommended r0 of (field, array)
  std::string group;               // static, dynamic, air gap, sensor tilt, magnet tilt, signal chain, magnetization elevation
  double p99_only_deg = 0;         // p99 of pp with only this group active (deg)
  double p99_all_deg = 0;          // p99 of pp with the whole box (deg), same samples
  double share = 0;                // p99_only / p99_all
};

struct RadiusScanResult {
  std::vector<RadiusRow> rows;                 // field-major, then array, then r0
  std::vector<SpectrumRow> spectra;            // spectra cases (surrogate, fast_steps); extra "case"
  std::vector<ValidationRow> validation;
  std::vector<Recommendation> recommendations; // one per (field, array)
  std::vector<FieldScanInfo> fields;
  std::vector<BudgetRow> budget;               // per (field, array): one row per non-empty group
};

// InputError (one line) when the field cannot serve the box: an elevation
// axis (radius.tol_magnetization_elevation_deg > 0) needs a field whose
// magnetization can change, i.e. the exact field (`analytic`); a FEM solve,
// a grid, a table or the linear model has one fixed magnetization (or none).
// Also |elevation| + its half-width must stay <= 90 deg. run_radius_scan
// calls it first; the study calls it for every field before any work.
void check_field_serves_box(const FieldSource& field, const std::string& spec, const RadiusScanOptions& opt);
// The rows of a scan name their field by FieldSource::name() ("analytic", "fem", "grid", "table"): two
// sources of one kind would merge in every table and plot: InputError naming both specs.
void check_distinct_field_kinds(const std::vector<std::pair<std::string, FieldSourcePtr>>& fields);

// The scan for one field; results appended to `out`. `spec` is recorded.
void run_radius_scan(const FieldSource& field, const std::string& spec, const RadiusScanOptions& opt,
                     RadiusScanResult& out);

// The in-plane and vertical displacement (mm) the local field models must
// serve at radius r0 for the box and the spectra cases (tilts included).
std::pair<double, double> model_reach_mm(const RadiusScanOptions& opt, double r0_mm);

// Recommendation from rows of one (field, array), increasing r0.
Recommendation recommend(const std::vector<RadiusRow>& rows, double band_rel);

// Radius of the largest of y(x) (x increasing), refined by the parabola
// through the maximum and its neighbours; {x, y_max, at_edge}.
struct Peak {
  double x = 0, y = 0;
  bool at_edge = false;
};
Peak find_peak(const std::vector<double>& x, const std::vector<double>& y);

// Field specs to run: radius.fields (comma-separated), plus "fem:<radius.fem_dir>"
// when that directory holds a solved field (solve.json) and no fem: spec is
// listed. notes receives one line per decision (for summary.md).
// solve_mismatch(DIR) says why the solve in DIR does not fit cfg's magnet ("" when
// it fits or DIR has no solve.json): field_solver's SolvedFieldDir(DIR).mismatch(cfg),
// which this library cannot call itself.
using SolveMismatch = std::function<std::string(const std::string& dir)>;
std::vector<std::string> radius_field_specs(const Config& cfg, std::vector<std::string>& notes,
                                            const SolveMismatch& solve_mismatch);

}  // namespace magenc
