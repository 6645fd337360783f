// Probe arrays (docs/physics.md): nominal probe angles b_k on a circle of radius r0
// and the weights that form the cos and sin channels from the probe readings:
//   cos = sum_k wc_k * B_k,   sin = sum_k ws_k * B_k,   phi = atan2(sin, cos).
//   two:    b = 0, 90;            wc = (1, 0),  ws = (0, 1)
//   diff4:  b = 0, 90, 180, 270;  wc = (1, 0, -1, 0), ws = (0, 1, 0, -1)
//   ring:N: b_k = 360k/N;         wc_k = cos b_k, ws_k = sin b_k
//   point:  one sensing spot at the die centre (r0 unused) for the in-plane
//           principles (probe/sensor.hpp), whose channels come from the
//           in-plane components b1, b2, not from these weights (1 and 0).
#pragma once
#include <string>
#include <vector>

namespace magenc {

struct ProbeArray {
  std::string name;                 // "two", "diff4", "ring:8"
  std::vector<double> angle_deg;    // b_k
  std::vector<double> w_cos, w_sin; // channel weights per probe

  // Parses "two", "diff4", "ring:N" (3 <= N <= 1024), "point"; InputError otherwise,
  // naming `what` (e.g. "--array" or "sensor.array") and the allowed values.
  static ProbeArray parse(const std::string& spec, const std::string& what = "sensor.array");
  std::size_t size() const { return angle_deg.size(); }
  bool is_point() const { return name == "point"; }
};

}  // namespace magenc
