// The multipole study's computation (docs/multipole.md; docs/physics.md "Multipole rings and nonius"): the
// configured multipole ring ([magnet], exact field by sectors) read by Bz arrays with electrical spacing:
//  * interpolation: for every read gap (study.gaps_mm, above the top face) and array (study.arrays) at the
//    ideal mount, ce1..ce4 (orders p..4p) and pp of the incremental reading;
//  * eccentricity: a dynamic eccentricity e (study.eccentricities_mm) against the e/r law c1 = e / r0 rad;
//  * pole errors: study.pole_samples rings with seeds 1..N of edge and amplitude errors
//    (study.pole_edge_sigma_deg, study.pole_amplitude_sigma), ideal mount: pp, c1, ce1..ce4, percentiles;
//  * nonius ([nonius] present): study.box_samples mounts uniform in the tolerance box (sensor offsets,
//    eccentricity, air gap; seeded by study.seed), both tracks' fields at every probe: the synchronisation
//    margin (p1/p50/p99), the mounts that slip (gross errors of 360/p) apart from the error percentiles of
//    the others. The mounts run on the Monte Carlo engine (probe/multipole_pipeline.hpp; ideal rings and
//    plain read heads), else on the exact field.
#pragma once
#include <string>
#include <vector>

#include "core/config.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

struct MultipoleStudyOptions {
  int steps = 360;
  std::vector<double> gaps_mm;
  std::vector<std::string> arrays;
  std::vector<double> eccentricities_mm;
  int pole_samples = 100;
  double pole_edge_sigma_deg = 0.05, pole_amplitude_sigma = 0.02;
  int box_samples = 100;
  double box_offset_mm = 0.05, box_eccentricity_mm = 0.01, box_dz_mm = 0.1;
  long seed = 1;

  static std::vector<KeySpec> keys();  // study.* keys
  // InputError naming the keys: a uniform (non-multipole) magnet, an array the electrical head cannot take.
  static MultipoleStudyOptions from_config(const Config& cfg);
};

struct InterpolationPoint {
  double gap_mm = 0;
  std::string array;
  std::array<double, 4> ce_deg{};
  double pp_deg = 0;
};

struct EccentricityPoint {
  double e_mm = 0, c1_deg = 0, law_deg = 0, pp_deg = 0;
};

struct PoleSample {
  long seed = 0;
  double pp_deg = 0, c1_deg = 0;
  std::array<double, 4> ce_deg{};
};

struct BoxSample {
  int index = 0;
  Mount mount;
  double margin_deg = 0, pp_deg = 0, max_abs_deg = 0;
  int slipped_samples = 0;
};

struct MultipoleStudyResult {
  std::string array;
  int pole_pairs = 1, nonius_pole_pairs = 0;
  double r0_mm = 0, gap_mm = 0, nonius_r0_mm = 0, pole_pitch_mm = 0;
  MultipoleStudyOptions options;
  std::vector<InterpolationPoint> interpolation;
  std::vector<EccentricityPoint> eccentricity;
  std::vector<PoleSample> poles;
  std::vector<BoxSample> box;  // empty without a nonius
  bool box_engine = false;     // the box's mounts read by the Monte Carlo engine (else the exact field at each)
  double box_engine_misfit_T = 0;  // the engine's largest model misfit (MultipoleRingModel::misfit_T)
  double ideal_margin_deg = 0, ideal_pp_deg = 0;
};

MultipoleStudyResult run_multipole_study(const Config& cfg, const MultipoleStudyOptions& opt);

}  // namespace magenc
