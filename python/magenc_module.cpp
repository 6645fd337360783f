// The Python module `magenc` (docs/interfaces.md "Python module"): numpy in, numpy out, the names and units of
// the executables. Wiring only, like apps/: configuration -> library -> numbers.
//   field_at(points_mm, field, config, interp, **keys)      B (T) at (N, 3) points in the magnet frame
//   angle_error(field, array, config, interp, **keys)       (theta_deg, eps_deg) of the configured mount
//   spectrum(eps_deg)                                       the spectra table's coefficients
//   diagnose(measured, field, array, r0_mm, free, ...)      diagnose's fit.json as a dict
//   inspect(scan, free, config, **keys)                     inspect's fit.json as a dict
//   calibrate(measured, correction, method, apply, ...)     the correction and the residual after it
//   config_keys()                                           every key: default, allowed range, unit, help
// Keys come as a dict {"mount.sx_mm": 0.1} and/or keyword arguments (mount_sx_mm=0.1 or
// **{"mount.sx_mm": 0.1}), checked by the executables' schema (core/config); InputError -> ValueError
// with the same one-line message.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "analysis/calibrate_run.hpp"
#include "analysis/calibration_file.hpp"
#include "analysis/diagnose_run.hpp"
#include "analysis/inspect_run.hpp"
#include "analysis/measured_curve.hpp"
#include "analysis/sweep.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "fields/field_at.hpp"
#include "fields/field_factory.hpp"
#include "fields/magnet.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "probe/mounting.hpp"
#include "probe/spectrum.hpp"
#include "io/points_csv.hpp"
#include "report/diagnosis_report.hpp"
#include "report/inspect_report.hpp"
#include "field_solver/field_io/solved_field.hpp"

namespace py = pybind11;
using magenc::Config;
using magenc::InputError;

namespace {

// A Python value as the text --set takes: numbers with 17 significant digits (integers as all their digits,
// so the configuration's range check names a 10**30), bool and numpy.bool_ as true/false, lists as TOML
// arrays, dicts as TOML inline tables ({"mount.sx_mm": 0.1} -> {mount.sx_mm = 0.1}: keys such as
// calibration.at), strings as they are. A str is not a number (numeric keys refuse it), a complex number is
// refused, and so is a line break inside a string (a value is one line).
bool is_numpy_bool(const py::handle& v) {
  const py::object np = py::module_::import("numpy");
  return py::isinstance(v, np.attr("bool_"));
}

std::string value_text(const py::handle& v, const std::string& key, bool in_list = false) {
  const auto refuse = [&](const std::string& why) {
    return InputError(key + " = " + py::repr(v).cast<std::string>() + " " + why);
  };
  if (py::isinstance<py::bool_>(v) || is_numpy_bool(v)) return py::bool_(py::reinterpret_borrow<py::object>(v)) ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v.cast<double>());
    return buf;
  }
  if (py::isinstance<py::str>(v)) {
    const std::string s = v.cast<std::string>();
    if (s.find_first_of("\r\n") != std::string::npos) throw refuse("holds a line break: allowed a value of one line");
    return in_list ? "\"" + s + "\"" : s;
  }
  if (py::isinstance<py::dict>(v)) {
    std::string out = "{";
    bool first = true;
    for (const auto& [k, e] : v.cast<py::dict>()) {
      const std::string name = py::str(k).cast<std::string>();
      out += (first ? "" : ", ") + name + " = " + value_text(e, key + "." + name, true);
      first = false;
    }
    return out + "}";
  }
  if (py::isinstance<py::sequence>(v) || py::isinstance<py::array>(v)) {
    std::string out = "[";
    bool first = true;
    for (const auto& e : py::iter(v)) {
      out += (first ? "" : ", ") + value_text(e, key, true);
      first = false;
    }
    return out + "]";
  }
  if (PyComplex_Check(v.ptr()) || py::isinstance(v, py::module_::import("numpy").attr("complexfloating")))
    throw refuse("is a complex number: allowed a real number");
  if (py::isinstance(v, py::module_::import("numpy").attr("integer"))) return py::str(py::int_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
  if (py::hasattr(v, "__float__")) return value_text(py::float_(py::reinterpret_borrow<py::object>(v)), key, in_list);
  throw refuse("has no configuration form: allowed a number, bool, string, list or dict");
}

