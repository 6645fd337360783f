#include "studies/diagnosis/diagnosis_study.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <cmath>

#include <omp.h>

#include "analysis/sensor_noise.hpp"
#include "analysis/sweep.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/axisym_table_field.hpp"
#include "fields/field_factory.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

namespace {
// Parallel over independent fits: each runs on one thread, its own parallel regions nested inside and so
// serial (max active levels 1 for the scope; restored after).
class OuterParallelScope {
 public:
  OuterParallelScope() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(1); }
  ~OuterParallelScope() { omp_set_max_active_levels(levels_); }
  OuterParallelScope(const OuterParallelScope&) = delete;
  OuterParallelScope& operator=(const OuterParallelScope&) = delete;

 private:
  int levels_;
};
}  // namespace

std::vector<double> table_values(const ModelState& base, const std::vector<std::pair<std::string, double>>& set) {
  std::vector<double> v;
  for (const auto& p : fit_parameters()) v.push_back(p.get(base));
  for (const auto& [n, x] : set) v[fit_parameter_index(fit_parameter(n).name)] = x;
  return v;
}

CurveInput synthetic_curve(const FieldSource& field, const ModelState& base, const std::vector<double>& values,
                           const SyntheticOptions& so, std::mt19937& rng) {
  const int n = so.points;
  if (n < 64) throw InputError("synthetic curve points " + std::to_string(n) + " is out of range: allowed >= 64");
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  CurveInput c{{}, base, {}};
  c.curve.path = "synthetic";
  c.curve.format = "error_deg";
  Eigen::VectorXd theta(n);
  for (int i = 0; i < n; ++i) theta[i] = 360.0 * (i + 0.5 + jitter(rng)) / n;  // true rotor angles in (0, 360)
  c.curve.theta_deg = theta;
  const Eigen::VectorXd eps = model_curve_deg(field, c, values);  // at the true angles
  // The reference readout shared with the calibration run (analysis/sensor_noise.hpp).
  observe_curve(theta, eps, ReferenceReadout{so.noise_deg, so.quant_positions, so.zero_deg}, rng, c.curve.theta_deg,
                c.curve.error_deg);
  c.curve.row.resize(n);
  for (int i = 0; i < n; ++i) c.curve.row[i] = i + 2;
  c.curve.turns = 1.0;
  c.curve.median_step_deg = 360.0 / n;
  return c;
}

namespace {
// One fitted case into the round trip's counts: per variable, within 2 sigma (also at an equally good
// alternative minimum), not identifiable, |error| and sigma.
void tally_case(const DiagnosisResult& r, const std::vector<double>& truth, double zero_deg,
                const std::vector<std::string>& vars, RoundTripResult& res, std::vector<std::vector<double>>& abs_err,
                std::vector<std::vector<double>>& sig) {
  for (std::size_t j = 0; j < vars.size(); ++j) {
    const ParamValue* pv = nullptr;
    for (const auto& p : r.params)
      if (p.json_name == vars[j]) pv = &p;
    if (!pv) continue;
    const double t = vars[j] == "zero_offset_deg" ? zero_deg : truth[fit_parameter_index(vars[j])];
    if (std::find(r.not_identifiable.begin(), r.not_identifiable.end(), vars[j]) != r.not_identifiable.end()) {
      ++res.params[j].not_identifiable;
      continue;
    }
    if (!std::isfinite(pv->sigma)) continue;
    ++res.params[j].fitted;
    const double e = std::abs(pv->value - t);
    if (e <= 2.0 * pv->sigma) ++res.params[j].within_2sigma;
    bool any = e <= 2.0 * pv->sigma;
    const auto fi = std::find(r.free.begin(), r.free.end(), vars[j]) - r.free.begin();
    for (const auto& alt : r.alternatives)
      if (fi < static_cast<long>(alt.values.size()) && std::abs(alt.values[fi] - t) <= 2.0 * pv->sigma) any = true;
    if (any) ++res.params[j].within_2sigma_any;
    if (!r.alternatives.empty()) ++res.params[j].ambiguous;
    abs_err[j].push_back(e);
    sig[j].push_back(pv->sigma);
  }
}
}  // namespace

