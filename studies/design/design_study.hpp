// The design study (docs/studies/design.md): which magnet (radius, height, material), which air gap,
// which Bz array and which probe radius r0 meet the requirements with the smallest magnet.
//
// A design is one point of the grid material x magnet radius x magnet height x gap x r0 x sensor
// (DesignSpace; index order in that nesting, the sensor innermost). Per design, on the exact field of
// its magnet, through the fast pipeline of radius_scan.hpp (CircleFieldModel + FastPipeline):
//  * factory sample i: ToleranceBox::case_sample(seed_d, i) of the mounting box (at 20 C);
//  * run state i: the factory mount plus a drift (the drift box: a re-mount within +-drift half-widths)
//    at a temperature uniform in [temperature_min_C, temperature_max_C] with a homogeneous stray field
//    of magnitude uniform in [0, stray_mT] (ToleranceBox's environment; Br(T) of the design's material);
//  * uncalibrated pp: peak-to-peak of eps at the run state; calibrated pp: the correction of the
//    calibration method (harmonics:N or lut:K of analysis/calibration.hpp) taken from the pairs
//    (theta + eps, eps) at the factory state, its residual at the run state;
//  * p99 of both over the samples; the requirement applies to the calibrated one (the uncalibrated one
//    with method none);
//  * field margin: the chip's window against the peak |Bz| of the probes over the factory samples,
//    scaled by Br(T)/Br(20 C) at both temperature extremes and widened by the stray field magnitude
//    (a bound: the stray field adds at most |B_stray| to a reading): margin = min(low side, high side);
//  * magnet volume pi R^2 L.
// Seeds: seed_d = splitmix64(seed ^ splitmix64(index + 1)) with per-design seeding (default), the base
// seed itself otherwise (common random numbers: every design sees the same samples, as the radius
// study's radii do). The drift stream is splitmix64(seed_d + kDriftStream). So a design's result is a
// pure function of the configuration and its index: independent of thread count, of how the designs are
// split over MPI ranks and of which designs are evaluated beside it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/calibration.hpp"
#include "analysis/circle_field_model.hpp"
#include "analysis/tolerance.hpp"
#include "core/config.hpp"
#include "probe/probe_array.hpp"
#include "probe/sensor.hpp"
#include "probe/speed.hpp"

namespace magenc {

struct DesignSpace {
  std::vector<std::string> materials = {"ndfeb_sintered"};  // magnet.material names (Br(T) coefficient)
  std::vector<double> br_T = {1.2};                         // Br at 20 C of each material (T)
  std::vector<double> magnet_radius_mm = {2.0};
  std::vector<double> magnet_height_mm = {4.0};
  std::vector<double> magnet_inner_radius_mm = {0.0};        // ring magnets' inner radii Ri (0: solid)
  std::vector<double> gap_mm = {2.55};                       // plane height above the magnet's top face
  std::vector<double> r0_mm = {2.4};                         // probe radius
  std::vector<ProbeArray> sensors;                           // Bz arrays: two, diff4, ring:N
  // Side-shaft readers (design.side_principles: inplane, xmr; none by default): one spot beside the magnet, the
  // die centre at [side_radius, 0] and its plane side_height above the magnet's mid-plane; direction, zero and
  // gain trim (BCT) automatic at the nominal mount. Per magnet, their designs follow the Bz arrays'.
  std::vector<SensorPrinciple> side_principles;
  std::vector<double> side_radius_mm = {3.5};                // read radii (die centre's distance from the axis)
  std::vector<double> side_height_mm = {0.0};                // die plane above the magnet's mid-plane
  // The readers of one magnet: the Bz arrays at every gap and r0, then the side-shaft readers at every radius
  // and height. Reader indices: sensor innermost, then r0, gap; side: principle innermost, then height, radius.
  std::size_t bz_readers() const { return gap_mm.size() * r0_mm.size() * sensors.size(); }
  std::size_t readers() const {
    return bz_readers() + side_radius_mm.size() * side_height_mm.size() * side_principles.size();
  }
  std::size_t size() const {
    return materials.size() * magnet_radius_mm.size() * magnet_inner_radius_mm.size() * magnet_height_mm.size() *
           readers();
  }
  // Sensor indices (Design::sensor): the Bz arrays, then the side-shaft principles.
  std::size_t sensor_count() const { return sensors.size() + side_principles.size(); }
  bool is_side(std::size_t sensor) const { return sensor >= sensors.size(); }
  std::string sensor_name(std::size_t sensor) const;  // "ring:8", "side inplane"
};

struct DesignRequirements {
  double target_p99_deg = 0.5;         // p99 of the pp angle error must not exceed this
  FieldWindow window;                  // the chip's window (sensor.field_min_mT, field_max_mT; off by default)
  double temperature_min_C = 20, temperature_max_C = 20;
  double stray_mT = 0;                 // largest homogeneous stray field (mT)
  CalibrationMethod calibration;       // none, harmonics:N, lut:K
};

struct DesignOptions {
  DesignSpace space;
  DesignRequirements req;
  ToleranceBox box;                    // mounting box of the factory state (tol.*)
  double drift_inplane_mm = 0;         // drift half-width of each of sx, sy, dx, dy (mm)
  double drift_dz_mm = 0;              // drift half-width of the air gap (mm)
  long samples = 2000;
  std::uint64_t seed = 1;
  bool seed_per_design = true;
  int fast_steps = 360;
  int surrogate_order = 4;
  // The run state at a speed (speed.rpm and the sensor's timing keys, probe/speed.hpp): the uncalibrated and
  // calibrated pp are those of the turning encoder; the correction is taken at the factory state, at rest.
  SpeedChain speed;
  // How the local field models are built (design.surrogate_build; the exact field): automatic (= symmetry:
  // readings at 24 theta, interpolated exactly, FastPipeline::coarse_steps), symmetry or axis_aligned.
  CircleFieldModel::Construction surrogate_build = CircleFieldModel::Construction::automatic;