// A str value for a numeric or boolean key is refused (the configuration would read '0.1' as 0.1).
void check_value_kind(const Config& cfg, const std::string& key, const py::handle& v) {
  if (!py::isinstance<py::str>(v)) return;
  for (const auto& s : cfg.schema()) {
    if (s.key != key) continue;
    using T = magenc::KeySpec::Type;
    if (s.type == T::Real || s.type == T::Int || s.type == T::Bool)
      throw InputError(key + " = " + py::repr(v).cast<std::string>() + " is a str: allowed a " +
                       (s.type == T::Bool ? "bool" : "number") + " (not its text)");
  }
}

// The functions' own arguments, checked here so that a wrong type is one line naming the argument (TypeError)
// and a number beyond its range one line too (ValueError), not pybind11's list of signatures.
std::string repr_of(const py::handle& o) { return py::repr(o).cast<std::string>(); }

std::string text_arg(const py::handle& o, const char* name) {
  if (!py::isinstance<py::str>(o))
    throw py::type_error(std::string(name) + " = " + repr_of(o) + " is not a str: allowed text, e.g. " + name + "='...'");
  const std::string s = o.cast<std::string>();
  if (s.find_first_of("\r\n") != std::string::npos)
    throw InputError(std::string(name) + " = " + repr_of(o) + " holds a line break: allowed one line");
  return s;
}

long long int_arg(const py::handle& o, const char* name, long long lo, long long hi) {
  const bool integer = (py::isinstance<py::int_>(o) && !py::isinstance<py::bool_>(o)) ||
                       py::isinstance(o, py::module_::import("numpy").attr("integer"));
  if (!integer) throw py::type_error(std::string(name) + " = " + repr_of(o) + " is not an int: allowed an integer");
  const py::int_ v = py::reinterpret_borrow<py::object>(o);
  if (v < py::int_(lo) || v > py::int_(hi))
    throw InputError(std::string(name) + " = " + repr_of(o) + " is out of range: allowed [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
  return v.cast<long long>();
}

double real_arg(const py::handle& o, const char* name) {
  const py::object np = py::module_::import("numpy");
  const bool real = (py::isinstance<py::float_>(o) || py::isinstance<py::int_>(o) || py::isinstance(o, np.attr("floating")) ||
                     py::isinstance(o, np.attr("integer"))) &&
                    !py::isinstance<py::bool_>(o);
  if (!real) throw py::type_error(std::string(name) + " = " + repr_of(o) + " is not a real number: allowed an int or float");
  if (py::isinstance<py::int_>(o) && (py::reinterpret_borrow<py::int_>(o) > py::int_(1LL << 53) ||
                                      py::reinterpret_borrow<py::int_>(o) < py::int_(-(1LL << 53))))
    throw InputError(std::string(name) + " = " + repr_of(o) + " is out of range: allowed |value| <= 2**53");
  return py::float_(py::reinterpret_borrow<py::object>(o)).cast<double>();
}

bool bool_arg(const py::handle& o, const char* name) {
  if (!py::isinstance<py::bool_>(o) && !is_numpy_bool(o))
    throw py::type_error(std::string(name) + " = " + repr_of(o) + " is not a bool: allowed True or False");
  return py::bool_(py::reinterpret_borrow<py::object>(o));
}

// A number argument that becomes a key (r0_mm): a real number, as its --set text.
std::string number_key_text(const py::handle& o, const char* name) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", real_arg(o, name));
  return buf;
}