RoundTripResult run_round_trip(const FieldSource& field, const ModelState& base, const RoundTripOptions& opts) {
  RoundTripResult res;
  res.array = base.setup.array.name;
  res.field = field.name();
  std::mt19937 rng(opts.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  // 1. The free set: as given, or what one curve identifies at the base point (a curve of the ideal model).
  std::vector<std::string> free = opts.free;
  if (free.empty()) {
    std::mt19937 r0(opts.seed);
    SyntheticOptions s0 = opts.synth;
    s0.noise_deg = 0;
    s0.quant_positions = 0;
    const std::vector<CurveInput> nominal{synthetic_curve(field, base, table_values(base, {}), s0, r0)};
    DiagnosisOptions d;
    free = default_free_set(field, nominal, d, &res.default_free_note);
  }
  for (const auto& n : free) res.free.push_back(fit_parameter(n).json_name);
  for (const auto& n : opts.randomized) res.randomized.push_back(fit_parameter(n).json_name);
  std::vector<std::string> vars = res.free;
  vars.push_back("zero_offset_deg");
  std::vector<std::vector<double>> abs_err(vars.size()), sig(vars.size());
  res.params.resize(vars.size());
  for (std::size_t j = 0; j < vars.size(); ++j) res.params[j].json_name = vars[j];
  std::vector<double> rms;
  double total_s = 0;
  // 2. Cases: the truths, zero offsets and synthetic curves drawn in case order from one stream (serial),
  // then the fits, one case per thread (each fit runs serially inside: its own parallel regions are
  // nested), then the tallies in case order. The same numbers as fitting the cases one after the other.
  struct Case {
    std::vector<double> truth;
    double zero_deg = 0;
    std::vector<CurveInput> curves;
    DiagnosisResult r;
    bool ok = false;
  };
  std::vector<Case> cases(static_cast<std::size_t>(std::max(opts.cases, 0)));
  for (auto& c : cases) {
    std::vector<std::pair<std::string, double>> set;
    for (const auto& n : opts.randomized) set.push_back({n, uni(rng) * opts.range_scale * fit_parameter(n).scale});
    c.truth = table_values(base, set);
    SyntheticOptions so = opts.synth;
    so.zero_deg = uni(rng) * opts.max_zero_deg;
    c.zero_deg = so.zero_deg;
    c.curves = {synthetic_curve(field, base, c.truth, so, rng)};
  }
  {
    const OuterParallelScope outer;
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < opts.cases; ++k) {
      Case& c = cases[static_cast<std::size_t>(k)];
      DiagnosisOptions d;
      d.free = free;
      d.starts = opts.starts;
      d.fd_step = opts.fd_step;
      d.seed = opts.seed + static_cast<unsigned>(k);
      try {
        c.r = diagnose_curves(field, c.curves, d);
        c.ok = true;
      } catch (const std::exception&) {
        c.ok = false;
      }
    }
  }
  for (const Case& c : cases) {
    ++res.cases;
    if (!c.ok) {
      ++res.failed;
      continue;
    }
    total_s += c.r.fit_seconds;
    res.max_fit_s = std::max(res.max_fit_s, c.r.fit_seconds);
    rms.push_back(c.r.residual_rms_deg);
    tally_case(c.r, c.truth, c.zero_deg, vars, res, abs_err, sig);
  }
  const auto median = [](std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  for (std::size_t j = 0; j < vars.size(); ++j) {
    res.params[j].median_abs_err = median(abs_err[j]);
    res.params[j].median_sigma = median(sig[j]);
  }
  res.median_residual_rms_deg = median(rms);
  const int ok = res.cases - res.failed;
  res.mean_fit_s = ok ? total_s / ok : 0.0;
  return res;
}

Experiment run_experiment(const FieldSource& field, const ModelState& base, const std::string& title,
                          const std::string& target_label, const std::vector<std::pair<std::string, double>>& truth,
                          const std::vector<Candidate>& candidates, const SyntheticOptions& so, unsigned seed) {
  Experiment ex;
  ex.title = title;
  ex.target_label = target_label;
  ex.target_values = table_values(base, truth);
  std::mt19937 rng(seed);
  const CurveInput target = synthetic_curve(field, base, ex.target_values, so, rng);
  ex.target_h = harmonics_ls(target.curve.theta_deg, target.curve.error_deg);
  for (const auto& c : candidates) {
    ModelState known = base;
    for (const auto& [n, v] : c.known) fit_parameter(n).set(known, v);
    CurveInput in = target;
    in.base = known;
    DiagnosisOptions d;
    d.free = c.free;
    d.free_zero = c.free_zero;
    d.starts = 4;
    d.seed = seed;
    CandidateFit cf;
    cf.label = c.label;
    try {
      const DiagnosisResult r = diagnose_curves(field, {in}, d);
      cf.residual_rms_deg = r.residual_rms_deg;
      for (const auto& p : r.params)
        if (p.free) cf.values.push_back({p.json_name, {p.value, p.sigma}});
      cf.not_identifiable = r.not_identifiable;
      for (const auto& a : r.alternatives) {
        std::string alt;
        for (std::size_t k = 0; k < r.free.size() && k < a.values.size(); ++k)
          alt += (alt.empty() ? "" : " ") + r.free[k] + "=" + fmt_sig(a.values[k], 4);
        cf.alternatives.push_back(alt);
      }
    } catch (const std::exception& e) {
      cf.residual_rms_deg = std::nan("");
      cf.not_identifiable = {std::string("fit failed: ") + e.what()};
    }
    ex.fits.push_back(cf);
  }
  return ex;
}

std::vector<ExperimentSpec> anomaly_experiments() {
  std::vector<ExperimentSpec> e;
  const std::vector<std::pair<std::string, double>> sx_set{{"sx", 0.1}};
  // 1. Half the static-offset error the simulation predicts for the rig's sx = 0.1 mm.
  e.push_back({"half the predicted static-offset error",
               "sx = 0.05 mm: the 2nd harmonic of half the rig's nominal sx = 0.1 mm",
               {{"sx", 0.05}},
               {{"the rig's offset was smaller: sx free", {"sx"}, {}},
                {"sx = 0.1 mm as set + gain, phase free", {"gain", "phase"}, sx_set},
                {"sx = 0.1 mm as set + sensor tilt x, y free", {"tilt_x", "tilt_y"}, sx_set},
                {"sx = 0.1 mm as set + sy free", {"sy"}, sx_set},
                {"sx = 0.1 mm as set + air gap dz free", {"dz"}, sx_set}}});
  e.push_back({"half the predicted static-offset error",
               "sx = 0.1 mm as set, with a gain mismatch g = -0.01 and phase error -0.5 deg",
               {{"sx", 0.1}, {"gain", -0.01}, {"phase", -0.5}},
               {{"the rig's offset was smaller: sx free", {"sx"}, {}},
                {"sx = 0.1 mm as set + gain, phase free", {"gain", "phase"}, sx_set},
                {"sx = 0.1 mm as set + sensor tilt x, y free", {"tilt_x", "tilt_y"}, sx_set}}});
  // 2. A 1st harmonic under a purely static offset: which source, and does c3 tell them apart?
  const std::vector<Candidate> c1_candidates{
      {"sx = 0.1 mm as set + dynamic eccentricity dx, dy free", {"dx", "dy"}, sx_set},
      {"sx = 0.1 mm as set + channel offsets free", {"offset_cos", "offset_sin"}, sx_set},
      {"sx = 0.1 mm as set + magnet tilt free", {"magnet_tilt_x", "magnet_tilt_y"}, sx_set}};
  e.push_back({"a 1st harmonic under a purely static offset", "sx = 0.1 mm + dynamic eccentricity dx = 0.02 mm",
               {{"sx", 0.1}, {"dx", 0.02}}, c1_candidates});
  e.push_back({"a 1st harmonic under a purely static offset", "sx = 0.1 mm + cos-channel offset 0.3 mT",
               {{"sx", 0.1}, {"offset_cos", 0.3}}, c1_candidates});
  e.push_back({"a 1st harmonic under a purely static offset", "sx = 0.1 mm + magnet tilt 0.5 deg towards +x",
               {{"sx", 0.1}, {"magnet_tilt_x", 0.5}}, c1_candidates});
  // 3. A DC of the opposite sign for a y offset.
  e.push_back({"a DC of the opposite sign for a y offset",
               "sy = 0.1 mm + phase error 3 deg (a0 = delta/2 outweighs the offset's DC); encoder zero offset 0",
               {{"sy", 0.1}, {"phase", 3.0}},
               {{"sy free, zero offset known to be 0", {"sy"}, {}, false},
                {"sy, phase free, zero offset known to be 0", {"sy", "phase"}, {}, false},
                {"sy, sensor tilt free, zero offset known to be 0", {"sy", "tilt_x", "tilt_y"}, {}, false},
                {"sy free, free zero offset (diagnose's default)", {"sy"}, {}, true}}});
  // 4. A 4th harmonic at the best mount.
  e.push_back({"a 4th harmonic at the best mount", "sx = sy = 0.07 mm residual static offsets (c4 is 2nd order in s)",
               {{"sx", 0.07}, {"sy", 0.07}},
               {{"sx, sy free", {"sx", "sy"}, {}},
                {"gain, phase free", {"gain", "phase"}, {}},
                {"dynamic eccentricity dx, dy free", {"dx", "dy"}, {}}}});
  e.push_back({"a 4th harmonic at the best mount", "gain mismatch 0.03 + phase error 2 deg (signal chain only)",
               {{"gain", 0.03}, {"phase", 2.0}},
               {{"sx, sy free", {"sx", "sy"}, {}},
                {"gain, phase free", {"gain", "phase"}, {}},
                {"sensor tilt x, y free", {"tilt_x", "tilt_y"}, {}}}});
  e.push_back({"a 4th harmonic at the best mount", "dynamic eccentricity dx = 0.05 mm (diff4: field's 3rd angular harmonic aliases to c4)",
               {{"dx", 0.05}},
               {{"dx, dy free", {"dx", "dy"}, {}},
                {"sx, sy free", {"sx", "sy"}, {}},
                {"gain, phase free", {"gain", "phase"}, {}}}});
  return e;
}

namespace {

// Every parameter free on `cases` round trips: per parameter "`name` k/n", how often it was not identifiable.
std::vector<std::string> all_free_flags(const FieldSource& field, const ModelState& base, const RoundTripOptions& o,
                                        int cases, int starts) {
  RoundTripOptions oa = o;
  oa.cases = cases;
  oa.starts = starts;
  oa.free.clear();
  for (const auto& p : fit_parameters()) oa.free.push_back(p.name);
  const RoundTripResult ra = run_round_trip(field, base, oa);
  std::vector<std::string> flagged;
  for (const auto& p : ra.params)
    flagged.push_back("`" + p.json_name + "` " + std::to_string(p.not_identifiable) + "/" + std::to_string(ra.cases - ra.failed));
  return flagged;
}

// One example fit (the report plots it): a synthetic curve of randomized parameters and its diagnosis.
void example_fit(const FieldSource& field, const ModelState& base, const RoundTripOptions& o, DiagnosisStudyResult& res) {
  std::mt19937 rng(o.seed);
  std::vector<std::pair<std::string, double>> set;
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (const auto& n : o.randomized) set.push_back({n, uni(rng) * o.range_scale * fit_parameter(n).scale});
  SyntheticOptions so = o.synth;
  so.zero_deg = 0.2;
  res.example_curves = {synthetic_curve(field, base, table_values(base, set), so, rng)};
  DiagnosisOptions d;
  d.free = o.free;
  d.starts = o.starts;
  d.fd_step = o.fd_step;
  res.example_fit = diagnose_curves(field, res.example_curves, d);
}

// The anomaly experiments of every array (constructed curves on the exact field). Every (array,
// experiment) is independent: one per thread, kept in order.
std::vector<std::pair<std::string, Experiment>> anomalies(const Config& cfg, const std::vector<std::string>& arrays,
                                                          const FieldSource& field, const SyntheticOptions& synth,
                                                          unsigned seed) {
  const std::vector<ExperimentSpec> specs = anomaly_experiments();
  std::vector<std::pair<std::string, Experiment>> done(arrays.size() * specs.size());
  std::vector<std::exception_ptr> err(done.size());
  const OuterParallelScope outer;
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < static_cast<int>(done.size()); ++k) {
    const std::string& a = arrays[static_cast<std::size_t>(k) / specs.size()];
    const ExperimentSpec& spec = specs[static_cast<std::size_t>(k) % specs.size()];
    try {
      const ModelState base{Mount::from_config(cfg), probe_setup_from_config(cfg, a, "study.arrays")};
      SyntheticOptions so = synth;
      so.zero_deg = spec.zero_deg;
      done[static_cast<std::size_t>(k)] = {a, run_experiment(field, base, spec.title, spec.target_label, spec.truth,
                                                             spec.candidates, so, seed)};
    } catch (...) {
      err[static_cast<std::size_t>(k)] = std::current_exception();
    }
  }
  for (const auto& e : err)
    if (e) std::rethrow_exception(e);
  return done;
}

}  // namespace

