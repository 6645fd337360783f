#include "analysis/calibrate_run.hpp"

#include <sstream>

#include "analysis/calibration_file.hpp"
#include "analysis/measured_curve.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "probe/mounting.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

namespace {
std::string g10(double v) { return fmt_sig(v, 10); }

CurveReadOptions read_options(const CalibrateRequest& req) {
  CurveReadOptions ro;
  ro.error_sign = req.error_sign;
  return ro;
}
}  // namespace

CalibrationSource calibrate_correction(const CalibrateRequest& req, const Config& cfg, const std::string& what,
                                       const FieldGetter& field) {
  if (!req.measured.empty() && !req.correction.empty())
    throw InputError("--measured and --correction both give the correction: allowed one of the two");
  if (req.error_sign != 1 && req.error_sign != -1)
    throw InputError("--error-sign " + std::to_string(req.error_sign) + ": allowed +1 or -1");
  const CalibrationMethod method = calibration_method(cfg);  // checked even when a correction file is given
  if (!req.correction.empty()) {
    Correction c = read_correction_csv(req.correction);
    if (!method.none() && method.name() != c.method.name())
      throw InputError("calibration.method = " + method.name() + " (--method) contradicts " + req.correction +
                       ", a " + c.method.name() + " correction: allowed the table's own method or none");
    const auto principle = sensor_setup_from_config(cfg, cfg.str("sensor.array"), what).principle;
    if (c.turns != electrical_turns(principle))
      throw InputError("correction " + req.correction + " has turns " + std::to_string(c.turns) + " but sensor.principle " +
                       cfg.str("sensor.principle") + " turns its channel angle " +
                       std::to_string(electrical_turns(principle)) + " times per turn: allowed turns " +
                       std::to_string(electrical_turns(principle)) + " (a table of this sensor)");
    return {std::move(c), req.correction};
  }
  if (method.none())
    throw InputError("calibration.method = none: allowed harmonics:N, lut:K or ogp (--method), or --correction FILE");
  if (req.measured.empty())
    return {correction_from_config(field(), cfg, cfg.str("sensor.array"), what), "simulated calibration.at"};
  const int turns = electrical_turns(sensor_setup_from_config(cfg, cfg.str("sensor.array"), what).principle);
  const MeasuredCurve c = read_measured_curve(req.measured, read_options(req));
  if (method.kind != CalibrationKind::Ogp)
    return {correct_pairs(method, c.theta_deg + c.error_deg, c.error_deg, turns), req.measured};
  if (c.format != "raw")
    throw InputError("--method ogp needs the raw channels: " + req.measured + " has " + c.format +
                     ", allowed a curve with header theta_deg,u_cos,u_sin");
  return {correct_channels(c.channels, turns), req.measured};
}

CalibrationResidual calibrate_residual(const CalibrateRequest& req, const Correction& corr, const Config& cfg,
                                       const ProbeSetup& setup, const FieldGetter& field) {
  CalibrationResidual r;
  r.curve = req.apply;
  r.method = corr.method.name();
  if (req.apply == "run") {
    const AngleErrorResult run = angle_error(field(), setup, Mount::from_config(cfg));
    r.theta_deg = run.theta_deg;
    r.error_deg = run.eps_deg;
    r.residual_deg = residual_deg(corr, run);
    return r;
  }
  const MeasuredCurve c = read_measured_curve(req.apply, read_options(req));
  r.theta_deg = c.theta_deg;
  r.error_deg = c.error_deg;
  if (corr.method.kind != CalibrationKind::Ogp) {
    r.residual_deg = residual_of_pairs(corr, r.theta_deg, r.error_deg);
    return r;
  }
  if (c.format != "raw")
    throw InputError("an ogp correction applies to raw channels: " + req.apply + " has " + c.format +
                     ", allowed a curve with header theta_deg,u_cos,u_sin");
  r.residual_deg.resize(r.theta_deg.size());
  for (Eigen::Index i = 0; i < r.theta_deg.size(); ++i)
    r.residual_deg[i] =
        wrap_deg(corr.ellipse.angle_deg(c.channels(i, 0), c.channels(i, 1)) - corr.turns * r.theta_deg[i]) / corr.turns;
  return r;
}

std::string CalibrationResidual::csv() const {
  std::ostringstream os;
  os << "theta_deg,error_deg,residual_deg\n";
  for (Eigen::Index i = 0; i < theta_deg.size(); ++i)
    os << g10(theta_deg[i]) << "," << g10(error_deg[i]) << "," << g10(residual_deg[i]) << "\n";
  return os.str();
}

std::string CalibrationResidual::json() const {
  std::ostringstream os;
  const Eigen::VectorXd h = harmonics_ls(theta_deg, residual_deg, kHarmonics);
  os << "{\n  \"curve\": \"" << curve << "\",\n  \"method\": \"" << method << "\",\n  \"samples\": " << theta_deg.size()
     << ",\n  \"pp_before_deg\": " << g10(error_deg.maxCoeff() - error_deg.minCoeff())
     << ",\n  \"pp_after_deg\": " << g10(residual_deg.maxCoeff() - residual_deg.minCoeff())
     << ",\n  \"mean_after_deg\": " << g10(residual_deg.mean()) << ",\n  \"c_after_deg\": [";
  for (int n = 1; n <= kHarmonics; ++n) os << (n > 1 ? ", " : "") << g10(harmonic_amplitude(h, n));
  os << "]\n}\n";
  return os.str();
}

}  // namespace magenc