// A keyword name (mount_sx_mm) or a dotted key (mount.sx_mm) -> the dotted key of the schema.
std::string key_of(const Config& cfg, const std::string& name) {
  if (name.find('.') != std::string::npos) return name;
  std::string match;
  for (const auto& s : cfg.schema()) {
    std::string flat = s.key;
    const auto dot = flat.find('.');
    if (dot != std::string::npos) flat[dot] = '_';
    if (flat == name) match = s.key;
  }
  if (match.empty())
    throw InputError("unknown configuration keyword '" + name + "': allowed section_name keywords such as "
                     "mount_sx_mm or dotted keys {\"mount.sx_mm\": 0.1} (magenc.config_keys() lists them)");
  return match;
}

// The executables' configuration: defaults, then the dict, then the keyword arguments (each checked).
Config make_config(const py::object& config, const py::kwargs& keys,
                   const std::vector<magenc::KeySpec>& schema = magenc::common_keys()) {
  Config cfg(schema);
  auto apply = [&](const std::string& name, const py::handle& value) {
    const std::string key = key_of(cfg, name);
    check_value_kind(cfg, key, value);
    cfg.set(key + "=" + value_text(value, key));
  };
  if (!config.is_none()) {
    if (!py::isinstance<py::dict>(config))
      throw InputError("config must be a dict of keys such as {\"mount.sx_mm\": 0.1}: allowed a dict or None");
    for (const auto& [k, v] : config.cast<py::dict>()) apply(py::str(k).cast<std::string>(), v);
  }
  for (const auto& [k, v] : keys) apply(py::str(k).cast<std::string>(), v);
  return cfg;
}

magenc::FieldSourcePtr open_field(const std::string& field, const Config& cfg, const std::string& interp) {
  magenc::FieldOptions opts;
  opts.interp = magenc::parse_interp(interp, "interp");
  return magenc::open_field_source(field, cfg, opts);  // the field factory's sources plus fem:DIR
}

Eigen::Matrix3Xd points_from(const py::object& points_mm) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  // Only real numbers: numpy would turn complex points into their real part, bools into 0 and 1, and strs
  // such as '0.1' into numbers.
  py::array raw;
  try {
    raw = py::module_::import("numpy").attr("asarray")(points_mm);
  } catch (const py::error_already_set&) {
    throw InputError("points_mm is not an array of numbers: allowed an (N, 3) array in mm");
  }
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw InputError("points_mm holds " + py::str(raw.dtype()).cast<std::string>() +
                     " values: allowed real numbers (int or float) in mm, not " +
                     (kind == 'c' ? "complex numbers" : kind == 'b' ? "bools" : "text or objects"));
  Array a = Array::ensure(raw);
  if (!a) throw InputError("points_mm is not an array of numbers: allowed an (N, 3) array in mm");
  std::string shape = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
  shape += a.ndim() == 1 ? ",)" : ")";
  const bool one_point = a.ndim() == 1 && a.shape(0) == 3;
  if (!one_point && (a.ndim() != 2 || a.shape(1) != 3 || a.shape(0) < 1))
    throw InputError("points_mm has shape " + shape + ": allowed (N, 3) with N >= 1 or (3,) (x, y, z in mm, magnet frame)");
  const py::ssize_t n = one_point ? 1 : a.shape(0);
  Eigen::Matrix3Xd p(3, n);
  const double* d = a.data();
  for (py::ssize_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) p(k, i) = d[3 * i + k];
  return p;
}

py::array_t<double> rows_of(const Eigen::Matrix3Xd& m) {
  py::array_t<double> out({m.cols(), Eigen::Index(3)});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (int k = 0; k < 3; ++k) w(i, k) = m(k, i);
  return out;
}

py::array_t<double> vector_of(const Eigen::VectorXd& v) {
  py::array_t<double> out(v.size());
  std::copy(v.data(), v.data() + v.size(), out.mutable_data());
  return out;
}

// ---- the functions ----

py::array_t<double> py_field_at(const py::object& points_mm, const py::object& field_arg, const py::object& config,
                                const py::object& interp_arg, const py::kwargs& keys) {
  const std::string field = text_arg(field_arg, "field"), interp = text_arg(interp_arg, "interp");
  const Config cfg = make_config(config, keys);
  const Eigen::Matrix3Xd p = points_from(points_mm);
  const auto source = open_field(field, cfg, interp);
  Eigen::Matrix3Xd B;
  {
    py::gil_scoped_release unlocked;
    B = magenc::field_at(*source, p);
  }
  return rows_of(B);
}

