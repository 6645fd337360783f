#include "studies/error_sources/error_sources_engine.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/errors.hpp"
#include "fields/field_factory.hpp"

namespace magenc {

const std::vector<ErrorSource>& error_sources() {
  static const std::vector<ErrorSource> s = {
      {"tilt_x_deg", "mount.tilt_x_deg", "tilt_x", "sensor tilt about x", "deg", false, "sweep.tilt_max_deg"},
      {"tilt_y_deg", "mount.tilt_y_deg", "tilt_y", "sensor tilt about y", "deg", false, "sweep.tilt_max_deg"},
      {"magnet_tilt_deg", "mount.magnet_tilt_deg", "magnet tilt", "magnet tilt (azimuth as configured)", "deg", false,
       "sweep.magnet_tilt_max_deg"},
      {"magnetization_elevation_deg", "magnet.magnetization_elevation_deg", "elevation",
       "magnetization elevation", "deg", true, "sweep.elevation_max_deg"},
      {"offset_cos_mT", "sensor.offset_cos_mT", "o_c", "offset of the cos channel", "mT", false, "sweep.offset_max_mT"},
      {"offset_sin_mT", "sensor.offset_sin_mT", "o_s", "offset of the sin channel", "mT", false, "sweep.offset_max_mT"},
      {"offset_cos_rel", "sensor.offset_cos_rel", "o_{c,rel}", "relative offset of the cos channel (xmr, amr)", "", false,
       "sweep.offset_max_rel"},
      {"offset_sin_rel", "sensor.offset_sin_rel", "o_{s,rel}", "relative offset of the sin channel (xmr, amr)", "", false,
       "sweep.offset_max_rel"},
      {"gain_mismatch", "sensor.gain_mismatch", "g", "gain mismatch of the sin channel", "", false, "sweep.gain_max"},
      {"phase_error_deg", "sensor.phase_error_deg", "{/Symbol d}", "phase error of the sin channel", "deg", false, "sweep.phase_max_deg"},
  };
  return s;
}

const ErrorSource& find_error_source(const std::string& swept, const std::string& what) {
  std::string allowed;
  for (const auto& s : error_sources()) {
    if (s.swept == swept) return s;
    allowed += (allowed.empty() ? "" : ", ") + s.swept;
  }
  throw InputError(what + ": '" + swept + "' is not an error source: allowed " + allowed);
}

std::vector<KeySpec> error_source_sweep_keys() {
  return {
      int_key("sweep.points", 11, 4, 100000, "values per source sweep, 0..max (>= 4 for the cubic fit)"),
      real_key("sweep.tilt_max_deg", 2.0, 0, 10, "deg", "sensor tilts tilt_x, tilt_y swept over 0..this", true),
      real_key("sweep.magnet_tilt_max_deg", 2.0, 0, 10, "deg", "magnet tilt swept over 0..this", true),
      real_key("sweep.elevation_max_deg", 5.0, 0, 45, "deg", "magnetization elevation swept over 0..this", true),
      real_key("sweep.offset_max_mT", 1.0, 0, 100, "mT", "channel offsets o_c, o_s swept over 0..this", true),
      real_key("sweep.offset_max_rel", 0.02, 0, 1, "",
               "relative channel offsets of xmr/amr swept over 0..this (fraction of the amplitude)", true),
      real_key("sweep.gain_max", 0.02, 0, 0.5, "", "gain mismatch g swept over 0..this (fraction)", true),
      real_key("sweep.phase_max_deg", 2.0, 0, 20, "deg", "phase error delta swept over 0..this", true),
  };
}

std::string source_axis_label(const ErrorSource& src) {
  return src.symbol + " [" + (src.unit.empty() ? std::string("1") : src.unit) + "]";
}

namespace {
std::string num_text(double v) {
  std::ostringstream os;
  os << std::setprecision(12) << v;
  return os.str();
}
}  // namespace

SweepResult run_source_sweep(const Config& cfg, const std::string& field_spec, const FieldSource& field,
                             const ProbeSetup& base_setup, const ErrorSource& src, const std::vector<double>& values) {
  if (values.empty()) throw InputError("sweep of " + src.swept + " has no values");
  if (src.changes_field && field_spec != "analytic")
    throw InputError("study.field = '" + field_spec + "' cannot follow " + src.swept +
                     " (it changes the magnet, so the field): allowed analytic for this source");
  SweepResult res;
  res.spec.label = src.symbol;
  res.spec.swept = src.swept;
  res.spec.values_mm = values;
  res.spec.base = Mount::from_config(cfg);
  res.field = field.name();
  res.setup = base_setup;
  for (double v : values) {
    // 1. The configuration with this source at v (range-checked by the key's declaration).
    Config c = cfg;
    c.set_value(src.key, v);
    // 2. Mount and signal chain from it; the field rebuilt only when the source changes the magnet.
    ProbeSetup s = base_setup;
    s.chain = SignalChain::from_config(c);
    const Mount m = Mount::from_config(c);
    FieldSourcePtr own;
    if (src.changes_field) own = make_field_source(field_spec, c);
    const FieldSource& f = own ? *own : field;
    // 3. One spectra row.
    SpectrumRow row;
    row.field = f.name();
    row.array = s.array.name;
    row.r0_mm = s.r0_mm;
    row.mount = m;
    row.spectrum = error_spectrum(f, s, m);
    row.extra = {{"sweep", src.symbol}, {"swept", src.swept}, {"value", num_text(v)},
                 {"principle", principle_name(s.principle)}};
    res.rows.push_back(std::move(row));
  }
  return res;
}

ErrorSourcesRun run_error_sources(const Config& cfg, const std::vector<ProbeSetup>& setups, const std::string& study) {
  ErrorSourcesRun run;
  // 1. Inputs (all checked before any work).
  run.field_spec = cfg.str("study.field");
  const FieldSourcePtr field = make_field_source(run.field_spec, cfg);
  run.field = field->name();
  run.setups = setups;
  for (const auto& name : cfg.strings("study.sources")) {
    const ErrorSource& src = find_error_source(name, "study.sources");
    if (src.changes_field && run.field_spec != "analytic")
      throw InputError("study.sources: " + src.swept + " changes the magnet, which study.field = '" + run.field_spec +
                       "' cannot follow: allowed analytic (or drop " + src.swept + ")");
    run.sources.push_back(&src);
  }
  run.coefs = cfg.strings("sweep.coefs");
  run.sweep_points = cfg.integer("sweep.points");
  run.floor_deg = cfg.real("summary.floor_deg");
  run.relative = cfg.real("summary.relative");
  check_coef_names(run.coefs, "sweep.coefs");
  const int points = static_cast<int>(cfg.integer("sweep.points"));
  // 2. Each source alone on each array; cubic fits.
  for (const ErrorSource* src : run.sources) {
    const auto values = linspace(0.0, cfg.real(src->range_key), points);
    std::vector<SweepResult> per_array;
    for (const auto& setup : setups) {
      if (!source_applies(*src, setup.principle)) {  // e.g. an mT offset on xmr: an empty sweep marks it
        SweepResult none;
        none.spec.label = src->symbol;
        none.spec.swept = src->swept;
        none.field = field->name();
        none.setup = setup;
        per_array.push_back(std::move(none));
        continue;
      }
      per_array.push_back(run_source_sweep(cfg, run.field_spec, *field, setup, *src, values));
      const auto f = fit_sweep(per_array.back(), study, run.coefs);
      run.fits.insert(run.fits.end(), f.begin(), f.end());
    }
    run.sweeps.push_back(std::move(per_array));
  }
  return run;
}

bool source_applies(const ErrorSource& src, SensorPrinciple p) {
  if (src.key == "sensor.offset_cos_mT" || src.key == "sensor.offset_sin_mT") return !relative_offsets(p);
  if (src.key == "sensor.offset_cos_rel" || src.key == "sensor.offset_sin_rel") return relative_offsets(p);
  return true;
}

std::string sensor_label(const ProbeSetup& s) {
  return reads_in_plane(s.principle) ? principle_name(s.principle) : s.array.name;
}

HarmonicSignature harmonic_signature(const SweepResult& sweep, double value) {
  if (sweep.rows.empty()) throw InputError("harmonic signature of an empty sweep");
  std::size_t k = sweep.rows.size() - 1;
  if (std::isfinite(value)) {
    for (std::size_t i = 0; i < sweep.rows.size(); ++i)
      if (std::abs(sweep.spec.values_mm[i] - value) < std::abs(sweep.spec.values_mm[k] - value)) k = i;
  }
  HarmonicSignature h;
  h.swept = sweep.spec.swept;
  h.array = sensor_label(sweep.setup);
  h.value = sweep.spec.values_mm[k];
  const Spectrum& s = sweep.rows[k].spectrum;
  h.c_deg[0] = std::abs(s.a0_deg);
  for (int n = 1; n <= 8; ++n) h.c_deg[n] = s.c_deg[n];
  h.pp_deg = s.pp_deg;
  return h;
}

}  // namespace magenc
