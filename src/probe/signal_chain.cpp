#include "probe/signal_chain.hpp"

#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

SignalChain SignalChain::from_config(const Config& cfg) {
  SignalChain c;
  c.offset_cos_mT = cfg.real("sensor.offset_cos_mT");
  c.offset_sin_mT = cfg.real("sensor.offset_sin_mT");
  c.gain_mismatch = cfg.real("sensor.gain_mismatch");
  c.phase_error_deg = cfg.real("sensor.phase_error_deg");
  c.validate();
  return c;
}

void SignalChain::validate() const {
  require_finite({{"sensor.offset_cos_mT", offset_cos_mT},
                  {"sensor.offset_sin_mT", offset_sin_mT},
                  {"sensor.gain_mismatch", gain_mismatch},
                  {"sensor.phase_error_deg", phase_error_deg}});
  if (!(gain_mismatch > -1.0))
    throw InputError("sensor.gain_mismatch = " + num(gain_mismatch) + " is out of range: allowed (-1, 10]");
  if (!(std::abs(phase_error_deg) < 90.0))
    throw InputError("sensor.phase_error_deg = " + num(phase_error_deg) + " is out of range: allowed (-90, 90) deg");
}

SignalChain::Applied SignalChain::applied() const {
  Applied a;
  a.ideal = ideal();
  a.oc_T = offset_cos_mT * 1e-3;
  a.os_T = offset_sin_mT * 1e-3;
  const double delta = deg_to_rad(phase_error_deg);
  a.gs = (1.0 + gain_mismatch) * std::cos(delta);
  a.gc = (1.0 + gain_mismatch) * std::sin(delta);
  return a;
}

}  // namespace magenc