py::tuple py_angle_error(const py::object& field_arg, const py::object& array, const py::object& config,
                         const py::object& interp_arg, const py::kwargs& keys) {
  const std::string field = text_arg(field_arg, "field"), interp = text_arg(interp_arg, "interp");
  Config cfg = make_config(config, keys);
  if (!array.is_none()) cfg.set("sensor.array=" + text_arg(array, "array"));
  const magenc::ProbeSetup setup =
      magenc::probe_setup_from_config(cfg, cfg.str("sensor.array"), array.is_none() ? "sensor.array" : "array");
  const magenc::Mount mount = magenc::Mount::from_config(cfg);
  const auto source = open_field(field, cfg, interp);
  magenc::AngleErrorResult res;
  {
    py::gil_scoped_release unlocked;
    res = magenc::angle_error(*source, setup, mount);
  }
  return py::make_tuple(vector_of(res.theta_deg), vector_of(res.eps_deg));
}

py::dict spectrum_dict(const magenc::Spectrum& s) {
  py::dict d;
  for (const auto& c : magenc::spectrum_columns()) d[py::str(c)] = s.column(c);
  if (s.pole_pairs > 0)  // a multipole read: ce1..ce4 (orders p..4p), as error_spectrum's table
    for (const auto& c : magenc::electrical_columns()) d[py::str(c)] = s.column(c);
  return d;
}

py::dict py_spectrum(const py::object& eps_deg, int pole_pairs) {
  if (pole_pairs < 0)
    throw InputError("pole_pairs = " + std::to_string(pole_pairs) + " is out of range: allowed 0 (none) or >= 1");
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(eps_deg);
  if (!a || a.ndim() != 1 || a.shape(0) < 2 * magenc::kHarmonics + 1)
    throw InputError("eps_deg must be a 1-D array of at least " + std::to_string(2 * magenc::kHarmonics + 1) +
                     " angle errors (deg) at uniform theta over one turn: allowed shape (M,), M >= 17");
  Eigen::VectorXd e(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    e[i] = a.at(i);
    if (!std::isfinite(e[i]))
      throw InputError("eps_deg[" + std::to_string(i) + "] is not finite: allowed finite angle errors (deg)");
  }
  return spectrum_dict(magenc::spectrum_of(e, pole_pairs));
}

py::dict py_diagnose(const py::object& measured, const py::object& field_arg, const py::object& array,
                     const py::object& r0_mm, const py::object& free, const py::object& config,
                     const py::object& fixed_zero, const py::object& error_sign, const py::object& max_gap_deg,
                     const py::object& starts, const py::object& seed, const py::object& cond_limit,
                     const py::object& interp_arg, const py::kwargs& keys) {
  const std::string field = text_arg(field_arg, "field"), interp = text_arg(interp_arg, "interp");
  Config cfg = make_config(config, keys);
  if (!array.is_none()) cfg.set("sensor.array=" + text_arg(array, "array"));
  if (!r0_mm.is_none()) cfg.set("sensor.r0_mm=" + number_key_text(r0_mm, "r0_mm"));
  magenc::DiagnoseRequest req;
  if (py::isinstance<py::str>(measured) || py::hasattr(measured, "__fspath__"))
    req.measured.push_back(py::str(measured).cast<std::string>());
  else
    for (const auto& m : py::iter(measured)) req.measured.push_back(py::str(m).cast<std::string>());
  if (!free.is_none()) {
    if (py::isinstance<py::str>(free)) {
      std::stringstream ss(free.cast<std::string>());
      for (std::string x; std::getline(ss, x, ',');)
        if (!x.empty()) req.free.push_back(x);
    } else {
      for (const auto& n : py::iter(free)) req.free.push_back(py::str(n).cast<std::string>());
    }
  }
  req.field = field;
  req.interp = interp;
  req.fixed_zero = bool_arg(fixed_zero, "fixed_zero");
  req.error_sign = static_cast<int>(int_arg(error_sign, "error_sign", -1, 1));
  req.max_gap_deg = real_arg(max_gap_deg, "max_gap_deg");
  req.starts = static_cast<int>(int_arg(starts, "starts", 1, 1000000));
  req.seed = static_cast<unsigned>(int_arg(seed, "seed", 0, 4294967295LL));
  req.cond_limit = real_arg(cond_limit, "cond_limit");
  req.array_name = array.is_none() ? "sensor.array" : "array";
  req.max_gap_name = "max_gap_deg";
  magenc::DiagnoseRun run;
  {
    py::gil_scoped_release unlocked;
    run = magenc::run_diagnose(req, cfg);
  }
  const auto& curves = run.curves;
  const magenc::DiagnosisResult& res = run.result;
  magenc::DiagnosisRunInfo info;
  info.program = "magenc.diagnose";
  info.command_line = "magenc.diagnose (Python)";
  info.field_spec = field;
  info.config_json = cfg.to_json();
  info.config_toml = cfg.to_toml();
  info.options = run.options;
  const std::string json = magenc::diagnosis_json(curves, res, info);
  return py::module_::import("json").attr("loads")(json).cast<py::dict>();
}

