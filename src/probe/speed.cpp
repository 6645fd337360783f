#include "probe/speed.hpp"

#include <algorithm>
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

// The values at theta (rad; step = e^{i theta}) of the two real trigonometric interpolants of the turn (unscaled
// DFT coefficients, k = 0..kmax): (1/M) [Re U_0 + 2 sum_{0<k<M/2} Re(U_k e^{ik theta}) + Re(U_{M/2} e^{i M/2 theta})], both channels
// in one pass over k.
void interpolants_at(const SpeedChain::FilteredTurn& t, double theta_rad, std::complex<double> step, double& u_c,
                     double& u_s) {
  const int M = t.M;
  cd e = 1.0;
  double sc = 0, ss = 0;
  for (int k = 0; k <= t.kmax; ++k) {
    if (k % 64 == 0 && k > 0) e = std::polar(1.0, k * theta_rad);  // (keeps the recurrence's round-off small)
    const double weight = k == 0 || 2 * k == M ? 1.0 : 2.0;
    sc += weight * (t.c[std::size_t(k)] * e).real();
    ss += weight * (t.s[std::size_t(k)] * e).real();
    e *= step;
  }
  u_c = sc / M;
  u_s = ss / M;
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

SpeedChain::FilteredTurn SpeedChain::filter(Eigen::MatrixXd& channels) const {
  FilteredTurn t;
  const int M = t.M = static_cast<int>(channels.rows());
  const double w = omega_rad_s(), wc = 2.0 * kPi * filter_hz;
  // H_k for k = 0..M/2 (negative k: the conjugate), made once per chain and M on each thread (the Monte Carlo
  // engine runs one chain over many cases); the cos(M/2 theta) term of an even M takes Re H (its half weight).
  struct Transfer {
    int M = -1;
    double w = 0, tau_c = 0, tau_s = 0, wc = 0;
    std::vector<cd> Hc, Hs;
  };
  thread_local Transfer H;
  const double tau_c = delay_us * 1e-6, tau_s = (delay_us + skew_us) * 1e-6;
  if (H.M != M || H.w != w || H.tau_c != tau_c || H.tau_s != tau_s || H.wc != wc) {
    H = Transfer{M, w, tau_c, tau_s, wc, std::vector<cd>(std::size_t(M / 2 + 1)), std::vector<cd>(std::size_t(M / 2 + 1))};
    for (int k = 0; 2 * k <= M; ++k) {
      const cd lp = wc > 0 ? 1.0 / cd(1.0, k * w / wc) : cd(1.0);
      cd Hc = std::polar(1.0, -k * w * tau_c) * lp, Hs = std::polar(1.0, -k * w * tau_s) * lp;
      if (2 * k == M) {
        Hc = Hc.real();
        Hs = Hs.real();
      }
      H.Hc[std::size_t(k)] = Hc;
      H.Hs[std::size_t(k)] = Hs;
    }
  }
  thread_local std::vector<cd> z, Z, out;
  z.resize(std::size_t(M));
  Z.resize(z.size());
  out.resize(z.size());
  t.c.resize(std::size_t(M / 2 + 1));
  t.s.resize(t.c.size());
  // Both channels in one complex DFT (z = u_c + i u_s), split into the real channels' coefficients, each
  // multiplied by its H_k, recombined.
  const ComplexDft& dft = ComplexDft::of(M);
  for (int m = 0; m < M; ++m) z[std::size_t(m)] = cd(channels(m, 0), channels(m, 1));
  dft.forward(z.data(), Z.data());
  double largest = 0;
  for (int k = 0; 2 * k <= M; ++k) {
    const std::size_t kp = std::size_t(k), km = std::size_t((M - k) % M);
    const cd a = Z[kp], b = std::conj(Z[km]);
    const cd uc = H.Hc[kp] * 0.5 * (a + b), us = H.Hs[kp] * cd(0.0, -0.5) * (a - b);  // the channels' component k
    t.c[kp] = uc;
    t.s[kp] = us;
    out[kp] = uc + cd(0.0, 1.0) * us;
    out[km] = std::conj(uc) + cd(0.0, 1.0) * std::conj(us);  // component -k (k = 0, M/2: the same value)
    largest = std::max(largest, std::norm(uc) + std::norm(us));
  }
  dft.backward(out.data(), z.data());
  for (int m = 0; m < M; ++m) {
    channels(m, 0) = z[std::size_t(m)].real() / M;
    channels(m, 1) = z[std::size_t(m)].imag() / M;
  }
  // The hold's evaluations between grid angles stop at the last component whose size (the root of the two
  // channels' squared moduli) is above 1e-15 of the largest: the components left out (round-off of the
  // transforms, or a spectrum that has decayed) change a channel by less than M * 1e-15 of its amplitude.
  t.kmax = M / 2;
  while (t.kmax > 1 && std::norm(t.c[std::size_t(t.kmax)]) + std::norm(t.s[std::size_t(t.kmax)]) <= 1e-30 * largest)
    --t.kmax;
  return t;
}

void SpeedChain::output(const FilteredTurn& t, Eigen::VectorXd& eps_deg, int p, double* cos_out, double* sin_out) const {
  const int M = t.M;
  const double lead_deg = prediction == Prediction::Ideal ? lag_deg(p) : 0.0;
  if (lead_deg != 0.0)
    for (int m = 0; m < M; ++m) eps_deg[m] = wrap_deg(p * (eps_deg[m] + lead_deg)) / p;
  if (sample_hz <= 0) return;
  // The zero-order hold: at theta_m the output holds its value of the last sample time t_j = j / sample_hz
  // (t = 0 at theta = 0). u: the time of theta_m as a fraction of the turn, v that of its sample. The sample
  // angles are +-2 pi j / S: e^{i theta} of the next one by one rotation (a fresh sincos every 32).
  const double w = omega_rad_s(), sign = w > 0 ? 1.0 : -1.0;
  const double S = sample_hz * 60.0 / std::abs(rpm);  // samples per turn (>= 2)
  const cd rot = std::polar(1.0, sign * 2.0 * kPi / S), lead = std::polar(1.0, deg_to_rad(p * lead_deg));
  thread_local Eigen::VectorXd eps;
  eps = eps_deg;
  long last_j = -1, steps = 0;
  double last_eps = 0, c = 1, s = 0;
  cd e_s = 1.0;
  for (int m = 0; m < M; ++m) {
    const double u = (w > 0 ? m : (M - m) % M) / double(M);
    const long j = static_cast<long>(std::floor(u * S + 1e-9));
    const double v = j / S;
    if (j != last_j) {
      const double g = (w > 0 ? v : 1.0 - v) * M;  // the sample's angle in grid steps
      const double gr = std::round(g), theta_s_deg = 360.0 * g / M;
      const bool next = last_j >= 0 && std::abs(j - last_j) == 1 && ++steps % 32 != 0;
      e_s = next ? (j > last_j ? e_s * rot : e_s * std::conj(rot)) : std::polar(1.0, deg_to_rad(theta_s_deg));
      if (std::abs(g - gr) < 1e-6) {
        last_eps = eps[static_cast<Eigen::Index>(static_cast<long>(gr) % M)];
        if (cos_out) {
          c = std::cos(deg_to_rad(theta_s_deg + last_eps));
          s = std::sin(deg_to_rad(theta_s_deg + last_eps));
        }
      } else {  // between grid angles: the channels from their interpolants, then the angle and the lead
        double u_c = 0, u_s = 0;
        interpolants_at(t, deg_to_rad(theta_s_deg), e_s, u_c, u_s);
        last_eps = wrap_deg(rad_to_deg(std::atan2(u_s, u_c)) + p * lead_deg - p * theta_s_deg) / p;
        if (cos_out && p == 1) {  // the output's direction: the channels' turned by the lead
          const cd out = cd(u_c, u_s) / std::hypot(u_c, u_s) * lead;
          c = out.real();
          s = out.imag();
        } else if (cos_out) {
          c = std::cos(deg_to_rad(theta_s_deg + last_eps));
          s = std::sin(deg_to_rad(theta_s_deg + last_eps));
        }
      }
      last_j = j;
    }
    const double ahead_deg = 360.0 * (w > 0 ? v - u : u - v);  // theta_sample - theta_m
    eps_deg[m] = wrap_deg(p * (last_eps + ahead_deg)) / p;
    if (cos_out) {
      cos_out[m] = c;
      sin_out[m] = s;
    }
  }
}

void SpeedChain::apply(Eigen::MatrixXd& channels, Eigen::VectorXd& eps_deg, int p) const {
  const FilteredTurn t = filter(channels);
  const int M = t.M;
  eps_deg.resize(M);
  for (int m = 0; m < M; ++m)
    eps_deg[m] = wrap_deg(rad_to_deg(std::atan2(channels(m, 1), channels(m, 0))) - p * (360.0 * m / M)) / p;
  output(t, eps_deg, p);
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
