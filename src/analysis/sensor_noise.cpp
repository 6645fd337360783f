#include "analysis/sensor_noise.hpp"

#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

double SensorNoise::lsb_T() const {
  if (adc_bits == 0) return 0.0;
  return 2.0 * adc_full_scale_mT * 1e-3 / std::ldexp(1.0, adc_bits);
}

double SensorNoise::probe_sigma_T() const {
  const double field_T = probe_noise_uT_rms * 1e-6;
  const double lsb = lsb_T();
  return std::sqrt(field_T * field_T + lsb * lsb / 12.0);
}

std::vector<KeySpec> SensorNoise::keys() {
  return {
      real_key("noise.probe_noise_uT_rms", 10.0, 0, 1e6, "uT",
               "input-referred field noise of each probe (rms, independent between probes)"),
      int_key("noise.adc_bits", 12, 0, 32, "ADC resolution per probe reading (0 = no quantization)"),
      real_key("noise.adc_full_scale_mT", 200.0, 0, 1e5, "mT", "ADC input range is +-full scale", true),
      real_key("noise.pp_sigmas", 6.0, 0, 100, "",
               "peak-to-peak equivalent of the angle noise in sigmas (6 = +-3 sigma)", true),
  };
}

SensorNoise SensorNoise::from_config(const Config& cfg) {
  SensorNoise n;
  n.probe_noise_uT_rms = cfg.real("noise.probe_noise_uT_rms");
  n.adc_bits = static_cast<int>(cfg.integer("noise.adc_bits"));
  n.adc_full_scale_mT = cfg.real("noise.adc_full_scale_mT");
  n.pp_sigmas = cfg.real("noise.pp_sigmas");
  n.validate();
  return n;
}

void SensorNoise::validate() const {
  if (!(std::isfinite(probe_noise_uT_rms) && probe_noise_uT_rms >= 0))
    throw InputError("noise.probe_noise_uT_rms = " + num(probe_noise_uT_rms) + " is out of range: allowed [0, 1e6] uT");
  if (adc_bits < 0 || adc_bits > 32)
    throw InputError("noise.adc_bits = " + std::to_string(adc_bits) + " is out of range: allowed [0, 32]");
  if (!(std::isfinite(adc_full_scale_mT) && adc_full_scale_mT > 0))
    throw InputError("noise.adc_full_scale_mT = " + num(adc_full_scale_mT) + " is out of range: allowed (0, 1e5] mT");
  if (!(std::isfinite(pp_sigmas) && pp_sigmas > 0))
    throw InputError("noise.pp_sigmas = " + num(pp_sigmas) + " is out of range: allowed (0, 100]");
}

ChannelFactors channel_factors(const ProbeArray& array) {
  ChannelFactors f;
  for (std::size_t k = 0; k < array.size(); ++k) {
    const double b = deg_to_rad(array.angle_deg[k]);
    f.gain_cos += array.w_cos[k] * std::cos(b);
    f.gain_sin += array.w_sin[k] * std::sin(b);
    f.norm_cos += array.w_cos[k] * array.w_cos[k];
    f.norm_sin += array.w_sin[k] * array.w_sin[k];
    f.dot_cs += array.w_cos[k] * array.w_sin[k];
  }
  f.norm_cos = std::sqrt(f.norm_cos);
  f.norm_sin = std::sqrt(f.norm_sin);
  return f;
}

namespace {

// Effective weights of the quantization errors: probes at b and b + 180 deg
// read exactly opposite fields (B(-x) = -B(x) on the plane of a diametric
// magnet) and q(-B) = -q(B), so their quantization errors are exactly
// opposite; each antipodal group g contributes one error with weight
// sum_k w_k * s_k (s_k = +1 at the group's angle, -1 opposite).
void antipodal_weights(const ProbeArray& array, std::vector<double>& wc, std::vector<double>& ws) {
  std::vector<double> group_angle;
  wc.clear();
  ws.clear();
  for (std::size_t k = 0; k < array.size(); ++k) {
    const double b = std::fmod(std::fmod(array.angle_deg[k], 360.0) + 360.0, 360.0);
    std::size_t g = 0;
    double sign = 1;
    for (; g < group_angle.size(); ++g) {
      const double d = std::fmod(b - group_angle[g] + 720.0, 360.0);
      if (std::abs(d) < 1e-9 || std::abs(d - 360.0) < 1e-9) break;
      if (std::abs(d - 180.0) < 1e-9) {
        sign = -1;
        break;
      }
    }
    if (g == group_angle.size()) {
      group_angle.push_back(b);
      wc.push_back(0);
      ws.push_back(0);
    }
    wc[g] += sign * array.w_cos[k];
    ws[g] += sign * array.w_sin[k];
  }
}

}  // namespace

