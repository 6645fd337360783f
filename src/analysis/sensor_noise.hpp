// Sensor noise model: how field noise and ADC quantization at the probes
// become angle noise, for any probe array (probe_array.hpp).
//
// Assumptions (stated defaults, all configurable under [noise]):
//  * Every probe reading carries independent, zero-mean noise of
//    probe_noise_uT_rms (input-referred field noise, uT rms; 10 uT is a
//    typical integrated CMOS Hall plate at a few kHz bandwidth).
//  * Every probe reading is digitized on its own by an ADC of adc_bits bits
//    over +-adc_full_scale_mT (defaults 12 bits over +-200 mT): LSB =
//    2*full_scale/2^bits, and the quantization error is modelled as uniform
//    noise of rms LSB/sqrt(12) (valid when the signal sweeps many LSBs per
//    turn). It is NOT independent between probes: on the plane of a
//    diametric magnet, probes at b and b+180 deg read exactly opposite fields
//    and q(-B) = -q(B), so their quantization errors are exactly opposite and
//    add coherently in a differential channel (diff4: channel quantization
//    variance 4 q^2, not 2 q^2). The model keeps that correlation
//    (conservative when field noise dithers the ADC); probes at other angles
//    are independent. The total per probe is
//        sigma_probe = sqrt(sigma_field^2 + LSB^2/12).
//  * The channels are cos = sum wc_k B_k, sin = sum ws_k B_k with the ideal
//    readings B_k = A cos(b_k - theta) (A = amplitude of Bz on the probe
//    circle). Their noises have variances sigma^2*|wc|^2, sigma^2*|ws|^2 and
//    covariance sigma^2*(wc.ws). To first order phi = atan2(S, C) moves by
//        dphi = (C dS - S dC) / (C^2 + S^2),
//    so var(dphi) = (C^2 var(S) + S^2 var(C) - 2CS cov(C,S))/(C^2+S^2)^2;
//    sigma_phi is its rms over a turn. For independent probe noise sigma it
//    does not depend on theta: two: sigma/A; diff4: sigma/(sqrt(2) A);
//    ring:N: sigma/(sqrt(N/2) A). With the correlated quantization q the
//    differential arrays get sqrt(sigma^2/2 + q^2)/A (diff4) and
//    sqrt(sigma^2 + 2 q^2)/(2A) (ring:8). The angle noise grows where A(r0)
//    is weak.
//  * Peak-to-peak equivalent: noise_pp = pp_sigmas * sigma_phi (default 6,
//    i.e. a +-3 sigma band, exceeded by 0.27% of readings).
#pragma once
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/config.hpp"
#include "probe/probe_array.hpp"

namespace magenc {

struct SensorNoise {
  double probe_noise_uT_rms = 10.0;  // input-referred field noise per probe (uT rms)
  int adc_bits = 12;                 // ADC resolution (bits); 0 = no quantization
  double adc_full_scale_mT = 200.0;  // ADC input range +-full scale (mT)
  double pp_sigmas = 6.0;            // peak-to-peak equivalent in units of sigma_phi

  double lsb_T() const;              // ADC step 2*FS/2^bits (T); 0 when adc_bits == 0
  double probe_sigma_T() const;      // sqrt(noise^2 + LSB^2/12) (T)

  static std::vector<KeySpec> keys();  // [noise] section
  static SensorNoise from_config(const Config& cfg);
  void validate() const;               // InputError naming the key
};

// Channel factors of an array for a unit-amplitude cos field: the cos and sin
// channel gains (amplitudes of C and S per tesla of A) and the weight norms
// |wc|, |ws| (noise per unit probe noise).
struct ChannelFactors {
  double gain_cos = 0, gain_sin = 0;  // amplitude of C, S per unit A
  double norm_cos = 0, norm_sin = 0;  // |wc|, |ws|
  double dot_cs = 0;                  // wc . ws
};
ChannelFactors channel_factors(const ProbeArray& array);

// rms angle noise (rad) over a turn for independent probe noise sigma_probe_T
// and signal amplitude amplitude_T (first-order, see above). InputError if
// amplitude <= 0.
double angle_noise_sigma_rad(const ProbeArray& array, double amplitude_T, double sigma_probe_T);
// The same with independent field noise sigma_field_T plus quantization noise
// sigma_quant_T (= LSB/sqrt(12)) that is exactly opposite at antipodal probes.
double angle_noise_sigma_rad(const ProbeArray& array, double amplitude_T, double sigma_field_T, double sigma_quant_T);

struct AngleNoise {
  double sigma_deg = 0;   // rms angle noise (deg)
  double pp_deg = 0;      // pp_sigmas * sigma_deg
  bool adc_clipped = false;  // amplitude exceeds the ADC full scale
};
AngleNoise angle_noise(const ProbeArray& array, double amplitude_T, const SensorNoise& noise);

// The reference-encoder readout of an error curve (diagnose's synthetic curves and the calibration run
// share it): the sensor's angle phi = theta + eps is quantized to 360/quant_positions (0: not), the
// reference encoder reads theta + n with n Gaussian of rms noise_deg (one draw per sample, in order), and
// the observed pair is (reference, wrap(phi_q + zero_deg - reference)).
struct ReferenceReadout {
  double noise_deg = 0;     // reference-encoder noise, rms (deg)
  int quant_positions = 0;  // sensor output positions per turn (0: no quantization)
  double zero_deg = 0;      // zero offset between the encoders (deg)
};
// theta_deg: true rotor angles; eps_deg: the sensor's error there. Writes reference_deg and error_deg
// (same size); one Gaussian draw from rng per sample, whatever noise_deg.
void observe_curve(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& eps_deg, const ReferenceReadout& r,
                   std::mt19937& rng, Eigen::VectorXd& reference_deg, Eigen::VectorXd& error_deg);

}  // namespace magenc
