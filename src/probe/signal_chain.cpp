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
  if (cfg.has("sensor.offset_cos_rel")) c.offset_cos_rel = cfg.real("sensor.offset_cos_rel");
  if (cfg.has("sensor.offset_sin_rel")) c.offset_sin_rel = cfg.real("sensor.offset_sin_rel");
  c.validate();
  return c;
}

void SignalChain::validate() const {
  require_finite({{"sensor.offset_cos_mT", offset_cos_mT},
                  {"sensor.offset_sin_mT", offset_sin_mT},
                  {"sensor.gain_mismatch", gain_mismatch},
                  {"sensor.phase_error_deg", phase_error_deg},
                  {"sensor.offset_cos_rel", offset_cos_rel},
                  {"sensor.offset_sin_rel", offset_sin_rel}});
  if (!(gain_mismatch > -1.0))
    throw InputError("sensor.gain_mismatch = " + num(gain_mismatch) + " is out of range: allowed (-1, 10]");
  if (!(std::abs(phase_error_deg) < 90.0))
    throw InputError("sensor.phase_error_deg = " + num(phase_error_deg) + " is out of range: allowed (-90, 90) deg");
  const std::pair<const char*, double> rel[] = {{"sensor.offset_cos_rel", offset_cos_rel},
                                                {"sensor.offset_sin_rel", offset_sin_rel}};
  for (const auto& [key, v] : rel)
    if (std::abs(v) > 1.0) throw InputError(std::string(key) + " = " + num(v) + " is out of range: allowed [-1, 1]");
}

void SignalChain::validate_for(SensorPrinciple p) const {
  validate();
  const std::pair<const char*, double> mT[] = {{"sensor.offset_cos_mT", offset_cos_mT},
                                               {"sensor.offset_sin_mT", offset_sin_mT}};
  const std::pair<const char*, double> rel[] = {{"sensor.offset_cos_rel", offset_cos_rel},
                                                {"sensor.offset_sin_rel", offset_sin_rel}};
  const bool relative = relative_offsets(p);
  for (const auto& [key, v] : relative ? mT : rel)
    if (v != 0.0)
      throw InputError(std::string(key) + " = " + num(v) + " does not apply to sensor.principle = " +
                       principle_name(p) + ": allowed 0 (" +
                       (relative ? "xmr/amr offsets are relative: sensor.offset_cos_rel, sensor.offset_sin_rel)"
                                 : "bz/inplane offsets are in mT: sensor.offset_cos_mT, sensor.offset_sin_mT)"));
}

SignalChain::Applied SignalChain::applied(SensorPrinciple p) const {
  Applied a = applied();
  if (relative_offsets(p)) {
    a.oc_T = offset_cos_rel;
    a.os_T = offset_sin_rel;
  }
  return a;
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
