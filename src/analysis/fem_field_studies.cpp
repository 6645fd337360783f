#include "analysis/fem_field_studies.hpp"

#include <cmath>
#include <utility>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace magenc {

std::vector<KeySpec> acceptance_keys() {
  return {
      string_list_key("acceptance.arrays", {"two", "diff4"}, {}, "arrays the acceptance check covers"),
      string_list_key("acceptance.coefs", {"c1_deg", "c2_deg", "c3_deg", "c4_deg"}, {},
                 "coefficients the acceptance check covers (rule fixed: max(2 % of exact, 0.002 deg))"),
  };
}

int AcceptanceResult::judged() const {
  int n = 0;
  for (const auto& c : cells) n += c.judged ? 1 : 0;
  return n;
}

int AcceptanceResult::passed() const {
  int n = 0;
  for (const auto& c : cells) n += c.pass ? 1 : 0;
  return n;
}

AcceptanceResult judge_acceptance(const ComparisonRun& run, const std::vector<std::string>& arrays,
                                  const std::vector<std::string>& coefs, const AcceptanceRule& rule) {
  AcceptanceResult a{rule, arrays, coefs, {}};
  for (std::size_t k = 0; k < run.plan.points.size(); ++k)
    for (const auto& r : run.arrays) {
      bool judged = false;
      for (const auto& name : arrays) judged = judged || name == r.setup.array.name;
      for (const auto& f : r.fem)
        for (const auto& coef : coefs) {
          AcceptanceCell c;
          c.offset = k;
          c.array = r.setup.array.name;
          c.source = f.label;
          c.coef = coef;
          c.value_deg = f.points[k].spectrum.column(coef);
          c.exact_deg = r.exact.points[k].spectrum.column(coef);
          c.tolerance_deg = rule.tolerance_deg(c.exact_deg);
          c.judged = judged;
          c.pass = judged && rule.pass(c.value_deg, c.exact_deg);
          a.cells.push_back(c);
        }
    }
  return a;
}

RealFieldResult run_real_field(const Config& cfg, const std::string& study, FemSources fem) {
  RealFieldResult r;
  // 1. Inputs: the FEM sources (opened by the caller), the exact field, the arrays.
  r.inputs = comparison_inputs_from_config(cfg, std::move(fem));
  r.options = OffsetSweepOptions::from_config(cfg);
  const auto acc_arrays = cfg.strings("acceptance.arrays");
  const auto acc_coefs = cfg.strings("acceptance.coefs");
  check_coef_names(acc_coefs, "acceptance.coefs");
  for (const auto& o : r.options.offsets)
    if (o == "dz_mm") throw InputError("sweep.offsets: dz_mm is the airgap study's (plane.vti has no dz)");
  r.solve_mu_r = r.inputs.solve_mu_r;
  r.interp = cfg.str("fem_field.interp");

  // 2. Per array, on every FEM source and on the exact field: the ideal mount, each
  //    offset at the reference value (points) and swept (sweeps, with fits).
  const auto& o = r.options;
  ComparisonPlan plan{study, {}, o.coefs, r.inputs.base, {}};
  for (const auto& name : o.offsets) {
    plan.sweeps.push_back({offset_symbol(name), name, o.values_mm, r.inputs.base});
    plan.points.push_back(with_offset(r.inputs.base, name, o.reference_mm));
  }
  r.run = run_comparison(r.inputs.sources, *r.inputs.exact, r.inputs.setups, plan);

  // 3. The acceptance rule, deliberately not configurable.
  r.acceptance = judge_acceptance(r.run, acc_arrays, acc_coefs, AcceptanceRule{});
  return r;
}

AirgapResult run_airgap(const Config& cfg, const std::string& study, FemSources fem) {
  AirgapResult r;
  // 1. Inputs.
  r.inputs = comparison_inputs_from_config(cfg, std::move(fem));
  const auto coefs = cfg.strings("dz_sweep.coefs");
  check_coef_names(coefs, "dz_sweep.coefs");
  if (!(cfg.real("dz_sweep.max_mm") > cfg.real("dz_sweep.min_mm")))
    throw InputError("dz_sweep.max_mm must be > dz_sweep.min_mm");
  r.dz_mm = linspace(cfg.real("dz_sweep.min_mm"), cfg.real("dz_sweep.max_mm"),
                     static_cast<int>(cfg.integer("dz_sweep.points")));
  r.residual_sx_mm = cfg.real("residual.sx_mm");
  r.residual_dx_mm = cfg.real("residual.dx_mm");
  r.solve_mu_r = r.inputs.solve_mu_r;
  r.interp = cfg.str("fem_field.interp");
  const Mount& base = r.inputs.base;
  const Mount with_sx = with_offset(base, "sx_mm", base.sx_mm + r.residual_sx_mm);
  const Mount with_dx = with_offset(base, "dx_mm", base.dx_mm + r.residual_dx_mm);
  const Mount with_both = with_offset(with_sx, "dx_mm", base.dx_mm + r.residual_dx_mm);
  const std::string sx_text = "sx=" + fmt(r.residual_sx_mm, 2), dx_text = "dx=" + fmt(r.residual_dx_mm, 2);
  r.cases = {{"dz alone", "alone", "none", base},
             {"dz with " + sx_text, "sx", sx_text, with_sx},
             {"dz with " + dx_text, "dx", dx_text, with_dx},
             {"dz with " + sx_text + " " + dx_text, "sxdx", sx_text + " " + dx_text, with_both}};
  for (const auto& c : coefs)
    if (c != "pp_deg" && c != "a0_deg") r.diff_coefs.push_back(c);

  // 2. Every case on every source and on the exact field; fits in dz.
  ComparisonPlan plan{study, {}, coefs, std::nullopt, {}};
  for (const auto& c : r.cases) plan.sweeps.push_back({c.label, "dz_mm", r.dz_mm, c.base});
  r.run = run_comparison(r.inputs.sources, *r.inputs.exact, r.inputs.setups, plan);

  // 3. eps(theta) of the sx+dx case at the sweep ends and dz = 0 (nearest value), first FEM source.
  std::size_t i0 = 0;
  for (std::size_t i = 0; i < r.dz_mm.size(); ++i)
    if (std::abs(r.dz_mm[i]) < std::abs(r.dz_mm[i0])) i0 = i;
  r.eps_index[0] = 0;
  r.eps_index[1] = i0;
  r.eps_index[2] = r.dz_mm.size() - 1;
  for (const auto& a : r.run.arrays) {
    std::vector<AngleErrorResult> e;
    for (std::size_t i : r.eps_index)
      e.push_back(angle_error(*r.inputs.sources.front().field, a.setup,
                              with_offset(r.cases.back().base, "dz_mm", r.dz_mm[i])));
    r.eps.push_back(std::move(e));
  }
  return r;
}

}  // namespace magenc
