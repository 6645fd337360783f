#include "analysis/offset_sweeps.hpp"

#include <cmath>

#include "core/format.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_factory.hpp"

namespace magenc {

KeySpec study_arrays_key() {
  return string_list_key("study.arrays", {"two", "diff4", "ring:8"}, {}, "probe arrays (two, diff4, ring:N)");
}

std::vector<KeySpec> offset_sweep_keys(const std::string& reference_use) {
  return {
      int_key("sweep.points", 26, 4, 100000, "values per offset sweep (>= 4 for the cubic fit)"),
      real_key("sweep.max_mm", 0.5, 0, 100, "mm", "each offset is swept over 0..max_mm", true),
      real_key("sweep.reference_mm", 0.1, 0, 100, "mm", "offset of " + reference_use, true),
      string_list_key("sweep.offsets", {"sx_mm", "sy_mm", "dx_mm", "dy_mm"}, {},
                 "offsets swept one at a time from 0 (sx_mm, sy_mm, dx_mm, dy_mm, dz_mm)"),
      string_list_key("sweep.coefs", {"a0_deg", "a1_deg", "b1_deg", "a2_deg", "b2_deg", "c1_deg", "c2_deg", "c3_deg", "c4_deg"}, {},
                 "spectra columns fitted with a cubic"),
  };
}

std::vector<KeySpec> dz_sweep_keys(const std::string& start_note) {
  return {
      int_key("dz_sweep.points", 21, 4, 100000, "values of the air-gap sweep (>= 4 for the cubic fit)"),
      real_key("dz_sweep.min_mm", -0.5, -100, 100, "mm", "air-gap sweep start" + start_note),
      real_key("dz_sweep.max_mm", 0.5, -100, 100, "mm", "air-gap sweep end"),
  };
}

OffsetSweepOptions OffsetSweepOptions::from_config(const Config& cfg) {
  OffsetSweepOptions o;
  o.offsets = cfg.strings("sweep.offsets");
  o.coefs = cfg.strings("sweep.coefs");
  check_coef_names(o.coefs, "sweep.coefs");
  for (const auto& name : o.offsets) with_offset(Mount{}, name, 0.0);  // validates the names
  o.reference_mm = cfg.real("sweep.reference_mm");
  o.values_mm = linspace(0.0, cfg.real("sweep.max_mm"), static_cast<int>(cfg.integer("sweep.points")));
  return o;
}

const std::vector<PhysicsMdValue>& physics_md_linear_values() {
  static const std::vector<PhysicsMdValue> values = {
      {"sx_mm", "a0_deg", 1.169},  {"sx_mm", "a2_deg", 1.145},  {"sx_mm", "b2_deg", -1.193},
      {"sx_mm", "c2_deg", 1.653},  {"sx_mm", "c4_deg", 0.024},  {"sy_mm", "a0_deg", -1.169},
      {"sy_mm", "a2_deg", 1.145},  {"sy_mm", "b2_deg", 1.193},  {"dx_mm", "a1_deg", -2.387},
      {"dx_mm", "b1_deg", 2.387},  {"dx_mm", "c1_deg", 3.376},  {"dx_mm", "a2_deg", -0.099},
      {"dy_mm", "pp_deg", 0.0},
  };
  return values;
}

int LinearModelResult::physics_md_mismatches() const {
  int bad = 0;
  for (const auto& c : physics_md) bad += c.agrees ? 0 : 1;
  return bad;
}

LinearModelResult run_linear_model(const Config& cfg, const std::string& study) {
  LinearModelResult r;
  // 1. Inputs.
  const LinearField field;
  r.setup = probe_setup_from_config(cfg, cfg.str("sensor.array"));
  r.base = Mount::from_config(cfg);
  r.options = OffsetSweepOptions::from_config(cfg);
  const auto& o = r.options;

  // 2. Ideal mount, the sweeps with their fits, each offset alone at the reference value.
  r.ideal = angle_error(field, r.setup, r.base);
  for (const auto& name : o.offsets) {
    r.sweeps.push_back(run_sweep(field, r.setup, {offset_symbol(name), name, o.values_mm, r.base}));
    auto f = fit_sweep(r.sweeps.back(), study, o.coefs);
    r.fits.insert(r.fits.end(), f.begin(), f.end());
  }
  for (const auto& name : o.offsets)
    r.refs.push_back(angle_error(field, r.setup, with_offset(r.base, name, o.reference_mm)));

  // 3. docs/physics.md's sanity values, for their configuration only.
  const Mount& b = r.base;
  r.physics_md_applies = r.setup.array.name == "two" && std::abs(r.setup.r0_mm - 2.4) < 1e-12 &&
                         std::abs(o.reference_mm - 0.1) < 1e-12 && b.sx_mm == 0 && b.sy_mm == 0 && b.dx_mm == 0 &&
                         b.dy_mm == 0 && b.dz_mm == 0;
  if (r.physics_md_applies)
    for (const auto& ref : physics_md_linear_values())
      for (std::size_t i = 0; i < o.offsets.size(); ++i) {
        if (o.offsets[i] != ref.swept) continue;
        const double v = r.refs[i].spectrum.column(ref.coef);
        r.physics_md.push_back(
            {ref.swept, ref.coef, v, ref.value_deg, std::abs(v - ref.value_deg) <= kPhysicsMdToleranceDeg});
      }
  return r;
}

ExactFieldResult run_exact_field(const Config& cfg, const std::string& study) {
  ExactFieldResult r;
  // 1. Inputs.
  const FieldSourcePtr field = make_field_source(cfg.str("study.field"), cfg);
  const LinearField linear;
  r.field = field->name();
  r.base = Mount::from_config(cfg);
  const auto arrays = cfg.strings("study.arrays");
  r.options = OffsetSweepOptions::from_config(cfg);
  const auto& o = r.options;
  const double residual_dx_mm = cfg.real("dz_sweep.residual_dx_mm");
  r.dz_values_mm = linspace(cfg.real("dz_sweep.min_mm"), cfg.real("dz_sweep.max_mm"),
                            static_cast<int>(cfg.integer("dz_sweep.points")));
  r.dz_base = with_offset(r.base, "dx_mm", r.base.dx_mm + residual_dx_mm);
  const std::string dz_label = "dz (dx=" + fmt(r.dz_base.dx_mm, 2) + ")";
  ProbeArray::parse(cfg.str("sensor.array"));  // unused here (study.arrays), but still checked
  std::vector<ProbeSetup> setups;
  for (const auto& a : arrays) setups.push_back(probe_setup_from_config(cfg, a, "study.arrays"));
  r.floor_deg = cfg.real("summary.floor_deg");
  r.relative = cfg.real("summary.relative");

  // 2. Per array: ideal mount, sweeps, fits, reference cases (study field and linear field).
  for (const auto& setup : setups) {
    ArraySweeps a;
    a.setup = setup;
    a.ideal = angle_error(*field, setup, r.base);
    for (const auto& name : o.offsets)
      a.sweeps.push_back(run_sweep(*field, setup, {offset_symbol(name), name, o.values_mm, r.base}));
    a.sweeps.push_back(run_sweep(*field, setup, {dz_label, "dz_mm", r.dz_values_mm, r.dz_base}));
    for (const auto& s : a.sweeps) {
      auto f = fit_sweep(s, study, o.coefs);
      r.fits.insert(r.fits.end(), f.begin(), f.end());
    }
    for (const auto& name : o.offsets) {
      const Mount m = with_offset(r.base, name, o.reference_mm);
      a.refs.push_back({offset_symbol(name) + " = " + fmt(o.reference_mm, 2) + " mm", name, m,
                        angle_error(*field, setup, m), angle_error(linear, setup, m)});
    }
    const Mount m = with_offset(r.dz_base, "dz_mm", o.reference_mm);
    a.refs.push_back({"dz = " + fmt(o.reference_mm, 2) + ", dx = " + fmt(r.dz_base.dx_mm, 2) + " mm", "dz_mm", m,
                      angle_error(*field, setup, m), angle_error(linear, setup, m)});
    r.arrays.push_back(std::move(a));
  }
  return r;
}

}  // namespace magenc