  static std::vector<KeySpec> keys();  // [design] keys and tol.*
  // InputError (one line naming the key) for a sensor that is not a Bz array, a material count that
  // differs from design.br_T's, a calibration method the fast path cannot take (ogp), r0 inside the
  // box's reach, a temperature range with min > max.
  static DesignOptions from_config(const Config& cfg);
  void validate() const;
  // The side-shaft axes (design.side_*): non-empty with a side principle, every spot clear of every magnet.
  void validate_side() const;
  // The drift box with the environment of the requirements, for a material's Br coefficient.
  ToleranceBox run_box(double br_tc_per_K) const;
};

// One design's variables (a pure function of the index).
struct Design {
  std::size_t index = 0;
  std::string material;
  double br_T = 0, br_tc_per_K = 0;
  double magnet_radius_mm = 0, magnet_height_mm = 0, gap_mm = 0, r0_mm = 0;
  double magnet_inner_radius_mm = 0;   // a ring when > 0 (the arrays read around its bore)
  std::size_t sensor = 0;              // DesignSpace::sensor_count() indices: a Bz array, then a side principle
  // A side-shaft reader (DesignSpace::is_side): its die centre's radius and plane height above the mid-plane;
  // gap_mm and r0_mm are then NaN (not its axes), and these are NaN for a Bz array.
  bool side = false;
  double side_radius_mm = 0, side_height_mm = 0;
  double volume_mm3() const;
  double plane_z_mm() const { return side ? side_height_mm : 0.5 * magnet_height_mm + gap_mm; }
};
Design design_at(const DesignSpace& s, std::size_t index);

// The numbers of one evaluated design (fixed count: kValues, for gathering across ranks).
struct DesignResult {
  double p99_uncal_deg = 0;            // p99 of the uncalibrated pp at the run state
  double p99_cal_deg = 0;              // the same after calibration (= uncal with method none)
  double p50_uncal_deg = 0, p50_cal_deg = 0;
  double field_min_mT = 0, field_max_mT = 0;  // extremes of the probes' peak |Bz| at 20 C over the factory samples
  double field_lo_mT = 0, field_hi_mT = 0;    // the same at the temperature extremes, widened by the stray field
  double margin_mT = 0;                // window margin (negative: outside; +inf without a window)
  double bz_amplitude_mT = 0;          // first-harmonic Bz amplitude on the probe circle (NaN: a side-shaft reader)
  static constexpr int kValues = 10;
  void to(double* v) const;
  static DesignResult from(const double* v);
  double p99_req_deg(const DesignRequirements& r) const { return r.calibration.none() ? p99_uncal_deg : p99_cal_deg; }
  bool field_ok() const { return margin_mT >= 0; }
  bool pass(const DesignRequirements& r) const { return field_ok() && p99_req_deg(r) <= r.target_p99_deg; }
  // "" when it passes, else why (e.g. "p99 0.61 deg > 0.5 deg; field 12 mT below window 30 mT").
  std::string reason(const DesignRequirements& r) const;
};

// The seed of design `index`.
std::uint64_t design_seed(const DesignOptions& o, std::size_t index);
// Evaluates designs [begin, end) (OpenMP over samples inside each design).
std::vector<DesignResult> evaluate_designs(const DesignOptions& o, std::size_t begin, std::size_t end);
// The same for one design with a given mounting box (the budget).
DesignResult evaluate_design(const DesignOptions& o, std::size_t index, const ToleranceBox& box, bool drift);

struct BudgetEntry {
  std::string group;                   // a ToleranceBox group, or "drift and environment"
  double p99_uncal_deg = 0, p99_cal_deg = 0;
};

struct DesignStudyResult {
  std::vector<Design> designs;
  std::vector<DesignResult> results;
  std::vector<std::vector<std::size_t>> pareto;  // per sensor: design indices on the front, increasing volume
  long recommended = -1;               // design index, -1: no design meets the requirements
  std::vector<BudgetEntry> budget;     // of the recommended design (empty without one)
  std::size_t passing = 0;
};

// Pareto front of (p99_req, volume) per sensor among designs whose field is in the window, recommended
// design (smallest volume meeting every requirement; ties: smaller p99, then smaller index).
DesignStudyResult summarize_designs(const DesignOptions& o, std::vector<DesignResult> results);
// The error budget of design `index`: each group of the mounting box alone (no drift, 20 C), then the drift
// and the environment alone (no mounting tolerance).
std::vector<BudgetEntry> design_budget(const DesignOptions& o, std::size_t index);

}  // namespace magenc
