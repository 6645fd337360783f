#include "report/inspect_report.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {
nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  if (!out) throw InputError("cannot write " + p.string() + ": allowed a writable output directory");
}
}  // namespace

std::string inspect_json(const FieldScan& scan, const InspectResult& res, const InspectRunInfo& info) {
  const auto& table = inspect_parameters();
  nlohmann::json j;
  nlohmann::json params = nlohmann::json::object();
  for (int i = 0; i < kInspectParams; ++i)
    params[table[i].name] = {{"value", res.value[i]},
                             {"sigma", res.free[i] ? finite_or_null(res.sigma[i]) : nlohmann::json(0.0)},
                             {"free", bool(res.free[i])},
                             {"unit", table[i].unit},
                             {"identifiable", !res.free[i] || std::isfinite(res.sigma[i])}};
  j["parameters"] = params;
  j["residual_rms_mT"] = res.residual_rms_mT;
  j["not_identifiable"] = res.not_identifiable;
  j["free"] = res.free_names;
  nlohmann::json corr = nlohmann::json::array();
  for (Eigen::Index a = 0; a < res.correlation.rows(); ++a) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index b = 0; b < res.correlation.cols(); ++b) row.push_back(finite_or_null(res.correlation(a, b)));
    corr.push_back(row);
  }
  j["correlation"] = {{"names", res.free_names}, {"matrix", corr}};
  j["singular_values_normalised"] =
      std::vector<double>(res.singular_values.data(), res.singular_values.data() + res.singular_values.size());
  j["condition_number"] = finite_or_null(res.condition);
  j["n_readings"] = scan.p_mm.cols();
  j["iterations"] = res.iterations;
  j["scan"] = info.scan_file;
  j["scan_unit"] = info.unit;
  j["command_line"] = info.command_line;
  if (!info.config_json.empty()) j["config"] = nlohmann::json::parse(info.config_json);
  return j.dump(2) + "\n";
}

std::string inspect_csv(const FieldScan& scan, const InspectResult& res) {
  std::ostringstream os;
  os << "i,x_mm,y_mm,z_mm,Bx_measured_mT,By_measured_mT,Bz_measured_mT,Bx_fitted_mT,By_fitted_mT,Bz_fitted_mT,"
        "Bx_residual_mT,By_residual_mT,Bz_residual_mT\n";
  for (Eigen::Index j = 0; j < scan.p_mm.cols(); ++j) {
    os << j + 1;
    for (int k = 0; k < 3; ++k) os << "," << fmt_sig(scan.p_mm(k, j), 10);
    for (int k = 0; k < 3; ++k) os << "," << fmt_sig(1e3 * scan.B_T(k, j), 10);
    for (int k = 0; k < 3; ++k) os << "," << fmt_sig(1e3 * res.fitted_T(k, j), 10);
    for (int k = 0; k < 3; ++k) os << "," << fmt_sig(1e3 * (res.fitted_T(k, j) - scan.B_T(k, j)), 10);
    os << "\n";
  }
  return os.str();
}

std::string inspect_summary(const FieldScan& scan, const InspectResult& res, const InspectRunInfo& info) {
  const auto& table = inspect_parameters();
  std::ostringstream os;
  os << "# inspect: magnet and sensor pose from a field scan\n\n"
     << "Scan `" << info.scan_file << "`: " << scan.p_mm.cols() << " readings (field in " << info.unit
     << "). Command: `" << info.command_line << "`.\n\n"
     << "Model: reading = R^T B(nominal + offset), R = Rz(rot_z) Ry(rot_y) Rx(rot_x); B the exact field of the "
        "configured cylinder with the fitted polarization. Free groups: ";
  for (std::size_t i = 0; i < res.free_names.size(); ++i) os << (i ? ", " : "") << res.free_names[i];
  os << ".\n\n| parameter | value | 1 sigma | unit | free |\n| --- | ---: | ---: | --- | --- |\n";
  for (int i = 0; i < kInspectParams; ++i) {
    os << "| " << table[i].name << " | " << fmt_sig(res.value[i], 7) << " | "
       << (res.free[i] ? (std::isfinite(res.sigma[i]) ? fmt_sig(res.sigma[i], 3) : std::string("not identifiable"))
                       : std::string("fixed"))
       << " | " << table[i].unit << " | " << (res.free[i] ? "yes" : "no") << " |\n";
  }
  os << "\nResidual RMS " << fmt_sig(res.residual_rms_mT, 4) << " mT over " << 3 * scan.p_mm.cols()
     << " components; condition number of the column-normalised Jacobian " << fmt_sig(res.condition, 3) << ".\n";
  if (!res.not_identifiable.empty()) {
    os << "\nThe scan cannot separate: ";
    for (std::size_t i = 0; i < res.not_identifiable.size(); ++i) os << (i ? ", " : "") << res.not_identifiable[i];
    os << " (sigma infinite; scan at more heights or positions).\n";
  }
  os << "\n![measured vs fitted components](components.png)\n";
  return os.str();
}

void write_inspect_outputs(const std::filesystem::path& dir, const FieldScan& scan, const InspectResult& res,
                           const InspectRunInfo& info) {
  write_text(dir / "fit.json", inspect_json(scan, res, info));
  write_text(dir / "fit.csv", inspect_csv(scan, res));
  write_text(dir / "summary.md", inspect_summary(scan, res, info));
  write_text(dir / "config.toml", info.config_toml);
  PlotSpec spec;
  spec.title = "inspect: measured (points) and fitted (lines) components along the scan";
  spec.height_px = 900;
  const char* names[3] = {"B_x", "B_y", "B_z"};
  for (int k = 0; k < 3; ++k) {
    PlotPanel panel;
    panel.xlabel = "reading";
    panel.ylabel = std::string(names[k]) + " [mT]";
    PlotSeries meas{"measured", {}, {}, "points", "pt 7 ps 0.6"}, fit{"fitted", {}, {}, "lines", "lw 1.5"};
    for (Eigen::Index j = 0; j < scan.p_mm.cols(); ++j) {
      meas.x.push_back(double(j + 1));
      meas.y.push_back(1e3 * scan.B_T(k, j));
      fit.x.push_back(double(j + 1));
      fit.y.push_back(1e3 * res.fitted_T(k, j));
    }
    panel.series = {meas, fit};
    spec.panels.push_back(panel);
  }
  write_plot(dir, "components", spec);
}

}  // namespace magenc
