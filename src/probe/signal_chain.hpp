// Signal-chain imperfections (docs/physics.md, "Beyond the five offsets"), applied
// to the array's channel signals u_c, u_s (tesla) before atan2:
//   u_c' = u_c + oc
//   u_s' = (1 + g) * (u_s cos delta + u_c sin delta) + os
// oc, os: channel offsets (config in mT, converted to T here); g: gain
// mismatch of the sin channel; delta: phase error of the sin channel. For
// ideal signals u_c = A cos theta, u_s = A sin theta this gives
// u_s' = (1+g) A sin(theta + delta) + os.
// Principles with unit-amplitude channels (xmr, amr: probe/sensor.hpp) take
// relative offsets instead (sensor.offset_cos_rel, sensor.offset_sin_rel:
// fractions of the unit amplitude); validate_for() refuses the other kind.
#pragma once
#include "core/config.hpp"
#include "probe/sensor.hpp"

namespace magenc {

struct SignalChain {
  double offset_cos_mT = 0;    // oc, added to the cos channel
  double offset_sin_mT = 0;    // os, added to the sin channel
  double gain_mismatch = 0;    // g: sin channel gain 1 + g (> -1)
  double phase_error_deg = 0;  // delta: sin channel phase error, |delta| < 90
  double offset_cos_rel = 0;   // xmr/amr: cos channel offset, fraction of the unit amplitude
  double offset_sin_rel = 0;   // xmr/amr: sin channel offset

  // Reads sensor.offset_cos_mT, sensor.offset_sin_mT, sensor.gain_mismatch, sensor.phase_error_deg,
  // sensor.offset_cos_rel, sensor.offset_sin_rel.
  static SignalChain from_config(const Config& cfg);
  // Finite values, gain_mismatch > -1, |phase_error_deg| < 90, |relative offsets| <= 1 (InputError naming the key).
  void validate() const;
  // validate(), and the offsets of the other kind are 0: mT offsets on xmr/amr, relative ones on
  // bz/inplane are refused (InputError naming the key and the principle).
  void validate_for(SensorPrinciple p) const;
  bool ideal() const {
    return offset_cos_mT == 0 && offset_sin_mT == 0 && gain_mismatch == 0 && phase_error_deg == 0 &&
           offset_cos_rel == 0 && offset_sin_rel == 0;
  }

  // Precomputed form of the chain for a loop over many samples.
  struct Applied {
    double oc_T = 0, os_T = 0;     // offsets in the channels' unit: tesla (bz, inplane) or relative (xmr, amr)
    double gc = 0, gs = 1;         // u_s' = gs*u_s + gc*u_c + os: gs = (1+g) cos delta, gc = (1+g) sin delta
    bool ideal = true;
    // Applies the chain in place (u_c, u_s in tesla).
    void operator()(double& u_c, double& u_s) const {
      if (ideal) return;
      const double c = u_c, s = u_s;
      u_c = c + oc_T;
      u_s = gs * s + gc * c + os_T;
    }
  };
  Applied applied() const;
  // The chain for principle p: offsets in tesla (bz, inplane) or relative (xmr, amr).
  Applied applied(SensorPrinciple p) const;
  // One-shot form: applies the chain to (u_c, u_s) in place.
  void apply(double& u_c_T, double& u_s_T) const { applied()(u_c_T, u_s_T); }
};

}  // namespace magenc