DiagnosisStudyResult run_diagnosis_study(const Config& cfg, const FieldSourcePtr& fem_or_null) {
  // 1. Inputs.
  const auto arrays = cfg.strings("study.arrays");
  for (const auto& a : arrays) (void)probe_setup_from_config(cfg, a, "study.arrays");  // all checked before any work
  struct Src {
    std::string label;
    FieldSourcePtr field;
    int cases;
  };
  // The exact field through its (r, z) tables (roundtrip.exact_tables; fields/axisym_table_field.hpp: within
  // 1e-12 of the quadrature, which it calls only to build the tables and near the magnet).
  FieldSourcePtr exact = make_field_source("analytic", cfg);
  if (cfg.flag("roundtrip.exact_tables")) exact = std::make_shared<AxisymmetricTableField>(exact);
  std::vector<Src> sources{{"exact", exact, static_cast<int>(cfg.integer("roundtrip.cases"))}};
  if (fem_or_null)
    sources.push_back({"fem:" + cfg.str("fem_field.dir"), fem_or_null, static_cast<int>(cfg.integer("roundtrip.fem_cases"))});
  RoundTripOptions rt;
  rt.seed = static_cast<unsigned>(cfg.integer("roundtrip.seed"));
  rt.synth.points = static_cast<int>(cfg.integer("roundtrip.points"));
  rt.synth.noise_deg = cfg.real("roundtrip.noise_deg");
  rt.synth.quant_positions = static_cast<int>(cfg.integer("roundtrip.quant_positions"));
  // Unknown names: the error names the key (the bad-input matrix found it naming only the parameter).
  const auto parameter_list = [&](const std::string& key) {
    try {
      auto names = expand_free_names(cfg.strings(key));
      for (const auto& n : names) fit_parameter(n);
      return names;
    } catch (const InputError& e) {
      throw InputError(key + ": " + e.what());
    }
  };
  rt.free = parameter_list("roundtrip.free");
  rt.range_scale = cfg.real("roundtrip.range_scale");
  rt.max_zero_deg = cfg.real("roundtrip.max_zero_deg");
  rt.starts = static_cast<int>(cfg.integer("roundtrip.starts"));
  const auto randomized = parameter_list("roundtrip.randomized");

  DiagnosisStudyResult res;
  res.synth = rt.synth;
  res.seed = rt.seed;
  res.range_scale = rt.range_scale;
  res.max_zero_deg = rt.max_zero_deg;

  // 2. Round trips.
  bool example_done = false;
  for (const auto& src : sources)
    for (const auto& a : arrays) {
      const ModelState base{Mount::from_config(cfg), probe_setup_from_config(cfg, a, "study.arrays")};
      RoundTripOptions o = rt;
      o.cases = src.cases;
      o.fd_step = src.label == "exact" ? 1e-4 : 1e-2;
      std::string note;
      if (o.free.empty()) {  // the default free set of this array, then randomize it (or the given list)
        std::mt19937 r0(o.seed);
        SyntheticOptions s0 = o.synth;
        s0.noise_deg = 0;
        s0.quant_positions = 0;
        // Chosen on the exact field (the physics; FE artefacts must not make confounded parameters look
        // separable), then fitted on this source.
        const std::vector<CurveInput> nominal{synthetic_curve(*sources.front().field, base, table_values(base, {}), s0, r0)};
        o.free = default_free_set(*sources.front().field, nominal, DiagnosisOptions{}, &note);
      }
      o.randomized = randomized.empty() ? o.free : randomized;
      RoundTripResult r = run_round_trip(*src.field, base, o);
      r.field = src.label;
      if (!note.empty()) r.default_free_note = note;
      res.trips.push_back(r);
      // Every parameter free on a few cases: what one curve cannot identify.
      // (exact field only: thirteen free parameters on an FE field take minutes per fit)
      const int nall = src.label == "exact" ? static_cast<int>(cfg.integer("roundtrip.all_free_cases")) : 0;
      res.all_free_starts = static_cast<int>(cfg.integer("roundtrip.all_free_starts"));
      if (nall > 0)
        res.all_free.push_back({src.label + " `" + a + "`", all_free_flags(*src.field, base, o, nall, res.all_free_starts)});
      // One example fit (the report plots it).
      if (!example_done) {
        example_fit(*src.field, base, o, res);
        example_done = true;
      }
    }

  // 3. Anomalies (constructed curves on the exact field).
  if (cfg.flag("anomalies.enabled")) res.anomalies = anomalies(cfg, arrays, *sources.front().field, rt.synth, rt.seed);
  return res;
}

}  // namespace magenc
