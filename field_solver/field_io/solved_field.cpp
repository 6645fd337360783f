#include "field_solver/field_io/solved_field.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/grid_field.hpp"

namespace magenc {

namespace fs = std::filesystem;

namespace {

// DIR/solve.json, or null when there is none. A file that is there but is not a JSON object (truncated,
// corrupted) is an InputError, not a silently skipped check.
nlohmann::json read_record(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nullptr;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object()) throw InputError(file.string() + ": not a JSON object (expected solve_field's record)");
  return j;
}

// A number of the record (NaN when absent); InputError when present with another type.
double json_number(const nlohmann::json& obj, const char* key, const fs::path& file) {
  if (!obj.is_object() || !obj.contains(key)) return std::numeric_limits<double>::quiet_NaN();
  const auto& v = obj.at(key);
  if (!v.is_number()) throw InputError(file.string() + ": '" + key + "' is not a number (expected solve_field's record)");
  return v.get<double>();
}

// nlohmann's get<int>/get<long> static_casts a stored double (1e300 -> undefined behaviour): integers of
// the record are read through this range check instead.
long json_integer(const nlohmann::json& j, const char* key, long fallback, bool required, long lo, long hi) {
  if (!j.contains(key)) {
    if (required) throw std::out_of_range(std::string("key '") + key + "' not found");
    return fallback;
  }
  const auto& v = j.at(key);
  if (!v.is_number_integer() || v.get<double>() < double(lo) || v.get<double>() > double(hi))
    throw std::out_of_range(std::string("'") + key + "' is not an integer in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]");
  return v.get<long>();
}

}  // namespace

bool SolvedFieldDir::has_record() const { return fs::exists(record_file()); }

std::string SolvedFieldDir::mismatch(const Config& cfg) const {
  const fs::path file = record_file();
  const nlohmann::json j = read_record(file);
  if (j.is_null() || !j.contains("magnet")) return "";
  if (!j["magnet"].is_object())
    throw InputError(file.string() + ": 'magnet' is not an object (expected solve_field's record)");
  const auto differs = [](double a, double b) { return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b)); };
  for (const char* k : {"radius_mm", "height_mm", "br_T"}) {
    const double solved = json_number(j["magnet"], k, file);
    const double want = cfg.real(std::string("magnet.") + k);
    if (differs(solved, want))
      return "was solved with magnet." + std::string(k) + " = " + fmt(solved, 4) + ", the study uses " + fmt(want, 4) +
             ": solve again with the study's [magnet] keys";
  }
  {  // solid cylinders are recorded without the key
    const double solved = j["magnet"].contains("inner_radius_mm") ? json_number(j["magnet"], "inner_radius_mm", file) : 0.0;
    const double want = cfg.has("magnet.inner_radius_mm") ? cfg.real("magnet.inner_radius_mm") : 0.0;
    if (differs(solved, want))
      return "was solved with magnet.inner_radius_mm = " + fmt(solved, 4) + ", the study uses " + fmt(want, 4) +
             ": solve again with the study's [magnet] keys";
  }
  {  // solves written before the key existed had no elevation
    const double solved = j["magnet"].value("magnetization_elevation_deg", 0.0);
    const double want = cfg.real("magnet.magnetization_elevation_deg");
    if (differs(solved, want))
      return "was solved with magnet.magnetization_elevation_deg = " + fmt(solved, 4) + ", the study uses " +
             fmt(want, 4) + ": solve again with the study's [magnet] keys";
  }
  {  // uniform magnets are recorded without the pattern keys
    const nlohmann::json& m = j["magnet"];
    if (m.contains("pattern") && !m["pattern"].is_string())
      throw InputError(file.string() + ": 'pattern' is not a string (expected solve_field's record)");
    const std::string solved = m.contains("pattern") ? m["pattern"].get<std::string>() : std::string("uniform");
    const std::string want = cfg.has("magnet.pattern") ? cfg.str("magnet.pattern") : "uniform";
    long solved_p = 1;
    try {
      solved_p = json_integer(m, "pole_pairs", 1, false, 1, 100000);
    } catch (const std::out_of_range& e) {
      throw InputError(file.string() + ": " + e.what() + " (expected solve_field's record)");
    }
    const long want_p = cfg.has("magnet.pole_pairs") ? cfg.integer("magnet.pole_pairs") : 1L;
    if (solved != want || (want != "uniform" && want != "radial" && solved_p != want_p))
      return "was solved with magnet.pattern = " + solved + " (pole_pairs " + std::to_string(solved_p) +
             "), the study uses " + want + " (pole_pairs " + std::to_string(want_p) + "): solve again with the study's [magnet] keys";
  }
  if (j.contains("plane_z_mm")) {
    const double solved = json_number(j, "plane_z_mm", file);
    const double want = 0.5 * cfg.real("magnet.height_mm") + cfg.real("sensor.plane_height_mm");
    if (differs(solved, want))
      return "has its sensing plane at z = " + fmt(solved, 4) + " mm, the study uses z_s = " + fmt(want, 4) +
             " mm (sensor.plane_height_mm)";
  }
  return "";
}

