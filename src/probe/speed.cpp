#include "probe/speed.hpp"

#include <cmath>
#include <complex>
#include <vector>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "probe/spectrum.hpp"
#include "probe/trig_interpolation.hpp"

namespace magenc {

namespace {

using cd = std::complex<double>;

// The per-turn frequency of DFT bin k of length M: 0..M/2, then negative.
int frequency(int k, int M) { return 2 * k <= M ? k : k - M; }

// H_k = exp(-i k omega tau) / (1 + i k omega / omega_c) (omega_c = 0: no filter).
cd transfer(int k, double omega_rad_s, double tau_s, double omega_c_rad_s) {
  const double kw = k * omega_rad_s;
  const cd delay = std::polar(1.0, -kw * tau_s);
  return omega_c_rad_s > 0 ? delay / cd(1.0, kw / omega_c_rad_s) : delay;
}

// The value at theta (rad) of the real trigonometric interpolant with DFT coefficients U (length M,
// unscaled): (1/M) [Re U_0 + 2 sum_{0<k<M/2} Re(U_k e^{ik theta}) + Re(U_{M/2} e^{i M/2 theta})].
double interpolant_at(const std::vector<cd>& U, double theta_rad) {
  const int M = static_cast<int>(U.size());
  const cd step = std::polar(1.0, theta_rad);
  cd e = step;
  double sum = U[0].real();
  for (int k = 1; 2 * k < M; ++k) {
    sum += 2.0 * (U[static_cast<std::size_t>(k)] * e).real();
    e *= step;
    if (k % 64 == 0) e = std::polar(1.0, (k + 1) * theta_rad);  // (keeps the recurrence's round-off small)
  }
  if (M % 2 == 0) sum += (U[static_cast<std::size_t>(M / 2)] * std::polar(1.0, M / 2 * theta_rad)).real();
  return sum / M;
}

}  // namespace

double SpeedChain::omega_rad_s() const { return 2.0 * kPi * rpm / 60.0; }

double SpeedChain::lag_deg(int p) const {
  const double w = omega_rad_s();
  double lag_rad = w * delay_us * 1e-6;
  if (filter_hz > 0) lag_rad += std::atan(p * w / (2.0 * kPi * filter_hz)) / p;
  return rad_to_deg(lag_rad);
}

std::string prediction_name(Prediction p) { return p == Prediction::Ideal ? "ideal" : "none"; }

Prediction parse_prediction(const std::string& text) {
  if (text == "none") return Prediction::None;
  if (text == "ideal") return Prediction::Ideal;
  throw InputError("sensor.prediction = '" + text + "' is not a prediction: allowed none, ideal");
}

SpeedChain SpeedChain::from_config(const Config& cfg) {
  SpeedChain s;
  s.rpm = cfg.real("speed.rpm");
  s.delay_us = cfg.real("sensor.delay_us");
  s.skew_us = cfg.real("sensor.skew_us");
  s.filter_hz = cfg.real("sensor.filter_hz");
  s.sample_hz = cfg.real("sensor.sample_hz");
  s.prediction = parse_prediction(cfg.str("sensor.prediction"));
  s.validate();
  return s;
}

void SpeedChain::validate() const {
  require_finite({{"speed.rpm", rpm},
                  {"sensor.delay_us", delay_us},
                  {"sensor.skew_us", skew_us},
                  {"sensor.filter_hz", filter_hz},
                  {"sensor.sample_hz", sample_hz}});
  const std::pair<const char*, double> nonneg[] = {{"sensor.delay_us", delay_us},
                                                   {"sensor.skew_us", skew_us},
                                                   {"sensor.filter_hz", filter_hz},
                                                   {"sensor.sample_hz", sample_hz}};
  for (const auto& [key, v] : nonneg)
    if (v < 0) throw InputError(std::string(key) + " = " + num(v) + " is out of range: allowed >= 0");
  if (prediction != Prediction::None && !moving())
    throw InputError("sensor.prediction = " + prediction_name(prediction) +
                     " needs a speed, but speed.rpm = 0: allowed sensor.prediction = none at speed.rpm = 0");
  const double f_rot_hz = std::abs(rpm) / 60.0;
  if (sample_hz > 0 && moving() && sample_hz < 2.0 * f_rot_hz)
    throw InputError("sensor.sample_hz = " + num(sample_hz) + " is below twice the rotation frequency at speed.rpm = " +
                     num(rpm) + ": allowed 0 or >= " + num(2.0 * f_rot_hz) + " Hz");
}

void SpeedChain::apply(Eigen::MatrixXd& channels, Eigen::VectorXd& eps_deg, int p) const {
  const int M = static_cast<int>(channels.rows());
  const double w = omega_rad_s(), wc = 2.0 * kPi * filter_hz;
  const double tau_c_s = delay_us * 1e-6, tau_s_s = (delay_us + skew_us) * 1e-6;
  // 1. Both channels in one complex DFT (z = u_c + i u_s), split, filtered and delayed, recombined.
  const ComplexDft& dft = ComplexDft::of(M);
  std::vector<cd> z(static_cast<std::size_t>(M)), Z(z.size()), Uc(z.size()), Us(z.size()), Zout(z.size());
  for (int m = 0; m < M; ++m) z[std::size_t(m)] = cd(channels(m, 0), channels(m, 1));
  dft.forward(z.data(), Z.data());
  for (int k = 0; k < M; ++k) {
    const cd a = Z[std::size_t(k)], b = std::conj(Z[std::size_t((M - k) % M)]);
    const int f = frequency(k, M);
    cd Hc = transfer(f, w, tau_c_s, wc), Hs = transfer(f, w, tau_s_s, wc);
    if (2 * k == M) {  // the cos(M/2 theta) term of a real channel: the half-weight split between +-M/2
      Hc = Hc.real();
      Hs = Hs.real();
    }
    Uc[std::size_t(k)] = Hc * 0.5 * (a + b);
    Us[std::size_t(k)] = Hs * cd(0.0, -0.5) * (a - b);
    Zout[std::size_t(k)] = Uc[std::size_t(k)] + cd(0.0, 1.0) * Us[std::size_t(k)];
  }
  dft.backward(Zout.data(), z.data());
  // 2. The angle and the prediction: eps = wrap(psi + p lead - p theta) / p.
  const double lead_deg = prediction == Prediction::Ideal ? lag_deg(p) : 0.0;
  auto error_deg = [&](double u_c, double u_s, double theta_deg) {
    return wrap_deg(rad_to_deg(std::atan2(u_s, u_c)) + p * lead_deg - p * theta_deg) / p;
  };
  Eigen::VectorXd eps(M);
  for (int m = 0; m < M; ++m) {
    channels(m, 0) = z[std::size_t(m)].real() / M;
    channels(m, 1) = z[std::size_t(m)].imag() / M;
    eps[m] = error_deg(channels(m, 0), channels(m, 1), 360.0 * m / M);
  }
  eps_deg = eps;
  if (sample_hz <= 0) return;
  // 3. The zero-order hold: at theta_m the output holds its value of the last sample time t_j = j / sample_hz
  //    (t = 0 at theta = 0). u: the time of theta_m as a fraction of the turn, v that of its sample.
  const double S = sample_hz * 60.0 / std::abs(rpm);  // samples per turn (>= 2)
  long last_j = -1;
  double last_eps = 0;
  for (int m = 0; m < M; ++m) {
    const double u = (w > 0 ? m : (M - m) % M) / double(M);
    const long j = static_cast<long>(std::floor(u * S + 1e-9));
    const double v = j / S;
    if (j != last_j) {
      const double g = (w > 0 ? v : 1.0 - v) * M;  // the sample's angle in grid steps
      const double gr = std::round(g);
      if (std::abs(g - gr) < 1e-6) {
        last_eps = eps[static_cast<Eigen::Index>(static_cast<long>(gr) % M)];
      } else {
        const double theta_s_deg = 360.0 * g / M;
        const double th = deg_to_rad(theta_s_deg);
        last_eps = error_deg(interpolant_at(Uc, th), interpolant_at(Us, th), theta_s_deg);
      }
      last_j = j;
    }
    const double ahead_deg = 360.0 * (w > 0 ? v - u : u - v);  // theta_sample - theta_m
    eps_deg[m] = wrap_deg(p * (last_eps + ahead_deg)) / p;
  }
}

std::vector<KeySpec> speed_keys() {
  return {
      real_key("speed.rpm", 0.0, -1e6, 1e6, "rpm",
               "constant rotor speed (signed: the direction of rotation); 0 = static, the timing keys unused"),
      real_key("sensor.delay_us", 0.0, 0, 1e6, "us", "latency of both channels at speed (speed.rpm != 0)"),
      real_key("sensor.skew_us", 0.0, 0, 1e6, "us",
               "extra latency of the sin channel at speed (sequential sampling of the channels)"),
      real_key("sensor.filter_hz", 0.0, 0, 1e9, "Hz",
               "corner of a first-order low-pass on each channel at speed; 0 = no filter"),
      real_key("sensor.sample_hz", 0.0, 0, 1e9, "Hz",
               "output update rate at speed: zero-order hold, first sample at theta = 0; 0 = continuous, "
               "otherwise >= twice the rotation frequency"),
      string_key("sensor.prediction", "none", {"none", "ideal"},
                 "speed compensation of the output angle: none, or ideal (advanced by omega delay + "
                 "atan(omega / omega_c)); ideal needs speed.rpm != 0"),
  };
}

}  // namespace magenc
