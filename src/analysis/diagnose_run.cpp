#include "analysis/diagnose_run.hpp"

#include "analysis/measured_curve.hpp"
#include "analysis/sweep.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/field_io/solved_field.hpp"
#include "fields/field_factory.hpp"
#include "probe/mounting.hpp"

namespace magenc {

DiagnoseRun run_diagnose(const DiagnoseRequest& req, const Config& cfg) {
  if (!(req.max_gap_deg > 0 && req.max_gap_deg <= 180))
    throw InputError(req.max_gap_name + " " + num(req.max_gap_deg) + " is out of range: allowed (0, 180] deg");
  if (req.measured.empty()) throw InputError("measured: no curve files: allowed one path or a list of paths");
  CurveReadOptions ro;
  ro.error_sign = req.error_sign;
  ro.max_gap_deg = req.max_gap_deg;
  const ModelState base{Mount::from_config(cfg), probe_setup_from_config(cfg, cfg.str("sensor.array"), req.array_name)};
  DiagnoseRun run;
  for (const auto& path : req.measured) run.curves.push_back({read_measured_curve(path, ro), base, {}});
  for (const auto& cs : req.curve_sets) {
    const auto [c, o] = parse_curve_set(cs, static_cast<int>(run.curves.size()));
    run.curves[c].overrides.push_back(o);
  }
  DiagnosisOptions& opts = run.options;
  opts.free = req.free;
  for (const auto& n : expand_free_names(opts.free)) fit_parameter(n);  // unknown: one-line error
  opts.free_zero = !req.fixed_zero;
  opts.starts = req.starts;
  opts.seed = req.seed;
  opts.cond_limit = req.cond_limit;
  FieldOptions fo;
  fo.interp = parse_interp(req.interp, "interp");
  const FieldSourcePtr field = open_field_source(req.field, cfg, fo);
  // On a discretised field (fem:, grid:, table:) the Jacobian takes a larger step (1e-2 typical sizes, see
  // DiagnosisOptions::fd_step), and the default free set is chosen on the exact field of the same magnet.
  FieldSourcePtr exact;
  if (field->name() != "analytic" && field->name() != "linear") {
    exact = make_field_source("analytic", cfg);
    opts.identifiability_field = exact.get();
    opts.fd_step = req.fd_step > 0 ? req.fd_step : 1e-2;
  } else if (req.fd_step > 0) {
    opts.fd_step = req.fd_step;
  }
  run.result = diagnose_curves(*field, run.curves, opts);
  opts.identifiability_field = nullptr;
  if (!run.result.unexplained.empty()) throw ComputeError(run.result.unexplained);
  return run;
}

}  // namespace magenc
