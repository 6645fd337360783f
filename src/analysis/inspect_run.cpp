#include "analysis/inspect_run.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/magnet.hpp"
#include "io/points_csv.hpp"

namespace magenc {

InspectRun run_inspect(const InspectRequest& req, const Config& cfg) {
  if (!(req.cond_limit > 1 && std::isfinite(req.cond_limit)))
    throw InputError(req.cond_limit_name + " " + num(req.cond_limit) + " is out of range: allowed (1, inf)");
  const Magnet magnet = Magnet::from_config(cfg);
  InspectOptions opts;
  opts.groups = parse_inspect_groups(req.free, req.free_name);
  opts.cond_limit = req.cond_limit;
  const ScanTable table = read_scan_csv(req.scan_file, field_table_limits(cfg));
  InspectRun run{FieldScan{table.p_mm, table.B_T}, table.unit, {}};
  run.result = inspect_scan(magnet, run.scan, opts);
  return run;
}

}  // namespace magenc