py::object json_dict(const std::string& json) { return py::module_::import("json").attr("loads")(json); }

// The calibrate executable's steps (analysis/calibrate_run.hpp): the correction, and the residual of `apply`.
py::dict py_calibrate(const py::object& measured, const py::object& correction, const py::object& method,
                      const py::object& apply, const py::object& field_arg, const py::object& array,
                      const py::object& r0_mm, const py::object& config, const py::object& error_sign_arg,
                      const py::object& interp_arg, const py::kwargs& keys) {
  const std::string field = text_arg(field_arg, "field"), interp = text_arg(interp_arg, "interp");
  const int error_sign = static_cast<int>(int_arg(error_sign_arg, "error_sign", -1, 1));
  Config cfg = make_config(config, keys, magenc::merge_schemas(magenc::common_keys(), magenc::calibration_keys()));
  if (!array.is_none()) cfg.set("sensor.array=" + text_arg(array, "array"));
  if (!r0_mm.is_none()) cfg.set("sensor.r0_mm=" + number_key_text(r0_mm, "r0_mm"));
  if (!method.is_none()) cfg.set("calibration.method=" + text_arg(method, "method"));
  const auto path = [](const py::object& o) { return o.is_none() ? std::string() : py::str(o).cast<std::string>(); };
  const magenc::CalibrateRequest req{path(measured), path(correction), path(apply), error_sign};
  const std::string what = array.is_none() ? "sensor.array" : "array";
  const magenc::ProbeSetup setup = magenc::sensor_setup_from_config(cfg, cfg.str("sensor.array"), what);
  magenc::FieldSourcePtr source;
  const magenc::FieldGetter the_field = [&]() -> const magenc::FieldSource& {
    if (!source) source = open_field(field, cfg, interp);
    return *source;
  };
  const magenc::CalibrationSource cs = magenc::calibrate_correction(req, cfg, what, the_field);
  py::dict out;
  out["source"] = cs.source;
  out["correction"] = json_dict(magenc::correction_json(cs.correction));
  if (!req.apply.empty()) {
    const magenc::CalibrationResidual r = magenc::calibrate_residual(req, cs.correction, cfg, setup, the_field);
    py::dict res = json_dict(r.json());
    res["theta_deg"] = vector_of(r.theta_deg);
    res["error_deg"] = vector_of(r.error_deg);
    res["residual_deg"] = vector_of(r.residual_deg);
    out["residual"] = res;
  }
  return out;
}