double angle_noise_sigma_rad(const ProbeArray& array, double amplitude_T, double sigma_probe_T) {
  return angle_noise_sigma_rad(array, amplitude_T, sigma_probe_T, 0.0);
}

double angle_noise_sigma_rad(const ProbeArray& array, double amplitude_T, double sigma_field_T, double sigma_quant_T) {
  if (!(amplitude_T > 0)) throw InputError("angle noise: signal amplitude " + num(amplitude_T) + " T must be > 0");
  // Channel noise (co)variances: field noise independent per probe, quantization per antipodal group.
  const ChannelFactors f = channel_factors(array);
  std::vector<double> qc, qs;
  antipodal_weights(array, qc, qs);
  double qcc = 0, qss = 0, qcs = 0;
  for (std::size_t g = 0; g < qc.size(); ++g) {
    qcc += qc[g] * qc[g];
    qss += qs[g] * qs[g];
    qcs += qc[g] * qs[g];
  }
  const double nf = sigma_field_T * sigma_field_T, nq = sigma_quant_T * sigma_quant_T;
  const double var_c = nf * f.norm_cos * f.norm_cos + nq * qcc;
  const double var_s = nf * f.norm_sin * f.norm_sin + nq * qss;
  const double cov_cs = nf * f.dot_cs + nq * qcs;
  // Average var(dphi) over a turn with the exact ideal channels (general
  // weights; for the symmetric arrays the result is theta-independent).
  const int M = 360;
  double var_sum = 0;
  for (int m = 0; m < M; ++m) {
    const double theta = 2.0 * kPi * m / M;
    double C = 0, S = 0;
    for (std::size_t k = 0; k < array.size(); ++k) {
      const double Bk = amplitude_T * std::cos(deg_to_rad(array.angle_deg[k]) - theta);
      C += array.w_cos[k] * Bk;
      S += array.w_sin[k] * Bk;
    }
    const double r2 = C * C + S * S;
    if (!(r2 > 0)) throw ComputeError("angle noise: array " + array.name + " has a zero channel vector");
    var_sum += (C * C * var_s + S * S * var_c - 2 * C * S * cov_cs) / (r2 * r2);
  }
  return std::sqrt(var_sum / M);
}

AngleNoise angle_noise(const ProbeArray& array, double amplitude_T, const SensorNoise& noise) {
  AngleNoise a;
  a.sigma_deg = rad_to_deg(
      angle_noise_sigma_rad(array, amplitude_T, noise.probe_noise_uT_rms * 1e-6, noise.lsb_T() / std::sqrt(12.0)));
  a.pp_deg = noise.pp_sigmas * a.sigma_deg;
  a.adc_clipped = noise.adc_bits > 0 && amplitude_T > noise.adc_full_scale_mT * 1e-3;
  return a;
}

void observe_curve(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& eps_deg, const ReferenceReadout& r,
                   std::mt19937& rng, Eigen::VectorXd& reference_deg, Eigen::VectorXd& error_deg) {
  const auto n = theta_deg.size();
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double q = r.quant_positions > 0 ? 360.0 / r.quant_positions : 0.0;
  reference_deg.resize(n);
  error_deg.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double phi = theta_deg[i] + eps_deg[i];
    if (q > 0) phi = std::round(phi / q) * q;
    const double ref = theta_deg[i] + r.noise_deg * gauss(rng);  // drawn also at zero noise: same rng stream
    reference_deg[i] = ref;
    error_deg[i] = wrap_deg(phi + r.zero_deg - ref);
  }
}

}  // namespace magenc
