#include "probe/probe_array.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {
std::string allowed_arrays() {
  return "allowed two, diff4, ring:N with 3 <= N <= 1024 (sensor.principle bz), point (inplane, xmr, amr)";
}
}  // namespace

ProbeArray ProbeArray::parse(const std::string& spec, const std::string& what) {
  ProbeArray a;
  a.name = spec;
  if (spec == "two") {
    a.angle_deg = {0.0, 90.0};
    a.w_cos = {1.0, 0.0};
    a.w_sin = {0.0, 1.0};
    return a;
  }
  if (spec == "diff4") {
    a.angle_deg = {0.0, 90.0, 180.0, 270.0};
    a.w_cos = {1.0, 0.0, -1.0, 0.0};
    a.w_sin = {0.0, 1.0, 0.0, -1.0};
    return a;
  }
  if (spec == "point") {
    a.angle_deg = {0.0};
    a.w_cos = {1.0};
    a.w_sin = {0.0};
    return a;
  }
  const std::string prefix = "ring:";
  if (spec.rfind(prefix, 0) == 0) {
    const std::string digits = spec.substr(prefix.size());
    bool ok = !digits.empty() && digits.size() <= 5;
    for (char ch : digits) ok = ok && ch >= '0' && ch <= '9';
    const long n = ok ? std::stol(digits) : 0;
    if (ok && n >= 3 && n <= 1024) {
      for (long k = 0; k < n; ++k) {
        const double b_deg = 360.0 * static_cast<double>(k) / static_cast<double>(n);
        a.angle_deg.push_back(b_deg);
        a.w_cos.push_back(std::cos(deg_to_rad(b_deg)));
        a.w_sin.push_back(std::sin(deg_to_rad(b_deg)));
      }
      return a;
    }
  }
  throw InputError(what + " = '" + spec + "' is not a probe array: " + allowed_arrays());
}

}  // namespace magenc