py::dict py_inspect(const py::object& scan, const py::object& free, const py::object& config,
                    const py::object& cond_limit_arg, const py::kwargs& keys) {
  const double cond_limit = real_arg(cond_limit_arg, "cond_limit");
  const Config cfg = make_config(config, keys);
  magenc::InspectRequest req{py::str(scan).cast<std::string>(), "offset,rotation,polarization", cond_limit, "free",
                             "cond_limit"};
  if (!free.is_none()) {
    if (py::isinstance<py::str>(free)) {
      req.free = free.cast<std::string>();
    } else {
      req.free.clear();
      for (const auto& g : py::iter(free)) req.free += py::str(g).cast<std::string>() + ",";
    }
  }
  magenc::InspectRun run;
  {
    py::gil_scoped_release unlocked;
    run = magenc::run_inspect(req, cfg);
  }
  magenc::InspectRunInfo info;
  info.command_line = "magenc.inspect (Python)";
  info.scan_file = py::str(scan).cast<std::string>();
  info.unit = run.unit;
  info.config_json = cfg.to_json();
  return py::module_::import("json").attr("loads")(magenc::inspect_json(run.scan, run.result, info)).cast<py::dict>();
}

py::list py_config_keys() {
  py::list out;
  for (const auto& s : magenc::common_keys()) {
    py::dict d;
    d["key"] = s.key;
    d["default"] = s.default_value;
    d["allowed"] = magenc::allowed_range(s);
    d["unit"] = s.unit;
    d["help"] = s.help;
    out.append(d);
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_magenc, m) {
  m.doc() =
      "magenc: angle error of magnetic rotary encoders (the library behind build/bin/*).\n"
      "Lengths in mm, angles in degrees, fields in tesla; points in the magnet frame (magnet at rest,\n"
      "centred at the origin, axis z). Configuration keys as a dict {\"mount.sx_mm\": 0.1} or keyword\n"
      "arguments (mount_sx_mm=0.1), the same keys as --set; a bad key or value raises ValueError with\n"
      "the executables' one-line message. Field sources: 'analytic' (exact field of the [magnet] keys),\n"
      "'fem:DIR' (a solve_field output, evaluated in its tetrahedra), 'grid:FILE.vti', 'table:FILE', 'linear'.";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<magenc::ComputeError>(m, "ComputeError", PyExc_RuntimeError);

  m.def("field_at", &py_field_at, py::arg("points_mm"), py::arg("field") = "analytic", py::arg("config") = py::none(),
        py::arg("interp") = "cubic",
        "B at points, like a field library's getB (the field_at executable).\n\n"
        "points_mm: (N, 3) array (or one point of shape (3,)), x, y, z in mm in the magnet frame.\n"
        "field: 'analytic' (exact field of the configured magnet, inside it too: B = mu0 (H + M)),\n"
        "  'fem:DIR' (solve_field's output), 'grid:FILE.vti', 'table:FILE'. interp: nearest | linear | cubic (grid:/table:).\n"
        "config: dict of keys, e.g. {'magnet.magnetization_elevation_deg': 30}; **keys: the same as keywords.\n"
        "Returns an (N, 3) float64 array: Bx, By, Bz in T.\n"
        "Raises ValueError naming the first point on the magnet's surface or outside a grid.");
  m.def("angle_error", &py_angle_error, py::arg("field") = "analytic", py::arg("array") = py::none(),
        py::arg("config") = py::none(), py::arg("interp") = "cubic",
        "Angle error of one turn for the configured mount (what error_spectrum evaluates).\n\n"
        "field: as for field_at (also 'linear'). array: 'two' | 'diff4' | 'ring:N' (None: sensor.array,\n"
        "default 'two'). config / **keys: every key of error_spectrum (mount.*, sensor.*, magnet.*, ...).\n"
        "Returns (theta_deg, eps_deg): two (M,) float64 arrays, M = sensor.steps, theta_m = 360 m / M deg,\n"
        "eps = wrap(phi - theta) in deg (docs/physics.md).");
  m.def("spectrum", &py_spectrum, py::arg("eps_deg"), py::arg("pole_pairs") = 0,
        "Fourier coefficients of an angle-error curve, the spectra table's columns.\n\n"
        "eps_deg: (M,) array of errors in deg at theta_m = 360 m / M (uniform, one turn), M >= 17.\n"
        "pole_pairs: p of a multipole read (magnet.pole_pairs); 0 (default): none.\n"
        "Returns a dict {'a0_deg', 'a1_deg'..'a8_deg', 'b1_deg'..'b8_deg', 'c1_deg'..'c8_deg', 'pp_deg'}\n"
        "of floats in deg (c_n = hypot(a_n, b_n), pp = peak-to-peak); with pole_pairs p >= 1 also\n"
        "'ce1_deg'..'ce4_deg', the amplitudes of the orders p..4p (error_spectrum's columns).");
  m.def("diagnose", &py_diagnose, py::arg("measured"), py::arg("field") = "analytic", py::arg("array") = py::none(),
        py::arg("r0_mm") = py::none(), py::arg("free") = py::none(), py::arg("config") = py::none(),
        py::arg("fixed_zero") = false, py::arg("error_sign") = 1, py::arg("max_gap_deg") = 30.0,
        py::arg("starts") = 6, py::arg("seed") = 1u, py::arg("cond_limit") = 1e4, py::arg("interp") = "cubic",
        "Fit mounting and signal-chain errors to measured angle-error curves (the diagnose executable).\n\n"
        "measured: a path or a list of paths of curve CSVs (theta_deg,error_deg | theta_deg,phi_deg |\n"
        "  theta_deg,u_cos,u_sin; >= 64 rows over one turn). field, array, r0_mm (mm), free (list or\n"
        "  comma-separated names: sx, sy, dx, dy, dz, tilt_x, ...; None: what the curves identify),\n"
        "  fixed_zero, error_sign (+1 | -1), max_gap_deg, starts, seed, cond_limit: diagnose's flags.\n"
        "Returns diagnose's fit.json as a dict: parameters {name: {value, sigma, free, ...}},\n"
        "residual_rms_deg, not_identifiable, ...");
  m.def("calibrate", &py_calibrate, py::arg("measured") = py::none(), py::arg("correction") = py::none(),
        py::arg("method") = py::none(), py::arg("apply") = py::none(), py::arg("field") = "analytic",
        py::arg("array") = py::none(), py::arg("r0_mm") = py::none(), py::arg("config") = py::none(),
        py::arg("error_sign") = 1, py::arg("interp") = "cubic",
        "The factory correction and what is left of it (the calibrate executable).\n\n"
        "measured: a calibration curve CSV, or correction: a correction.csv written before; neither: the\n"
        "  simulated calibration state (calibration.at keys). method: none, harmonics:N, lut:K, ogp\n"
        "  (calibration.method). apply: a curve CSV to correct, or 'run' (the configured mount).\n"
        "Returns {'source', 'correction': correction.json as a dict, 'residual': residual.json as a dict\n"
        "  with the arrays theta_deg, error_deg, residual_deg (only with apply)}.");
  m.def("inspect", &py_inspect, py::arg("scan"), py::arg("free") = py::none(), py::arg("config") = py::none(),
        py::arg("cond_limit") = 1e6,
        "Fit a magnet's polarization and a sensor's pose to a 3-axis field scan (the inspect executable).\n\n"
        "scan: path of a CSV x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT (or _T): nominal positions in the magnet frame\n"
        "  and the readings in the sensor's axes. free: groups among 'offset', 'rotation', 'polarization',\n"
        "  'direction' (list or comma-separated; None: the first three). config / **keys: the magnet's size\n"
        "  and nominal polarization ([magnet] keys).\n"
        "Returns inspect's fit.json as a dict: parameters {offset_x_mm, ..., rot_x_deg, ..., polarization_T,\n"
        "magnetization_deg, magnetization_elevation_deg: {value, sigma, free, unit}}, residual_rms_mT, ...");
  m.def("config_keys", &py_config_keys,
        "Every configuration key: a list of dicts {key, default, allowed, unit, help}.");
}