void SolvedFieldDir::require_complete_solve_of(const Config& cfg, const std::string& key) const {
  const std::string d = dir_.string();
  if (const std::string why = mismatch(cfg); !why.empty()) throw InputError(key + ": '" + d + "' " + why);
  for (const char* f : {"mesh.vtu", "plane.vti", "solve.json"})
    if (!fs::exists(dir_ / f))
      throw InputError(key + ": '" + d + "' has no " + f +
                       ": run solve_field first (solve_field --set output.mesh_vtu=true --out " + d + ")");
}

FeSolveFacts SolvedFieldDir::facts() const {
  const fs::path file = record_file();
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open (a solve_field output directory has one)");
  FeSolveFacts f;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (!j.is_object()) throw std::invalid_argument("not a JSON object");
    const long big = 1L << 50;
    f.order = static_cast<int>(json_integer(j, "order", 0, true, 1, 2));
    f.elements = json_integer(j, "elements", 0, true, 0, big);
    f.dofs = json_integer(j, "dofs", 0, true, 0, big);
    f.iterations = json_integer(j, "iterations", 0, false, 0, big);
    f.t_total_s = j.value("t_total_s", NAN);
    f.mu_r = j.contains("magnet") ? j["magnet"].value("mu_r", NAN) : NAN;
    if (j.contains("domain")) {
      const auto& d = j["domain"];
      f.h_magnet_mm = d.value("h_magnet_mm", NAN);
      f.h_zone_mm = d.value("h_zone_mm", NAN);
      f.h_core_mm = d.contains("zone") ? d["zone"].value("h_core_mm", 0.0) : 0.0;
      f.symmetry_order = static_cast<int>(
          json_integer(d, "symmetry_order", d.value("symmetric", false) ? 2 : 1, false, 1, 64));
    }
    f.plane_step_mm = j.contains("plane_grid") ? j["plane_grid"].value("step_mm", NAN) : NAN;
  } catch (const std::exception& e) {
    throw InputError(file.string() + ": unreadable solve record (" + std::string(e.what()) + ")");
  }
  return f;
}

std::string SolvedFieldDir::description() const {
  std::ostringstream s;
  try {
    const nlohmann::json j = read_record(record_file());
    if (j.is_null() || j.empty()) return "";
    const long big = 1L << 50;
    s << "order " << json_integer(j, "order", 0, false, 0, 2) << ", " << json_integer(j, "elements", 0, false, 0, big)
      << " tetrahedra, " << json_integer(j, "dofs", 0, false, 0, big) << " dofs";
    if (j.contains("domain")) {
      const auto& d = j["domain"];
      s << ", " << json_integer(d, "segments", 0, false, 0, 1L << 30) << " segments on the curved face, h_zone " << fmt(d.value("h_zone_mm", 0.0), 3)
        << " mm, outer radius " << fmt(d.value("outer_radius_mm", 0.0), 1) << " mm";
    }
    if (j.contains("magnet")) s << ", magnet mu_r " << fmt(j["magnet"].value("mu_r", 0.0), 3);
    if (j.contains("plane_grid")) s << ", plane grid step " << fmt(j["plane_grid"].value("step_mm", 0.0), 3) << " mm";
    if (j.contains("box_grid")) s << ", box grid step " << fmt(j["box_grid"].value("step_mm", 0.0), 3) << " mm";
    s << ", solve " << fmt(j.value("t_total_s", 0.0), 1) << " s";
  } catch (...) {
    return "";
  }
  return s.str();
}

double SolvedFieldDir::mu_r() const {
  const fs::path file = record_file();
  const nlohmann::json j = read_record(file);
  if (j.is_null() || !j.contains("magnet")) return std::numeric_limits<double>::quiet_NaN();
  return json_number(j["magnet"], "mu_r", file);
}

std::shared_ptr<const FemField> SolvedFieldDir::fem() const { return std::make_shared<const FemField>(dir_); }

FieldSourcePtr open_field_source(const std::string& spec, const Config& cfg, const FieldOptions& opts) {
  if (spec.rfind("fem:", 0) != 0) return make_field_source(spec, cfg, opts);
  const std::string dir = spec.substr(4);
  if (dir.empty()) throw InputError("--field fem: needs a directory: fem:DIR (a solve_field output, e.g. output/field)");
  try {
    return SolvedFieldDir(dir).fem();
  } catch (const InputError& e) {
    throw InputError("--field fem:" + dir + ": " + e.what());
  }
}

}  // namespace magenc
