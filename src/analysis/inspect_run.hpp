// What the inspect executable and the Python module's inspect() do between reading their arguments and
// writing their outputs (docs/interfaces.md "inspect"): read the scan, parse the free groups, check the
// condition limit and fit the magnet's polarization and the sensor's pose (analysis/inspect_fit.hpp).
#pragma once
#include <string>

#include "analysis/inspect_fit.hpp"
#include "core/config.hpp"

namespace magenc {

struct InspectRequest {
  std::string scan_file;                              // x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT (or _T)
  std::string free = "offset,rotation,polarization";  // free groups
  double cond_limit = 1e6;                            // (1, inf)
  // The names the caller's user knows the options by, for one-line errors.
  std::string free_name = "--free";
  std::string cond_limit_name = "--cond-limit";
};

struct InspectRun {
  FieldScan scan;     // positions (mm) and readings (T)
  std::string unit;   // "mT" or "T": the scan's field columns
  InspectResult result;
};

// InputError (one line naming the option) for a bad condition limit, unknown groups or a bad scan file,
// all before the fit.
InspectRun run_inspect(const InspectRequest& req, const Config& cfg);

}  // namespace magenc
