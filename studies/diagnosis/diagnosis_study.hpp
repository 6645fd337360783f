// The diagnosis study's library part (studies/diagnosis/diagnosis.cpp stays thin):
//  * synthetic measured curves: the forward model at given parameter values, sampled at the reference
//    encoder's readings (reference noise), with the sensor's quantization (positions per turn) and a zero
//    offset between the encoders;
//  * the round trip: seeded random truths -> synthetic curves -> diagnose_curves -> coverage of the
//    2-sigma intervals per free parameter, and how often each parameter was reported not identifiable;
//  * constructed curves for the anomalies of the original study: a target curve made from one set of sources,
//    fitted with other candidate sets (some values known), to see which combinations reproduce it.
#pragma once
#include <random>
#include <string>
#include <vector>

#include "analysis/diagnosis_fit.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"

namespace magenc {

struct SyntheticOptions {
  int points = 360;              // samples per turn (reference readings, jittered around a uniform grid)
  double noise_deg = 0.005;      // reference-encoder noise, RMS (Gaussian)
  int quant_positions = 8192;    // sensor output positions per turn (0: no quantization)
  double zero_deg = 0.0;         // zero offset between the encoders
};

// A synthetic measured curve of the model at `values` (table order): the true rotor angle theta_k is a
// jittered uniform grid; the sensor's angle phi(theta_k) = theta_k + eps_model is quantized to
// 360/quant_positions; the reference reads theta_k + noise; the curve stores (reference, wrap(phi_q +
// zero - reference)). rng draws the jitter and the noise.
CurveInput synthetic_curve(const FieldSource& field, const ModelState& base, const std::vector<double>& values,
                           const SyntheticOptions& so, std::mt19937& rng);

struct RoundTripOptions {
  int cases = 100;
  unsigned seed = 1;
  SyntheticOptions synth;
  std::vector<std::string> randomized;  // parameters drawn uniformly in +-range_scale * typical size
  double range_scale = 2.0;
  double max_zero_deg = 0.5;            // zero offset drawn uniformly in +-max_zero_deg
  std::vector<std::string> free;        // fitted set (empty: default_free_set at the base point)
  int starts = 3;
  double fd_step = 1e-4;                // DiagnosisOptions::fd_step (1e-2 on FE/grid fields)
};

struct RoundTripParam {
  std::string json_name;
  int fitted = 0;            // cases where it was free and had a finite sigma
  int within_2sigma = 0;     // |fit - truth| <= 2 sigma
  int within_2sigma_any = 0; // the same at the best or at an equally good alternative minimum
  int ambiguous = 0;         // cases with an equally good alternative minimum
  int not_identifiable = 0;  // cases where the fit reported it not identifiable
  double median_abs_err = 0; // median |fit - truth| (unit of the parameter)
  double median_sigma = 0;
  double coverage() const { return fitted ? static_cast<double>(within_2sigma) / fitted : 0.0; }
  double coverage_any() const { return fitted ? static_cast<double>(within_2sigma_any) / fitted : 0.0; }
};

struct RoundTripResult {
  std::string array, field;
  std::vector<std::string> free;        // json names fitted (shared parameters)
  std::vector<std::string> randomized;  // json names drawn at random
  std::vector<RoundTripParam> params;   // per free variable (zero offset included)
  int cases = 0, failed = 0;            // failed: fits that threw (domain errors)
  double median_residual_rms_deg = 0;
  double mean_fit_s = 0, max_fit_s = 0;
  std::string default_free_note;
};

RoundTripResult run_round_trip(const FieldSource& field, const ModelState& base, const RoundTripOptions& opts);

// A constructed-curve experiment: the target is made from `truth` (table values); each candidate fits its
// free set with its known values.
struct Candidate {
  std::string label;                 // "channel offsets (oc, os)"
  std::vector<std::string> free;     // short names
  std::vector<std::pair<std::string, double>> known;  // values held fixed (others at the base value)
  bool free_zero = true;             // fit a zero offset between the encoders
};
struct CandidateFit {
  std::string label;
  double residual_rms_deg = 0;
  std::vector<std::pair<std::string, std::pair<double, double>>> values;  // json name -> (value, sigma)
  std::vector<std::string> not_identifiable;
  std::vector<std::string> alternatives;  // equally good minima elsewhere, "name=value ..." each (mirror images)
};
struct Experiment {
  std::string title;                 // the anomaly
  std::string target_label;          // "sx 0.1 mm + oc 0.3 mT"
  std::vector<double> target_values; // table order
  Eigen::VectorXd target_h;          // harmonics_ls of the target (a0, a1, b1, ...)
  std::vector<CandidateFit> fits;
};
Experiment run_experiment(const FieldSource& field, const ModelState& base, const std::string& title,
                          const std::string& target_label, const std::vector<std::pair<std::string, double>>& truth,
                          const std::vector<Candidate>& candidates, const SyntheticOptions& so, unsigned seed);

// The anomalies of the original study as constructed-curve experiments (hypotheses, not findings): each
// target is one possible cause; the candidates are the other explanations tried against it.
struct ExperimentSpec {
  std::string title, target_label;
  std::vector<std::pair<std::string, double>> truth;
  std::vector<Candidate> candidates;
  double zero_deg = 0.0;
};
std::vector<ExperimentSpec> anomaly_experiments();

// Table values at the base point with some entries set by short name.
std::vector<double> table_values(const ModelState& base, const std::vector<std::pair<std::string, double>>& set);

// The whole diagnosis study (studies/diagnosis/diagnosis.cpp): round trips per field and array, the all-free
// identifiability check, one example fit, the anomaly experiments. Reads the keys of studies/diagnosis/diagnosis.cpp
// (study.arrays, roundtrip.*, anomalies.enabled, fem_field.dir). The exact field is made here; the FE field
// (fem:DIR, served by field_solver/) is opened by the study and passed in, or null for the exact field only.
struct DiagnosisStudyResult {
  SyntheticOptions synth;               // noise, quantization, points of the round trips
  unsigned seed = 1;
  double range_scale = 2.0, max_zero_deg = 0.5;
  std::vector<RoundTripResult> trips;   // per field source, then per array
  // "<field> `<array>`" -> "`name` k/n" per parameter: cases reported not identifiable with every parameter free
  std::vector<std::pair<std::string, std::vector<std::string>>> all_free;
  int all_free_starts = 1;  // fit starts per all-free case
  std::vector<std::pair<std::string, Experiment>> anomalies;  // array -> experiment
  // One example fit (first field, first array), plotted by the report.
  std::vector<CurveInput> example_curves;
  DiagnosisResult example_fit;
};
DiagnosisStudyResult run_diagnosis_study(const Config& cfg, const FieldSourcePtr& fem_or_null);

}  // namespace magenc
